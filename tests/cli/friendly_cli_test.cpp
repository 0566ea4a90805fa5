// Friction a newcomer met (issue "A newcomer's first hour", item 6): a typo gets a
// suggestion, a mistyped preset the list of presets, a folder or a .raw file given as a
// scene says what to do, and the common shorthands exist (--threads N, -o).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli_expect.h"

namespace friendly_cli_test {

using multiray::testing::expect_input_error;
using multiray::testing::run_cli;
using multiray::testing::temp_file;

TEST(FriendlyCli, ATypoGetsTheNearestOption) {
  expect_input_error(run_cli(MULTIRAY_BIN, "render --sp 4"), "render --sp 4",
                     "did you mean --spp?");
  expect_input_error(run_cli(MULTIRAY_BIN, "render --bounce 3"), "--bounce",
                     "did you mean --bounces?");
  const auto far = run_cli(MULTIRAY_BIN, "render --zzzzzz 3");  // nothing near: no guess
  EXPECT_EQ(far.code, 2);
  EXPECT_THAT(far.out, ::testing::Not(::testing::HasSubstr("did you mean")));
}

TEST(FriendlyCli, AMistypedPresetListsThePresets) {
  const std::string raw = temp_file("friendly.raw", std::string(8 * 8 * 8, '\x40'));
  expect_input_error(run_cli(MULTIRAY_BIN, "render " + raw + " --raw 8x8x8:uint8 --tf bone"),
                     "--tf bone", "ct-bone");
}

TEST(FriendlyCli, AFolderOrARawFileAsASceneSaysWhatToDo) {
  const std::string raw = temp_file("friendly2.raw", std::string(64, '\0'));
  expect_input_error(run_cli(MULTIRAY_BIN, "render " + ::testing::TempDir()), "a folder",
                     "this is a folder");
  expect_input_error(run_cli(MULTIRAY_BIN, "render " + raw), ".raw", "--raw NXxNYxNZ:TYPE");
}

TEST(FriendlyCli, ThreadsAndOAreShorthands) {
  const std::string dir = ::testing::TempDir() + "/friendly_threads";
  std::filesystem::remove_all(dir);
  const auto r = run_cli(MULTIRAY_BIN, "render -q --res 8x8 --threads 2 -o " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(dir + "/stats.json");
  ASSERT_TRUE(in);
  const auto doc = nlohmann::json::parse(in);
  ASSERT_EQ(doc.at("devices").size(), 1u);
  EXPECT_THAT(doc.at("devices")[0].at("name").get<std::string>(),
              ::testing::HasSubstr("2 threads"));
  expect_input_error(run_cli(MULTIRAY_BIN, "render --threads 2 --devices cpu"), "both",
                     "excludes");
  expect_input_error(run_cli(MULTIRAY_BIN, "render --threads -1"), "--threads -1", "--threads");
}

// Issue 51, item 7: a mistyped command gets the nearest one, `help` works as git's does,
// and CUDA-style device names say how GPUs are reached.
TEST(FriendlyCli, AMistypedCommandGetsTheNearestOne) {
  expect_input_error(run_cli(MULTIRAY_BIN, "rendr"), "rendr", "did you mean render?");
  expect_input_error(run_cli(MULTIRAY_BIN, "bnech --frames 3"), "bnech", "did you mean bench?");
  const auto far = run_cli(MULTIRAY_BIN, "zzzzzzzz");
  EXPECT_EQ(far.code, 2);
  EXPECT_THAT(far.out, ::testing::HasSubstr("the commands: render"));
  EXPECT_THAT(far.out, ::testing::Not(::testing::HasSubstr("did you mean")));
}

TEST(FriendlyCli, HelpIsACommand) {
  const auto top = run_cli(MULTIRAY_BIN, "help");
  EXPECT_EQ(top.code, 0) << top.out;
  EXPECT_THAT(top.out, ::testing::HasSubstr("Examples:"));
  const auto render = run_cli(MULTIRAY_BIN, "help render");
  EXPECT_EQ(render.code, 0) << render.out;
  EXPECT_THAT(render.out, ::testing::HasSubstr("Usage: multiray render"));
  expect_input_error(run_cli(MULTIRAY_BIN, "help rendr"), "help rendr", "did you mean render?");
}

TEST(FriendlyCli, HelpIsShortAndHelpAllHasEveryOption) {
  const auto brief = run_cli(MULTIRAY_BIN, "render --help");
  EXPECT_EQ(brief.code, 0);
  EXPECT_LT(std::count(brief.out.begin(), brief.out.end(), '\n'), 70) << brief.out;
  EXPECT_THAT(brief.out, ::testing::HasSubstr("--spp"));
  EXPECT_THAT(brief.out, ::testing::Not(::testing::HasSubstr("--ground")));
  EXPECT_THAT(brief.out, ::testing::HasSubstr("multiray render --help-all"));
  const auto all = run_cli(MULTIRAY_BIN, "render --help-all");
  EXPECT_EQ(all.code, 0);
  EXPECT_THAT(all.out, ::testing::HasSubstr("--ground"));
  EXPECT_THAT(all.out, ::testing::HasSubstr("--spp"));
}

TEST(FriendlyCli, GpuDeviceNamesSayGpusAreReachedThroughOpenCl) {
  for (const char* d : {"gpu", "cuda:0", "optix"})
    expect_input_error(run_cli(MULTIRAY_BIN, std::string("render --devices ") + d), d,
                       "GPUs are reached through OpenCL");
}

}  // namespace friendly_cli_test
