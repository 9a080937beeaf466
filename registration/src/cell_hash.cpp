// The cell index hash of detail/cell_hash.h.
#include "radar_ndt/registration/detail/cell_hash.h"

#include <algorithm>
#include <limits>

namespace radar_ndt {
namespace detail {

void CellIndexHash::clear() {
  entries_.clear();
  dense_.clear();
  size_ = 0;
  mask_ = 0;
}

void CellIndexHash::finalize() {
  dense_.clear();
  if (size_ == 0) return;
  std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0, x1 = std::numeric_limits<std::int64_t>::min(),
               y1 = x1;
  for (const Entry& e : entries_) {
    if (e.slots[0] < 0) continue;
    std::int32_t ix, iy;
    unpackKey(e.key, ix, iy);
    x0 = std::min<std::int64_t>(x0, ix);
    x1 = std::max<std::int64_t>(x1, ix);
    y0 = std::min<std::int64_t>(y0, iy);
    y1 = std::max<std::int64_t>(y1, iy);
  }
  const std::int64_t w = x1 - x0 + 1, h = y1 - y0 + 1;
  const auto limit = static_cast<std::int64_t>(8 * size_ + 4096);  // at most ~8x the hash's entries
  if (w > limit || h > limit || w * h > limit) return;
  dense_.assign(static_cast<std::size_t>(w * h), Slots{{-1, -1, -1, -1}});
  for (const Entry& e : entries_) {
    if (e.slots[0] < 0) continue;
    std::int32_t ix, iy;
    unpackKey(e.key, ix, iy);
    std::copy(e.slots, e.slots + 4, dense_[static_cast<std::size_t>((iy - y0) * w + (ix - x0))].slots);
  }
  dense_x0_ = x0;
  dense_y0_ = y0;
  dense_w_ = w;
  dense_h_ = h;
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
  if (!dense_.empty()) dense_.clear();  // stale once a key changes; finalize() again to rebuild
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

std::size_t CellIndexHash::memoryBytes() const {
  return entries_.capacity() * sizeof(Entry) + dense_.capacity() * sizeof(Slots);
}

}  // namespace detail
}  // namespace radar_ndt
