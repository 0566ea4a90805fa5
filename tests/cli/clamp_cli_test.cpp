// --clamp through the command line: off by default and at 0 (bit for bit), a bound on every
// pixel when on, recorded in stats.json, refused in one line when not a finite number
// >= 0, and offered by render, bench and view in the help's Sampling section.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "support/cli_expect.h"

namespace clamp_cli_test {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

// Renders the default scene small into a folder of its own; returns the folder.
std::string render(const std::string& name, const std::string& extra) {
  const std::string dir = ::testing::TempDir() + "/clamp_cli_" + name;
  std::filesystem::remove_all(dir);
  const Result r = run("render --res 40x24 --spp 4 --threads 1 --exr -q --out " + dir + extra);
  EXPECT_EQ(r.code, 0) << r.out;
  return dir;
}

nlohmann::json stats(const std::string& dir) {
  return nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
}

std::string hash(const std::string& dir) {
  return stats(dir).at("frames").at(0).at("image_hash").get<std::string>();
}

float max_pixel(const std::string& dir) {
  const multiray::Framebuffer fb = multiray::read_exr(dir + "/frame_0000.exr");
  float m = 0;
  for (const multiray::Vec3& p : fb.pixels) m = std::max(m, multiray::max_component(p));
  return m;
}

TEST(ClampCli, ZeroIsBitIdenticalToNoClampAndTheValueIsRecorded) {
  const std::string off = render("off", ""), zero = render("zero", " --clamp 0"),
                    one = render("one", " --clamp 1");
  EXPECT_EQ(hash(zero), hash(off));
  EXPECT_NE(hash(one), hash(off));
  EXPECT_EQ(stats(off).at("settings").at("clamp"), 0.0);
  EXPECT_EQ(stats(one).at("settings").at("clamp"), 1.0);
}

// The default scene's light (radiance 17, 12, 4) and the brightest of its paths exceed 1:
// with --clamp 1 no pixel does.
TEST(ClampCli, NoPixelExceedsTheLimit) {
  EXPECT_GT(max_pixel(render("bound_off", "")), 4.0f);
  EXPECT_LE(max_pixel(render("bound_on", " --clamp 1")), 1.0f + 1e-6f);
}

TEST(ClampCli, RefusesWhatIsNotAFiniteNumberAtLeastZero) {
  for (const char* v : {"-1", "-0.001", "nan", "inf", "1e39", "abc"}) {
    const std::string args = "render --res 8x8 --spp 1 --overwrite --out " + ::testing::TempDir() +
                             "/clamp_cli_refused --clamp " + v;
    multiray::testing::expect_input_error(run(args), args, "--clamp");
  }
}

TEST(ClampCli, RenderBenchAndViewListItUnderSampling) {
  for (const char* command : {"render", "bench", "view"}) {
    const Result r = run(std::string(command) + " --help-all");
    ASSERT_EQ(r.code, 0) << r.out;
    const size_t section = r.out.find("\nSampling:"), option = r.out.find("--clamp");
    ASSERT_NE(section, std::string::npos) << command;
    ASSERT_NE(option, std::string::npos) << command;
    EXPECT_GT(option, section) << command;
    EXPECT_LT(option, r.out.find("\n\n", section)) << command << ": --clamp is not in Sampling";
  }
}

}  // namespace clamp_cli_test
