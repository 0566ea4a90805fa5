// `multiray render` of a format read through assimp (COLLADA), as a user would run it: the
// file's camera frames its textured duck and the picture is not black. Skips when the
// build has no assimp or Debian's assimp-testmodels are not installed.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <filesystem>
#include <string>

#include "support/run_cli.h"

namespace assimp_cli_test {

TEST(AssimpCli, RendersADaeFileNotBlack) {
#ifndef MULTIRAY_HAS_ASSIMP
  GTEST_SKIP() << "built without assimp (MULTIRAY_WITH_ASSIMP)";
#endif
  const std::string scene = std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/Collada/duck.dae";
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << "test file missing: " << scene;
  const std::string dir = ::testing::TempDir() + "/assimp_cli";
  std::filesystem::remove_all(dir);
  const auto r = multiray::testing::run_cli(
      MULTIRAY_BIN, "render " + scene + " --res 48x32 --spp 4 --frames 1 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load((dir + "/frame_0000.png").c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr) << "no readable frame_0000.png; output:\n" << r.out;
  double sum = 0;
  int lit = 0;  // pixels brighter than near-black
  for (int i = 0; i < w * h; ++i) {
    const int v = px[3 * i] + px[3 * i + 1] + px[3 * i + 2];
    sum += v;
    lit += v > 30;
  }
  stbi_image_free(px);
  EXPECT_EQ(w, 48);
  EXPECT_GT(sum / (3.0 * w * h), 20.0) << "mean 8-bit value";
  EXPECT_GT(lit, w * h / 4) << "pixels above near-black";
}

}  // namespace assimp_cli_test
