// Block histograms (Bruder et al. 2017, §5) on synthetic volumes whose answers are known:
// partial blocks, value ranges with their one-voxel apron, density counts, and block
// opacity that is exactly 0 for blocks the transfer function maps to nothing and
// conservative for narrow features between density bin edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "volume/blocks.h"

namespace multiray {
namespace blocks_test {

// nx x ny x nz voxels with values f(x, y, z).
template <class F>
Volume synthetic(int nx, int ny, int nz, F f) {
  Volume v;
  v.nx = nx, v.ny = ny, v.nz = nz;
  v.values.resize(v.voxel_count());
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) v.values[(size_t(z) * ny + y) * nx + x] = f(x, y, z);
  v.min_value = *std::min_element(v.values.begin(), v.values.end());
  v.max_value = *std::max_element(v.values.begin(), v.values.end());
  return v;
}

// 40x20x17 zeros with a ball of 100 (radius 7 around (20, 10, 8)).
Volume ball() {
  return synthetic(40, 20, 17, [](int x, int y, int z) {
    const int dx = x - 20, dy = y - 10, dz = z - 8;
    return dx * dx + dy * dy + dz * dz <= 49 ? 100.0f : 0.0f;
  });
}

// Range of `v` over block (bx, by, bz) and a one-voxel apron, by brute force.
std::array<float, 2> brute_range(const Volume& v, int bx, int by, int bz) {
  float lo = INFINITY, hi = -INFINITY;
  for (int z = std::max(bz * 16 - 1, 0); z < std::min(bz * 16 + 17, v.nz); ++z)
    for (int y = std::max(by * 16 - 1, 0); y < std::min(by * 16 + 17, v.ny); ++y)
      for (int x = std::max(bx * 16 - 1, 0); x < std::min(bx * 16 + 17, v.nx); ++x)
        lo = std::min(lo, v.at(x, y, z)), hi = std::max(hi, v.at(x, y, z));
  return {lo, hi};
}

TEST(Blocks, CountsPartialBlocksAndRangesWithApron) {
  const Volume v = ball();
  const VolumeBlocks b = build_blocks(v);
  EXPECT_EQ(b.bx, 3);
  EXPECT_EQ(b.by, 2);
  EXPECT_EQ(b.bz, 2);
  EXPECT_EQ(b.count(), 12u);
  EXPECT_EQ(block_length(2, 40), 8);
  EXPECT_EQ(block_length(1, 20), 4);
  EXPECT_EQ(block_length(1, 17), 1);
  for (int z = 0; z < b.bz; ++z) {
    for (int y = 0; y < b.by; ++y) {
      for (int x = 0; x < b.bx; ++x) {
        const size_t i = b.index(x, y, z);
        const auto want = brute_range(v, x, y, z);
        EXPECT_EQ(b.min_value[i], want[0]) << x << " " << y << " " << z;
        EXPECT_EQ(b.max_value[i], want[1]) << x << " " << y << " " << z;
        const uint64_t voxels =
            uint64_t(block_length(x, 40)) * block_length(y, 20) * block_length(z, 17);
        const auto& d = b.density[i];
        EXPECT_EQ(std::accumulate(d.begin(), d.end(), uint64_t(0)), voxels);
        EXPECT_EQ(uint64_t(d[0]) + d[kDensityBins - 1], voxels);  // only 0 and 100
      }
    }
  }
}

TEST(Blocks, ApronReachesOneVoxelIntoTheNeighbours) {
  // One voxel of 7 at x = 16: the first voxel of block 1 and the apron of block 0.
  const Volume v = synthetic(40, 4, 4, [](int x, int, int) { return x == 16 ? 7.0f : 0.0f; });
  const VolumeBlocks b = build_blocks(v);
  EXPECT_EQ(b.max_value[b.index(0, 0, 0)], 7);
  EXPECT_EQ(b.max_value[b.index(1, 0, 0)], 7);
  EXPECT_EQ(b.max_value[b.index(2, 0, 0)], 0);
  EXPECT_EQ(b.density[b.index(0, 0, 0)][kDensityBins - 1], 0u);   // not its own voxel
  EXPECT_EQ(b.density[b.index(1, 0, 0)][kDensityBins - 1], 16u);  // 1 x 4 x 4
}

TEST(Blocks, OpacityIsExactlyZeroWhereTheFunctionIsAndPositiveElsewhere) {
  const Volume v = ball();
  const VolumeBlocks b = build_blocks(v);
  TransferFunction tf;
  tf.points = {{0, {0, 0, 0}, 0}, {50, {1, 0, 0}, 0}, {100, {1, 1, 1}, 1}};
  const BlockOpacity o = block_opacity(b, tf, v);
  ASSERT_EQ(o.max_opacity.size(), b.count());
  size_t empty = 0;
  for (size_t i = 0; i < b.count(); ++i) {
    const bool has_ball = b.max_value[i] == 100;
    EXPECT_EQ(o.empty(i), !has_ball) << "block " << i;
    EXPECT_EQ(o.max_opacity[i], has_ball ? 1.0f : 0.0f);
    empty += o.empty(i);
    const auto& h = o.histogram[i];
    EXPECT_FLOAT_EQ(std::accumulate(h.begin(), h.end(), 0.0f), 1.0f);
    if (!has_ball) {
      EXPECT_EQ(h[0], 1.0f);
    }
  }
  EXPECT_GT(empty, 0u);
  EXPECT_LT(empty, b.count());
}

TEST(Blocks, NarrowSpikeBetweenBinEdgesIsNotMissed) {
  // Values 0..39 along x; density bins are 39/64 wide, so a spike at 10.2..10.4 lies
  // inside bin 16 ([9.75, 10.36]) and touches bin 17: no bin edge or block range end
  // coincides with its peak.
  const Volume v = synthetic(40, 20, 17, [](int x, int, int) { return float(x); });
  const VolumeBlocks b = build_blocks(v);
  TransferFunction tf;
  tf.points = {{0, {0, 0, 0}, 0},
               {10.2f, {1, 1, 1}, 0},
               {10.3f, {1, 1, 1}, 0.6f},
               {10.4f, {1, 1, 1}, 0},
               {39, {0, 0, 0}, 0}};
  const BlockOpacity o = block_opacity(b, tf, v);
  for (int z = 0; z < b.bz; ++z) {
    for (int y = 0; y < b.by; ++y) {
      EXPECT_EQ(o.max_opacity[b.index(0, y, z)], 0.6f);  // x 0..16 holds 10.3
      EXPECT_EQ(o.max_opacity[b.index(1, y, z)], 0.0f);  // x 15..32
      EXPECT_EQ(o.max_opacity[b.index(2, y, z)], 0.0f);
    }
  }
  // The voxels of bin 16 (x = 10) are counted as up to 0.6 opaque: bin 9 of 16.
  const auto& h = o.histogram[b.index(0, 0, 0)];
  EXPECT_GT(h[9], 0.0f);
  EXPECT_THROW(block_opacity(b, TransferFunction{}, v), std::invalid_argument);
}

TEST(Blocks, ConstantVolume) {
  const Volume v = synthetic(5, 5, 5, [](int, int, int) { return 3.0f; });
  const VolumeBlocks b = build_blocks(v);
  ASSERT_EQ(b.count(), 1u);
  EXPECT_EQ(b.density[0][0], 125u);
  TransferFunction tf;
  tf.points = {{0, {0, 0, 0}, 0}, {3, {1, 1, 1}, 0.5f}};
  EXPECT_EQ(block_opacity(b, tf, v).max_opacity[0], 0.5f);
}

}  // namespace blocks_test
}  // namespace multiray
