// The OpenCL volume image against the CPU's. Both run the same arithmetic in the same
// order (contraction off, correctly rounded division and sqrt), so most pixels are equal
// bit for bit; they differ where expm1 (PoCL's vs glibc's) rounds differently, by an ulp,
// and where that ulp tips an early-ray-termination decision (a sample more or less, at
// most 1 - ert_threshold = 1% of the colour) or a table index.
//
// Tolerance: per image, mean |difference| over channels < 1e-3 and at least 99.9% of the
// pixels within 1e-2 in every channel. An ERT flip changes a pixel by at most the 1% of
// colour behind the threshold, hence 1e-2 per pixel; the 0.1% allows a few such flips, and
// the mean bound catches what is spread over the image. A wrong step, table, gradient or
// camera moves the mean by far more (a step_scale of 2 on the ball moves it by ~1e-2, see
// opencl_volume_test.cpp). Measured on PoCL 3.1 (printed by each test): max 1.8e-7, mean
// below 5e-10, 97.8% (neghip) to 99.7% (ball) of pixels bit-identical, no ERT flip seen.
//
// Also here: CPU + OpenCL as one heterogeneous pair under the engine, and the CLI with two
// PoCL devices on a real volume.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "balance/balancer.h"
#include "engine/engine.h"
#include "opencl_helpers.h"
#include "opencl_volume_helpers.h"
#include "support/run_cli.h"

namespace multiray {
namespace opencl_volume_match_test {

using testing::ball_case;
using testing::render_whole;
using testing::view_of;
using testing::volume_settings;
using testing::VolumeCase;

void expect_close(const char* what, const Framebuffer& cpu, const Framebuffer& cl) {
  const testing::ImageDiff d = testing::diff(cpu, cl);
  testing::print_diff(what, d, cpu.pixels.size());
  EXPECT_LT(d.mean, 1e-3) << what;
  EXPECT_GE(d.within_1e2, 0.999) << what;
}

void expect_matches_cpu(const VolumeCase& c, const char* what, int w, int h, int spp) {
  CpuDevice cpu(*c.cache, {}, "cpu");
  OpenClDevice cl(*c.cache, {}, "opencl:0");
  const ViewSetup view = view_of(c.scene, w, h, 1);
  const RenderSettings s = volume_settings(c, spp, 3);
  expect_close(what, render_whole(cpu, view, s), render_whole(cl, view, s));
}

TEST(OpenClVolumeMatch, BallMatchesTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  expect_matches_cpu(*c, "ball, spp 1", 96, 72, 1);
  expect_matches_cpu(*c, "ball, spp 4", 96, 72, 4);
}

// A real CT volume (64^3, 8-bit) with the "angio" preset.
TEST(OpenClVolumeMatch, NeghipMatchesTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = testing::shared_case("neghip_64x64x64_uint8.nhdr", Vec3(60, 45, 110));
  if (!c) GTEST_SKIP() << "missing " << testing::shared_volume_path("neghip_64x64x64_uint8.nhdr");
  expect_matches_cpu(*c, "neghip, spp 1", 160, 120, 1);
  // Without early ray termination every ray runs to the end of the grid.
  auto no_ert = std::make_shared<VolumeStyle>(*c->style);
  no_ert->ert_threshold = 2;
  c->style = no_ert;
  expect_matches_cpu(*c, "neghip, no ERT", 160, 120, 1);
}

// Irregular sampling: a per-pixel sample map (0 to 3 samples) is honoured as on the CPU.
TEST(OpenClVolumeMatch, SampleMapMatchesTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  std::vector<uint8_t> map(size_t(48) * 36);
  for (size_t i = 0; i < map.size(); ++i) map[i] = uint8_t((i * 5 + i / 48) % 4);
  ViewSetup view = view_of(c->scene, 48, 36);
  view.spp_map = &map;
  CpuDevice cpu(*c->cache, {}, "cpu");
  OpenClDevice cl(*c->cache, {}, "opencl:0");
  const Framebuffer cl_image = render_whole(cl, view, volume_settings(*c));
  expect_close("ball, sample map", render_whole(cpu, view, volume_settings(*c)), cl_image);
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] == 0) {
      EXPECT_EQ(max_component(cl_image.pixels[i]), 0.0f);
    }
}

// CPU + OpenCL under the engine (hybrid balancer), frame after frame: every frame's image
// matches the CPU's alone within the tolerance, and both devices render part of it.
TEST(OpenClVolumeMatch, CpuAndOpenClPairMatchesTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  CpuDevice cpu(*c->cache, {}, "cpu");
  OpenClDevice cl(*c->cache, {}, "opencl:0");
  Engine engine({&cpu, &cl}, balance::make_balancer("hybrid", 2));
  const int w = 64, h = 48;
  uint64_t cl_pixels = 0;
  for (int f = 0; f < 6; ++f) {
    const ViewSetup view = view_of(c->scene, w, h, f);
    const FrameRecord rec = engine.render_frame(f, {view}, volume_settings(*c));
    ASSERT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(w * h)) << "frame " << f;
    cl_pixels += rec.devices[1].pixels;
    const Framebuffer alone = render_whole(cpu, view, volume_settings(*c));
    expect_close("cpu + opencl frame", alone, engine.images()[0]);
  }
  EXPECT_GT(cl_pixels, 0u);
}

#ifdef MULTIRAY_BIN
// "image_hash" of the first frame in <out>/stats.json.
std::string first_hash(const std::string& out) {
  std::ifstream in(out + "/stats.json");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const size_t at = s.find("\"image_hash\"");
  if (at == std::string::npos) return "";
  const size_t q = s.find('"', s.find(':', at));
  return s.substr(q + 1, 16);
}

// Through the CLI: a CPU + OpenCL pair is accepted for a volume, and two PoCL `basic`
// devices together give the image one of them gives alone, bit for bit.
TEST(OpenClVolumeCli, RendersARealVolumeOnCpuPlusOpenClAndTwoPoclDevices) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const std::string vol = testing::shared_volume_path("neghip_64x64x64_uint8.nhdr");
  if (!std::filesystem::exists(vol)) GTEST_SKIP() << "missing " << vol;
  const std::string out = ::testing::TempDir() + "/multiray_cl_volume";
  const std::string common = "render " + vol + " --res 64x48 -q --overwrite --out " + out;
  testing::CliResult r = testing::run_cli(MULTIRAY_BIN, common + " --devices cpu,opencl");
  ASSERT_EQ(r.code, 0) << r.out;
  if (list_opencl_devices()[0].platform.find("Portable Computing Language") == std::string::npos)
    GTEST_SKIP() << "the two-device part needs PoCL";
  const std::string env = "POCL_DEVICES='basic basic'";
  r = testing::run_cli(MULTIRAY_BIN, common + " --devices opencl:0", env);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string alone = first_hash(out);
  r = testing::run_cli(MULTIRAY_BIN, common + " --devices opencl:0,opencl:1:tile=16", env);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(alone.empty());
  EXPECT_EQ(first_hash(out), alone);
  std::filesystem::remove_all(out);
}
#endif

}  // namespace opencl_volume_match_test
}  // namespace multiray
