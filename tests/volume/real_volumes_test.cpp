// The real volumes in ../shared/data/volumes against the statistics in its README
// (dimensions, spacing, value range, share of zero voxels). Skipped with a message when
// the folder is absent. The raw loader reads the same files to the same values.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "volume/blocks.h"
#include "volume/load_volume.h"
#include "volume/volume_test_files.h"

namespace multiray {
namespace real_volumes_test {

using test::shared_volume;

double fraction(const Volume& v, bool (*pred)(float)) {
  return double(std::count_if(v.values.begin(), v.values.end(), pred)) / double(v.voxel_count());
}

TEST(RealVolumes, Aneurism) {
  const std::string p = shared_volume("aneurism_256x256x256_uint8.nhdr");
  SKIP_IF_MISSING(p);
  const Volume v = load_volume(p);
  EXPECT_EQ(v.nx, 256);
  EXPECT_EQ(v.ny, 256);
  EXPECT_EQ(v.nz, 256);
  EXPECT_EQ(v.type, VoxelType::u8);
  EXPECT_EQ(v.spacing.x, 1);
  EXPECT_EQ(v.min_value, 0);
  EXPECT_EQ(v.max_value, 255);
  EXPECT_NEAR(fraction(v, [](float x) { return x == 0; }), 0.990, 0.0005);  // README: 99.0%
}

TEST(RealVolumes, CraniumCt) {
  const std::string p = shared_volume("cranium_ct_256x256x108_int16le.nhdr");
  SKIP_IF_MISSING(p);
  const Volume v = load_volume(p);
  EXPECT_EQ(v.nx, 256);
  EXPECT_EQ(v.ny, 256);
  EXPECT_EQ(v.nz, 108);
  EXPECT_EQ(v.type, VoxelType::i16);
  EXPECT_EQ(v.spacing.x, 0.9570312f);
  EXPECT_EQ(v.spacing.y, 0.9570312f);
  EXPECT_EQ(v.spacing.z, 1.5f);
  EXPECT_EQ(v.min_value, -1024);
  EXPECT_EQ(v.max_value, 2986);
  // README: 34.0% above -500 HU, 6.9% above 200 HU.
  EXPECT_NEAR(fraction(v, [](float x) { return x > -500; }), 0.340, 0.0005);
  EXPECT_NEAR(fraction(v, [](float x) { return x > 200; }), 0.069, 0.0005);
}

TEST(RealVolumes, Neghip) {
  const std::string p = shared_volume("neghip_64x64x64_uint8.nhdr");
  SKIP_IF_MISSING(p);
  const Volume v = load_volume(p);
  EXPECT_EQ(v.voxel_count(), 64u * 64u * 64u);
  EXPECT_EQ(v.min_value, 0);
  EXPECT_EQ(v.max_value, 255);
  EXPECT_NEAR(fraction(v, [](float x) { return x == 0; }), 0.536, 0.0005);  // README: 53.6%
}

TEST(RealVolumes, RawLoaderReadsTheSameValues) {
  const std::string p = shared_volume("cranium_ct_256x256x108_int16le.raw");
  SKIP_IF_MISSING(p);
  const Volume raw =
      load_raw_volume(p, parse_raw_spec("256x256x108:int16:le:spacing=0.9570312,0.9570312,1.5"));
  const Volume nrrd = load_volume(shared_volume("cranium_ct_256x256x108_int16le.nhdr"));
  EXPECT_EQ(raw.values, nrrd.values);
  EXPECT_EQ(raw.spacing.z, nrrd.spacing.z);
}

TEST(RealVolumes, AneurismBlocksAreMostlyEmptyForAngio) {
  const std::string p = shared_volume("aneurism_256x256x256_uint8.nhdr");
  SKIP_IF_MISSING(p);
  const Volume v = load_volume(p);
  const VolumeBlocks b = build_blocks(v);
  EXPECT_EQ(b.count(), 16u * 16u * 16u);
  const BlockOpacity o = block_opacity(b, transfer_preset("angio", v), v);
  const size_t empty = size_t(std::count(o.max_opacity.begin(), o.max_opacity.end(), 0.0f));
  // Vessels fill a small part of the volume: most blocks can be skipped.
  EXPECT_GT(empty, b.count() / 2);
  EXPECT_LT(empty, b.count());
}

}  // namespace real_volumes_test
}  // namespace multiray
