// Every real scene renders visibly with default options (issue 14): `multiray render` at
// 96x54, and the picture must be neither black nor flat (mean and spread of the 8-bit
// luminance above a floor). Scenes whose files are absent skip with a message. Also the
// --env map and --sun options from the command line, and their one-line errors.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_cli.h"

namespace gallery_test {

using multiray::testing::run_cli;

struct Picture {
  double mean = 0, spread = 0;  // of 8-bit luminance
};

// Renders `args` into a fresh folder and measures frame_0000.png.
Picture render(const std::string& name, const std::string& args, std::string* out) {
  const std::string dir = ::testing::TempDir() + "/gallery_" + name;
  std::filesystem::remove_all(dir);
  const auto r = run_cli(MULTIRAY_BIN, "render " + args + " -q --out " + dir);
  *out = r.out;
  Picture p;
  if (r.code != 0) return p;
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load((dir + "/frame_0000.png").c_str(), &w, &h, &n, 3);
  if (px == nullptr) return p;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < w * h; ++i) {
    const double y = 0.2126 * px[3 * i] + 0.7152 * px[3 * i + 1] + 0.0722 * px[3 * i + 2];
    sum += y, sum2 += y * y;
  }
  stbi_image_free(px);
  p.mean = sum / (w * h);
  p.spread = std::sqrt(std::max(0.0, sum2 / (w * h) - p.mean * p.mean));
  return p;
}

struct SceneCase {
  const char* name;
  const char* root;  // "shared", "assimp" or "" (built-in)
  const char* path;
  const char* extra;
};

std::string file_of(const SceneCase& c) {
  if (std::string(c.root) == "shared") return std::string(MULTIRAY_SHARED_DATA_DIR) + "/" + c.path;
  if (std::string(c.root) == "assimp")
    return std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/" + c.path;
  return "";
}

class Gallery : public ::testing::TestWithParam<SceneCase> {};

// Floors: a mean of 25 (of 255) and a spread of 5 levels. Measured at the time of writing
// (96x54, 8 spp): means 31-181, spreads 6.7 (the small Wuson) to 53. Before daylight had
// a sun, the bunny and Wuson were light silhouettes on an equally light sky (spread
// 1.6-2.5) and failed, as did the black DamagedHelmet of before (max 9 of 255).
TEST_P(Gallery, DefaultRenderIsNeitherBlackNorFlat) {
  const SceneCase& c = GetParam();
  const std::string file = file_of(c);
  if (!file.empty() && !std::filesystem::exists(file)) GTEST_SKIP() << "missing " << file;
  std::string out;
  const Picture p = render(c.name, file + " --res 96x54 --spp 8 " + c.extra, &out);
  std::printf("%s: mean %.1f, spread %.1f\n", c.name, p.mean, p.spread);
  EXPECT_GT(p.mean, 25.0) << out;
  EXPECT_GT(p.spread, 5.0) << out;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, Gallery,
    ::testing::Values(
        SceneCase{"default", "", "", ""},
        SceneCase{"cornell_mcguire", "shared", "cornell_box/mcguire/CornellBox-Original.obj", ""},
        SceneCase{"cornell_mitsuba", "shared",
                  "cornell_box/mitsuba/docs/scenes/variants_cbox_rgb.xml",
                  "--allow-outside-paths"},
        SceneCase{"bunny", "shared", "meshes/stanford_bunny/bunny.ply", ""},
        SceneCase{"damaged_helmet", "shared", "meshes/damaged_helmet/DamagedHelmet.gltf", ""},
        SceneCase{"flight_helmet", "shared", "meshes/flight_helmet/FlightHelmet.gltf", ""},
        SceneCase{"flight_helmet_notextures", "shared",
                  "meshes/flight_helmet/FlightHelmet_notextures.gltf", ""},
        SceneCase{"sponza", "shared", "meshes/dabrovic_sponza/sponza.obj", ""},
        SceneCase{"engine", "shared", "meshes/assimp/2CylinderEngine.glb", ""},
        SceneCase{"clearcoat", "shared", "meshes/assimp/ClearCoatTest/ClearCoatTest.gltf", ""},
        SceneCase{"wuson_obj", "shared", "meshes/assimp/WusonOBJ.obj", ""},
        SceneCase{"wuson_ply", "shared", "meshes/assimp/Wuson.ply", ""},
        SceneCase{"regr01", "shared", "meshes/assimp/regr01.obj", ""}),
    [](const ::testing::TestParamInfo<SceneCase>& i) { return std::string(i.param.name); });

