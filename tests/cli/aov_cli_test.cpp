// --aov through the command line: the feature buffers as layers of one EXR (the frame's
// own with --exr, <image>_aov.exr beside a PNG), read back with OpenEXR's reader; bad
// names and impossible combinations refused in one line with exit code 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "support/cli_expect.h"
#include "support/exr_channels.h"

namespace aov_cli_test {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

std::string folder(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/aov_cli_" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

using multiray::testing::exr_channel;
using multiray::testing::exr_channels;

const std::string kSmall = "render --res 32x18 --spp 2 --threads 1 -q ";

// Beside a PNG: <image>_aov.exr with the beauty and every layer asked for. The default
// view of the Cornell box shows the box with a margin of sky: where a pixel met a surface
// its normal is unit and its depth finite, elsewhere (a miss) both say nothing was there.
TEST(AovCli, PngGetsALayeredExrBesideIt) {
  const std::string dir = folder("png");
  const Result r =
      run(kSmall + "--aov albedo,normal,depth,variance,emission --out " + dir + "/x.png");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/x.png"));
  const std::string exr = dir + "/x_aov.exr";
  ASSERT_TRUE(std::filesystem::exists(exr));
  EXPECT_THAT(exr_channels(exr),
              ::testing::ElementsAre("A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R",
                                     "depth.Z", "emission.B", "emission.G", "emission.R",
                                     "normal.X", "normal.Y", "normal.Z", "variance.Y"));
  const std::vector<float> x = exr_channel(exr, "normal.X"), y = exr_channel(exr, "normal.Y"),
                           z = exr_channel(exr, "normal.Z"), d = exr_channel(exr, "depth.Z"),
                           a = exr_channel(exr, "albedo.G"), v = exr_channel(exr, "variance.Y"),
                           e = exr_channel(exr, "emission.G"), beauty = exr_channel(exr, "G");
  size_t hits = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    const float n2 = x[i] * x[i] + y[i] * y[i] + z[i] * z[i];
    if (std::isinf(d[i])) {
      EXPECT_EQ(n2, 0.0f) << i;
      EXPECT_EQ(a[i], 0.0f) << i;
    } else {
      ++hits;
      EXPECT_NEAR(n2, 1.0f, 1e-4f) << i;
      EXPECT_GT(d[i], 0.0f) << i;
    }
    EXPECT_TRUE(a[i] >= 0 && a[i] <= 1) << i;
    EXPECT_GE(v[i], 0.0f) << i;
    EXPECT_GE(e[i], 0.0f) << i;
    EXPECT_LE(e[i], beauty[i]) << i;  // a part of the beauty
  }
  EXPECT_GT(hits, d.size() / 2);
}

// With --exr the frame's EXR itself holds the layers (only those asked for).
TEST(AovCli, ExrHoldsTheLayersAskedFor) {
  const std::string dir = folder("exr");
  const Result r = run(kSmall + "--exr --aov depth --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(exr_channels(dir + "/frame_0000.exr"),
              ::testing::ElementsAre("A", "B", "G", "R", "depth.Z"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/frame_0000_aov.exr"));
}

TEST(AovCli, BadNamesAndCombinationsAreOneLine) {
  using multiray::testing::expect_input_error;
  const std::string out = " --out " + folder("bad");
  for (const auto& [args, word] : std::vector<std::pair<std::string, std::string>>{
           {"--aov albdo", "did you mean albedo?"},
           {"--aov albedo,normals", "did you mean normal?"},
           {"--aov beauty", "unknown AOV 'beauty'"},
           {"--aov depth --integrator ao", "--integrator ao"},
           {"--aov depth --sampling foveated", "--sampling foveated"}}) {
    const std::string line = kSmall + args + out;
    expect_input_error(run(line), line, word);
  }
}

}  // namespace aov_cli_test
