// The feature buffers' multi-layer EXR (core/aov_exr.h) read back with OpenEXR's own
// reader: the channel names other tools expect, every value bit for bit; and --aov's list
// parsing (core/feature_buffers.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/aov_exr.h"
#include "core/error.h"
#include "support/exr_channels.h"

namespace multiray {
namespace aov_exr_test {

using multiray::testing::exr_channel;
using multiray::testing::exr_channels;

Framebuffer sample_frame() {
  Framebuffer fb(5, 3);
  fb.features.resize(5, 3);
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    const float k = float(i);
    fb.pixels[i] = Vec3(k, k + 0.25f, k + 0.5f);
    const float v[FeatureBuffers::kFloats] = {0.1f * k, 0.2f,      0.3f,     0.0f, 1.0f,    0.0f,
                                              2.0f + k, 0.01f * k, 5.0f * k, 6.0f, 7.0f + k};
    fb.features.set_packed(i, v);
  }
  fb.features.depth[0] = INFINITY;  // a miss
  return fb;
}

TEST(AovExr, EveryLayerReadsBackWithItsName) {
  const std::string path = ::testing::TempDir() + "/aov_exr_every.exr";
  const Framebuffer fb = sample_frame();
  write_exr_with_aovs(path, fb, aov_names());
  EXPECT_THAT(exr_channels(path),
              ::testing::ElementsAre("A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R",
                                     "depth.Z", "emission.B", "emission.G", "emission.R",
                                     "normal.X", "normal.Y", "normal.Z", "variance.Y"));
  const std::vector<float> r = exr_channel(path, "R"), a = exr_channel(path, "A");
  const std::vector<float> albedo = exr_channel(path, "albedo.R");
  const std::vector<float> ny = exr_channel(path, "normal.Y");
  const std::vector<float> depth = exr_channel(path, "depth.Z");
  const std::vector<float> var = exr_channel(path, "variance.Y");
  const std::vector<float> er = exr_channel(path, "emission.R"),
                           eg = exr_channel(path, "emission.G"),
                           eb = exr_channel(path, "emission.B");
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    EXPECT_EQ(r[i], fb.pixels[i].x);
    EXPECT_EQ(a[i], 1.0f);
    EXPECT_EQ(albedo[i], fb.features.albedo[3 * i]);
    EXPECT_EQ(ny[i], 1.0f);
    EXPECT_EQ(var[i], fb.features.variance[i]);
    EXPECT_EQ(er[i], 5.0f * float(i));
    EXPECT_EQ(eg[i], 6.0f);
    EXPECT_EQ(eb[i], 7.0f + float(i));
    if (i == 0)
      EXPECT_TRUE(std::isinf(depth[i]));
    else
      EXPECT_EQ(depth[i], fb.features.depth[i]);
  }
}

TEST(AovExr, OnlyTheLayersAskedFor) {
  const std::string path = ::testing::TempDir() + "/aov_exr_depth.exr";
  write_exr_with_aovs(path, sample_frame(), {"depth"});
  EXPECT_THAT(exr_channels(path), ::testing::ElementsAre("A", "B", "G", "R", "depth.Z"));
  write_exr_with_aovs(path, sample_frame(), {"emission"});
  EXPECT_THAT(exr_channels(path), ::testing::ElementsAre("A", "B", "G", "R", "emission.B",
                                                         "emission.G", "emission.R"));
}

TEST(AovExr, RefusesAFrameWithoutFeatureBuffers) {
  const std::string path = ::testing::TempDir() + "/aov_exr_none.exr";
  std::filesystem::remove(path);
  EXPECT_THROW(write_exr_with_aovs(path, Framebuffer(4, 4), {"albedo"}), InputError);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(AovList, ParsesAnySubsetInLayerOrder) {
  EXPECT_THAT(parse_aov_list("variance,albedo", "--aov"),
              ::testing::ElementsAre("albedo", "variance"));
  EXPECT_THAT(parse_aov_list("depth,depth", "--aov"), ::testing::ElementsAre("depth"));
  EXPECT_EQ(parse_aov_list("emission,albedo,normal,depth,variance", "--aov"), aov_names());
}

TEST(AovList, UnknownNamesSayTheNearest) {
  try {
    parse_aov_list("albedo,normals", "--aov");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("'normals' (did you mean normal?)"));
    EXPECT_THAT(e.what(), ::testing::Not(::testing::HasSubstr("\n")));
  }
  EXPECT_THROW(parse_aov_list("", "--aov"), InputError);
  EXPECT_THROW(parse_aov_list("beauty", "--aov"), InputError);
}

}  // namespace aov_exr_test
}  // namespace multiray
