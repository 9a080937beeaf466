// detail/cell_hash.h: the cell index (dense table and hash agree) and the key map that groups
// points by cell or voxel.
#include <gtest/gtest.h>

#include <cstdint>

#include "radar_ndt/registration/detail/cell_hash.h"

using namespace radar_ndt;

// The cell index answers the same through its dense table (compact keys, after finalize()) as
// through the hash (sparse keys, or after a later add()).
TEST(CellIndexHash, DenseTableAgreesWithTheHash) {
  auto fill = [](detail::CellIndexHash& h, int spread) {
    int cell = 0;
    for (int iy = -20; iy <= 20; iy += 2)
      for (int ix = -30; ix <= 30; ix += 3) h.add(ix * spread, iy, cell++);
  };
  for (const int spread : {1, 100000}) {  // 1: a dense table is built; 100000: too sparse for one
    detail::CellIndexHash hashed, dense;
    fill(hashed, spread);
    fill(dense, spread);
    dense.finalize();
    if (spread == 1) {
      EXPECT_GT(dense.memoryBytes(), hashed.memoryBytes());
    } else {
      EXPECT_EQ(dense.memoryBytes(), hashed.memoryBytes());
    }
    for (int iy = -25; iy <= 25; ++iy)
      for (int ix = -40; ix <= 40; ++ix) {
        const std::int32_t* a = hashed.find(ix * spread, iy);
        const std::int32_t* b = dense.find(ix * spread, iy);
        ASSERT_EQ(a == nullptr, b == nullptr) << ix << "," << iy;
        if (a) {
          for (int k = 0; k < 4; ++k) EXPECT_EQ(a[k], b[k]);
        }
      }
    // A key added after finalize() must be found (the dense table is dropped, not left stale).
    dense.add(1, 1, 999);
    const std::int32_t* added = dense.find(1, 1);
    ASSERT_NE(added, nullptr);
    EXPECT_EQ(added[0], 999);
  }
}

TEST(KeyIndexMap, FindsWhatItInsertedAndGrows) {
  detail::KeyIndexMap map(2);  // grows well past its first capacity
  std::int32_t next = 0;
  for (int ix = -50; ix < 50; ++ix)
    for (int iy = -3; iy < 3; ++iy) {
      bool inserted = false;
      EXPECT_EQ(map.findOrInsert(ix, iy, next, inserted), next);
      EXPECT_TRUE(inserted);
      ++next;
    }
  std::int32_t expect = 0;
  for (int ix = -50; ix < 50; ++ix)
    for (int iy = -3; iy < 3; ++iy) {
      bool inserted = true;
      EXPECT_EQ(map.findOrInsert(ix, iy, -7, inserted), expect++) << ix << "," << iy;
      EXPECT_FALSE(inserted);
    }
  std::int32_t ix = 0, iy = 0;
  detail::unpackKey(detail::packKey(-5, 123456), ix, iy);
  EXPECT_EQ(ix, -5);
  EXPECT_EQ(iy, 123456);
}
