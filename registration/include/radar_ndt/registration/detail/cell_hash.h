#pragma once
// Hashing 2D integer cell and voxel coordinates: the lookup from a point to its NDT cells and the
// one-pass grouping of points by cell or voxel, without sorting and without a dense grid over the
// extent (memory linear in the occupied cells).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace radar_ndt {
namespace detail {

/// A 2D integer cell or voxel coordinate packed into one 64-bit key, and the hash both maps below
/// use (splitmix64's finaliser).
inline std::uint64_t packKey(std::int32_t ix, std::int32_t iy) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) | static_cast<std::uint32_t>(iy);
}
inline void unpackKey(std::uint64_t key, std::int32_t& ix, std::int32_t& iy) {
  ix = static_cast<std::int32_t>(static_cast<std::uint32_t>(key >> 32));
  iy = static_cast<std::int32_t>(static_cast<std::uint32_t>(key & 0xffffffffu));
}
inline std::uint64_t hashKey(std::uint64_t k) {
  k ^= k >> 30;
  k *= 0xbf58476d1ce4e5b9ULL;
  k ^= k >> 27;
  k *= 0x94d049bb133111ebULL;
  k ^= k >> 31;
  return k;
}

/// Open-addressing hash from a 2D integer key to up to four cell indices (-1 = none). Memory is
/// linear in the number of keys; there is no dense grid over the extent.
class CellIndexHash {
 public:
  void clear();
  void reserve(std::size_t keys);
  /// Adds `cell` to the slot list of key (ix, iy).
  void add(std::int32_t ix, std::int32_t iy, std::int32_t cell);
  /// After the last add(): when the keys' bounding box is small against their count (a scan or a
  /// submap, not a long sparse track), also lay them out in a dense row-major table, so find() is
  /// an index computation instead of a hash probe. A later add() drops the table.
  void finalize();
  /// The four slots of (ix, iy), or nullptr when the key is absent.
  inline const std::int32_t* find(std::int32_t ix, std::int32_t iy) const {
    if (!dense_.empty()) {
      const std::int64_t dx = static_cast<std::int64_t>(ix) - dense_x0_, dy = static_cast<std::int64_t>(iy) - dense_y0_;
      if (dx < 0 || dy < 0 || dx >= dense_w_ || dy >= dense_h_) return nullptr;
      const std::int32_t* slots = dense_[static_cast<std::size_t>(dy * dense_w_ + dx)].slots;
      return slots[0] >= 0 ? slots : nullptr;
    }
    if (size_ == 0) return nullptr;
    const std::uint64_t key = packKey(ix, iy);
    std::size_t h = hashKey(key) & mask_;
    while (entries_[h].slots[0] >= 0) {
      if (entries_[h].key == key) return entries_[h].slots;
      h = (h + 1) & mask_;
    }
    return nullptr;
  }
  std::size_t size() const { return size_; }
  std::size_t memoryBytes() const;

 private:
  /// Key and its four slots in one 24-byte entry: a lookup touches one cache line. An entry is
  /// empty while slots[0] < 0 (an occupied key always has a first slot).
  struct Entry {
    std::uint64_t key;
    std::int32_t slots[4];
  };
  struct Slots {
    std::int32_t slots[4];
  };
  std::vector<Entry> entries_;
  std::size_t size_ = 0;
  std::size_t mask_ = 0;
  std::vector<Slots> dense_;  ///< empty unless finalize() found the keys compact
  std::int64_t dense_x0_ = 0, dense_y0_ = 0, dense_w_ = 0, dense_h_ = 0;
};

/// Open-addressing map from a packed 2D integer key to a dense index (0, 1, 2, … in order of first
/// insertion), for grouping points by cell or voxel in one pass without sorting.
class KeyIndexMap {
 public:
  explicit KeyIndexMap(std::size_t expected_keys) {
    std::size_t cap = 16;
    while (cap < 2 * expected_keys) cap <<= 1;
    keys_.assign(cap, 0);
    index_.assign(cap, -1);
    mask_ = cap - 1;
  }
  /// The index of key (ix, iy), inserting it with index `next` when absent (then `inserted` is true).
  inline std::int32_t findOrInsert(std::int32_t ix, std::int32_t iy, std::int32_t next, bool& inserted) {
    if (2 * (count_ + 1) > keys_.size()) grow();
    const std::uint64_t key = packKey(ix, iy);
    std::size_t h = hashKey(key) & mask_;
    while (index_[h] >= 0) {
      if (keys_[h] == key) {
        inserted = false;
        return index_[h];
      }
      h = (h + 1) & mask_;
    }
    keys_[h] = key;
    index_[h] = next;
    ++count_;
    inserted = true;
    return next;
  }

 private:
  void grow() {
    std::vector<std::uint64_t> keys;
    std::vector<std::int32_t> index;
    keys.swap(keys_);
    index.swap(index_);
    keys_.assign(2 * keys.size(), 0);
    index_.assign(2 * keys.size(), -1);
    mask_ = keys_.size() - 1;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (index[i] < 0) continue;
      std::size_t h = hashKey(keys[i]) & mask_;
      while (index_[h] >= 0) h = (h + 1) & mask_;
      keys_[h] = keys[i];
      index_[h] = index[i];
    }
  }
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> index_;
  std::size_t mask_ = 0, count_ = 0;
};

}  // namespace detail
}  // namespace radar_ndt
