// Compositing an RGBA layer over real images (core/composite.h): the over operation, the
// real image's round trip through linear light, and the background sequences' names.
#include <gtest/gtest.h>

#include <unistd.h>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <filesystem>
#include <string>

#include "core/composite.h"
#include "core/error.h"

namespace multiray {
namespace composite_test {

std::string scratch(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/composite-" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  return dir + "/" + name;
}

TEST(Composite, OverIsColourPlusTheUncoveredShareOfTheBackground) {
  Framebuffer layer(3, 1), bg(3, 1);
  layer.alpha = {0.0f, 0.25f, 1.0f};
  layer.pixels = {Vec3(0.0f), Vec3(0.1f), Vec3(0.5f, 0.2f, 0.1f)};
  bg.pixels = {Vec3(0.3f, 0.6f, 0.9f), Vec3(0.8f), Vec3(1.0f)};
  const Framebuffer out = composite_over(layer, bg);
  EXPECT_EQ(out.pixels[0].x, 0.3f);  // transparent: the background, bit for bit
  EXPECT_EQ(out.pixels[0].z, 0.9f);
  EXPECT_FLOAT_EQ(out.pixels[1].y, 0.1f + 0.75f * 0.8f);
  EXPECT_FLOAT_EQ(out.pixels[2].x, 0.5f);  // opaque: the layer
  EXPECT_TRUE(out.alpha.empty());
  Framebuffer no_alpha(3, 1);
  EXPECT_THROW(composite_over(no_alpha, bg), std::invalid_argument);
}

// Every 8-bit value of a real image comes back as itself after decoding to linear light and
// encoding again (the composite of a transparent pixel writes the pixel it read).
TEST(Composite, EightBitImagesSurviveTheTripThroughLinearLight) {
  Framebuffer ramp(256, 1);
  std::vector<uint8_t> rgb(256 * 3);
  for (int v = 0; v < 256; ++v) rgb[3 * v] = rgb[3 * v + 1] = rgb[3 * v + 2] = uint8_t(v);
  const std::string path = scratch("ramp.png");
  write_png_rgb8(path, 256, 1, rgb);
  const Framebuffer linear = read_image_linear(path);
  ASSERT_EQ(linear.width, 256);
  EXPECT_EQ(to_srgb8(linear), rgb);
}

TEST(Composite, RgbaPngsHoldStraightColour) {
  Framebuffer layer(2, 1);
  layer.alpha = {0.5f, 0.0f};
  layer.pixels = {Vec3(0.5f), Vec3(0.0f)};  // premultiplied: colour 1 at half coverage
  const std::vector<uint8_t> px = to_srgba8(layer);
  EXPECT_EQ(px[0], 255);
  EXPECT_EQ(px[3], 128);
  EXPECT_EQ(px[7], 0);
}

// An EXR of a layer carries its alpha as A beside the (premultiplied) colour.
TEST(Composite, ExrFilesOfALayerHoldItsAlpha) {
  Framebuffer layer(2, 1);
  layer.alpha = {0.25f, 1.0f};
  layer.pixels = {Vec3(0.1f), Vec3(0.7f)};
  const std::string path = scratch("layer.exr");
  write_exr(path, layer);
  Imf::InputFile file(path.c_str());
  EXPECT_NE(file.header().channels().findChannel("A"), nullptr);
  EXPECT_EQ(read_exr(path).pixels[1].x, 0.7f);
  Framebuffer plain(2, 1);
  write_exr(path, plain);
  EXPECT_EQ(Imf::InputFile(path.c_str()).header().channels().findChannel("A"), nullptr);
}

TEST(Composite, BackgroundSequencesAreNumberedByTheirRunOfHashes) {
  std::vector<uint8_t> rgb(8 * 6 * 3, 200);
  for (int f = 0; f < 3; ++f)
    write_png_rgb8(scratch("bg_00" + std::to_string(f) + ".png"), 8, 6, rgb);
  const BackgroundImages seq(scratch("bg_###.png"), 16, 12, 3);
  EXPECT_EQ(seq.path(2), scratch("bg_002.png"));
  const Framebuffer big = seq.frame(1);  // resized to the output, same aspect
  EXPECT_EQ(big.width, 16);
  EXPECT_EQ(big.height, 12);
  EXPECT_THROW(BackgroundImages(scratch("bg_###.png"), 16, 12, 4), InputError);  // no frame 3
  EXPECT_THROW(BackgroundImages(scratch("bg_###.png"), 16, 16, 3), InputError);  // aspect
  EXPECT_THROW(BackgroundImages(scratch("bg_#_#.png"), 16, 12, 1), InputError);
  // One file serves every frame.
  const BackgroundImages still(scratch("bg_000.png"), 8, 6, 100);
  EXPECT_EQ(still.path(57), scratch("bg_000.png"));
}

}  // namespace composite_test
}  // namespace multiray
