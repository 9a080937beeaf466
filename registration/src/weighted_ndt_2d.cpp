// The one translation unit that compiles WeightedNDT2D (and its PCL base templates) for the point
// types the library ships; every other unit sees the extern template declarations in the header.
#define RADAR_NDT_WEIGHTED_NDT_2D_INSTANTIATE
#define PCL_NO_PRECOMPILE  // compile PCL's search and kd-tree templates for PointRadar here
#include "radar_ndt/registration/weighted_ndt_2d.h"

#include "radar_ndt/registration/impl/weighted_ndt_2d.hpp"

namespace radar_ndt {
namespace detail {

void CellIndexHash::clear() {
  entries_.clear();
  size_ = 0;
  mask_ = 0;
}

void CellIndexHash::reserve(std::size_t keys) {
  std::size_t cap = 16;
  while (cap < 2 * keys) cap <<= 1;  // load factor <= 1/2: short linear probes
  if (cap <= entries_.size()) return;
  std::vector<Entry> old(cap, Entry{0, {-1, -1, -1, -1}});
  old.swap(entries_);
  mask_ = cap - 1;
  for (const Entry& e : old) {
    if (e.slots[0] < 0) continue;
    std::size_t h = hashKey(e.key) & mask_;
    while (entries_[h].slots[0] >= 0) h = (h + 1) & mask_;
    entries_[h] = e;
  }
}

void CellIndexHash::add(std::int32_t ix, std::int32_t iy, std::int32_t cell) {
  if (2 * (size_ + 1) > entries_.size()) reserve(2 * (size_ + 1));
  const std::uint64_t key = packKey(ix, iy);
  std::size_t h = hashKey(key) & mask_;
  while (entries_[h].slots[0] >= 0 && entries_[h].key != key) h = (h + 1) & mask_;
  Entry& e = entries_[h];
  if (e.slots[0] < 0) {
    e.key = key;
    ++size_;
  }
  for (int k = 0; k < 4; ++k)
    if (e.slots[k] < 0) {
      e.slots[k] = cell;
      return;
    }
  // More than four cells on one key cannot happen: each key is shared by exactly a 2x2 block.
}

std::size_t CellIndexHash::memoryBytes() const { return entries_.capacity() * sizeof(Entry); }

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