// Sponza with no flags (issue 32): seen from inside its courtyard, not as a brick box from
// outside, and exposed by the meter so that the interior is not black: at 96x54 and 8 spp
// the picture's mean was 18 of 255 at exposure 0 and is about 100 metered.
TEST(Gallery, SponzaIsSeenFromInsideAndMetered) {
  const std::string file =
      std::string(MULTIRAY_SHARED_DATA_DIR) + "/meshes/dabrovic_sponza/sponza.obj";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "missing " << file;
  std::string out;
  const Picture p = render("sponza_inside", file + " --res 96x54 --spp 8", &out);
  EXPECT_GT(p.mean, 60.0) << out;
  std::ifstream in(::testing::TempDir() + "/gallery_sponza_inside/stats.json");
  const auto settings = nlohmann::json::parse(in).at("settings");
  EXPECT_EQ(settings.at("camera").at("source"), "default-interior");
  EXPECT_EQ(settings.at("exposure"), "auto");
  EXPECT_GT(settings.at("exposure_ev").get<double>(), 2.0);
}

// A 16 x 8 Radiance .hdr written with stb: a dim sky with a bright band near the zenith.
std::string write_hdr_sky() {
  const std::string path = ::testing::TempDir() + "/gallery_sky.hdr";
  std::vector<float> px(16 * 8 * 3, 0.2f);
  for (int x = 0; x < 16; ++x)
    for (int c = 0; c < 3; ++c) px[size_t((1 * 16 + x) * 3 + c)] = 20.0f;
  EXPECT_NE(stbi_write_hdr(path.c_str(), 16, 8, 3, px.data()), 0);
  return path;
}

TEST(LightingCli, HdrMapAndSunRender) {
  std::string out;
  const Picture map = render("hdr", "--res 48x32 --spp 8 --env " + write_hdr_sky(), &out);
  EXPECT_GT(map.mean, 25.0) << out;
  const Picture sun = render("sun", "--res 48x32 --spp 8 --env 0 --sun 20,60,3", &out);
  EXPECT_GT(sun.mean, 10.0) << out;
}

TEST(LightingCli, BadValuesAreOneLineErrors) {
  const std::string dir = ::testing::TempDir() + "/gallery_bad";
  for (const std::string& args :
       {std::string("--sun 10"), std::string("--sun 10,95"), std::string("--sun 10,45,-1"),
        std::string("--sun 10,45,3,0"), std::string("--env missing.hdr"),
        std::string("--env-scale -1"), std::string("--env sky.png")}) {
    std::filesystem::remove_all(dir);
    const auto r = run_cli(MULTIRAY_BIN, "render --res 8x8 --spp 1 --out " + dir + " " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << args << ": " << r.out;
  }
  // Not an image at all, with the right extension.
  const std::string fake = ::testing::TempDir() + "/gallery_fake.exr";
  {
    std::FILE* f = std::fopen(fake.c_str(), "w");
    std::fputs("not an exr", f);
    std::fclose(f);
  }
  std::filesystem::remove_all(dir);
  const auto r = run_cli(MULTIRAY_BIN, "render --res 8x8 --spp 1 --out " + dir + " --env " + fake);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("gallery_fake.exr"), std::string::npos) << r.out;
}

}  // namespace gallery_test
