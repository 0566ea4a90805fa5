// The feature buffers' multi-layer EXR (core/aov_exr.h) read back with OpenEXR's own
// reader: the channel names other tools expect, every value bit for bit; and --aov's list
// parsing (core/feature_buffers.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/aov_exr.h"
#include "core/error.h"

namespace multiray {
namespace aov_exr_test {

// The channel names of `path`, in the file's (alphabetical) order.
std::vector<std::string> channels(const std::string& path) {
  Imf::InputFile file(path.c_str());
  std::vector<std::string> out;
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
    out.push_back(it.name());
  return out;
}

// Channel `name` of `path` as floats, row-major.
std::vector<float> read_channel(const std::string& path, const std::string& name) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i box = file.header().dataWindow();
  const int w = box.max.x - box.min.x + 1, h = box.max.y - box.min.y + 1;
  std::vector<float> v(size_t(w) * size_t(h));
  Imf::FrameBuffer fb;
  fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v.data()), sizeof(float),
                             sizeof(float) * size_t(w)));
  file.setFrameBuffer(fb);
  file.readPixels(box.min.y, box.max.y);
  return v;
}

Framebuffer sample_frame() {
  Framebuffer fb(5, 3);
  fb.features.resize(5, 3);
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    const float k = float(i);
    fb.pixels[i] = Vec3(k, k + 0.25f, k + 0.5f);
    const float v[8] = {0.1f * k, 0.2f, 0.3f, 0.0f, 1.0f, 0.0f, 2.0f + k, 0.01f * k};
    fb.features.set_packed(i, v);
  }
  fb.features.depth[0] = INFINITY;  // a miss
  return fb;
}

TEST(AovExr, EveryLayerReadsBackWithItsName) {
  const std::string path = ::testing::TempDir() + "/aov_exr_every.exr";
  const Framebuffer fb = sample_frame();
  write_exr_with_aovs(path, fb, aov_names());
  EXPECT_THAT(channels(path),
              ::testing::ElementsAre("A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R",
                                     "depth.Z", "normal.X", "normal.Y", "normal.Z", "variance.Y"));
  const std::vector<float> r = read_channel(path, "R"), a = read_channel(path, "A");
  const std::vector<float> albedo = read_channel(path, "albedo.R");
  const std::vector<float> ny = read_channel(path, "normal.Y");
  const std::vector<float> depth = read_channel(path, "depth.Z");
  const std::vector<float> var = read_channel(path, "variance.Y");
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    EXPECT_EQ(r[i], fb.pixels[i].x);
    EXPECT_EQ(a[i], 1.0f);
    EXPECT_EQ(albedo[i], fb.features.albedo[3 * i]);
    EXPECT_EQ(ny[i], 1.0f);
    EXPECT_EQ(var[i], fb.features.variance[i]);
    if (i == 0)
      EXPECT_TRUE(std::isinf(depth[i]));
    else
      EXPECT_EQ(depth[i], fb.features.depth[i]);
  }
}

TEST(AovExr, OnlyTheLayersAskedFor) {
  const std::string path = ::testing::TempDir() + "/aov_exr_depth.exr";
  write_exr_with_aovs(path, sample_frame(), {"depth"});
  EXPECT_THAT(channels(path), ::testing::ElementsAre("A", "B", "G", "R", "depth.Z"));
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
  EXPECT_EQ(parse_aov_list("albedo,normal,depth,variance", "--aov"), aov_names());
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
