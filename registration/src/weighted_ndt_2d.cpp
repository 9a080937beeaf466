// The one translation unit that compiles WeightedNDT2D (and its PCL base templates) for the point
// types the library ships; every other unit sees the extern template declarations in the header.
#define RADAR_NDT_WEIGHTED_NDT_2D_INSTANTIATE
#define PCL_NO_PRECOMPILE  // compile PCL's search and kd-tree templates for PointRadar here
#include "radar_ndt/registration/weighted_ndt_2d.h"

#include "radar_ndt/registration/impl/weighted_ndt_2d.hpp"

namespace radar_ndt {
namespace detail {

void CellIndexHash::clear() {
  keys_.clear();
  slots_.clear();
  used_.clear();
  size_ = 0;
  mask_ = 0;
}

void CellIndexHash::reserve(std::size_t keys) {
  std::size_t cap = 16;
  while (cap < 2 * keys) cap <<= 1;
  if (cap <= keys_.size()) return;
  std::vector<std::uint64_t> old_keys;
  std::vector<std::int32_t> old_slots;
  std::vector<std::uint8_t> old_used;
  old_keys.swap(keys_);
  old_slots.swap(slots_);
  old_used.swap(used_);
  keys_.assign(cap, 0);
  slots_.assign(4 * cap, -1);
  used_.assign(cap, 0);
  mask_ = cap - 1;
  for (std::size_t i = 0; i < old_keys.size(); ++i) {
    if (!old_used[i]) continue;
    std::size_t h = mix(old_keys[i]) & mask_;
    while (used_[h]) h = (h + 1) & mask_;
    used_[h] = 1;
    keys_[h] = old_keys[i];
    std::copy(old_slots.begin() + 4 * i, old_slots.begin() + 4 * i + 4, slots_.begin() + 4 * h);
  }
}

std::uint64_t CellIndexHash::mix(std::uint64_t k) {  // splitmix64 finaliser
  k ^= k >> 30;
  k *= 0xbf58476d1ce4e5b9ULL;
  k ^= k >> 27;
  k *= 0x94d049bb133111ebULL;
  k ^= k >> 31;
  return k;
}

void CellIndexHash::add(std::int32_t ix, std::int32_t iy, std::int32_t cell) {
  if (2 * (size_ + 1) > keys_.size()) reserve(2 * (size_ + 1));
  const std::uint64_t key = pack(ix, iy);
  std::size_t h = mix(key) & mask_;
  while (used_[h] && keys_[h] != key) h = (h + 1) & mask_;
  if (!used_[h]) {
    used_[h] = 1;
    keys_[h] = key;
    ++size_;
  }
  std::int32_t* s = &slots_[4 * h];
  for (int k = 0; k < 4; ++k)
    if (s[k] < 0) {
      s[k] = cell;
      return;
    }
  // More than four cells on one key cannot happen: each key is shared by exactly a 2x2 block.
}

const std::int32_t* CellIndexHash::find(std::int32_t ix, std::int32_t iy) const {
  if (size_ == 0) return nullptr;
  const std::uint64_t key = pack(ix, iy);
  std::size_t h = mix(key) & mask_;
  while (used_[h]) {
    if (keys_[h] == key) return &slots_[4 * h];
    h = (h + 1) & mask_;
  }
  return nullptr;
}

std::size_t CellIndexHash::memoryBytes() const {
  return keys_.capacity() * sizeof(std::uint64_t) + slots_.capacity() * sizeof(std::int32_t) + used_.capacity();
}

const std::int32_t* NdtGrid::cellsNear(double x, double y) const {
  // Keys are cell (or half-cell) counts; far-away or NaN points have none (and must not overflow).
  const double step = lookup == CellLookup::Neighbours ? resolution : 0.5 * resolution;
  const double shift = lookup == CellLookup::Neighbours ? 0.5 : 0.0;  // nearest vertex vs containing cell
  const double u = x / step + shift, v = y / step + shift;
  if (!(std::abs(u) < 1e9 && std::abs(v) < 1e9)) return nullptr;
  return index.find(floorToInt(u), floorToInt(v));
}

}  // namespace detail

template class WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>;
template class WeightedNDT2D<pcl::PointXYZI, pcl::PointXYZI>;
template class WeightedNDT2D<PointRadar, PointRadar>;

}  // namespace radar_ndt

// PCL's templates for the custom point type, compiled once here (PCL precompiles them only for its
// own point types): the Registration base, PCLBase and the kd-tree that Registration holds.
template class pcl::PCLBase<radar_ndt::PointRadar>;
template class pcl::search::KdTree<radar_ndt::PointRadar>;
template class pcl::KdTreeFLANN<radar_ndt::PointRadar>;
template class pcl::Registration<radar_ndt::PointRadar, radar_ndt::PointRadar, float>;
