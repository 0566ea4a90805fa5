// What `render` writes where (issue 32, a newcomer's first hour): the README's examples
// run one after another without --out, `-o render.png` is a file and not a folder named
// render.png, `-o shot_####.png` numbers frames, and --exposure auto meters the picture.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/run_cli.h"

namespace output_names_cli_test {

namespace fs = std::filesystem;
using multiray::testing::run_cli;

std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/names_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// `multiray render ARGS` run from inside `dir`.
multiray::testing::CliResult render_in(const std::string& dir, const std::string& args) {
  return run_cli(MULTIRAY_BIN, "render --res 24x16 --spp 1 " + args, "cd '" + dir + "' &&");
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(OutputNames, RunsWithoutOutNeverStopOnAnEarlierRun) {
  const std::string dir = fresh_dir("default");
  for (int i = 0; i < 3; ++i) ASSERT_EQ(render_in(dir, "-q").code, 0);
  EXPECT_TRUE(fs::exists(dir + "/out/frame_0000.png"));
  EXPECT_TRUE(fs::exists(dir + "/out-2/frame_0000.png"));
  const auto r = render_in(dir, "");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("writing to out-4/"));
  // A folder named on the command line is still protected.
  const auto again = render_in(dir, "-q -o out");
  EXPECT_EQ(again.code, 2);
  EXPECT_THAT(again.out, ::testing::HasSubstr("--overwrite"));
}

TEST(OutputNames, AnImageNameIsOneFileAndItsStatsBesideIt) {
  const std::string dir = fresh_dir("file");
  const auto r = render_in(dir, "-q -o render.png");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::is_regular_file(dir + "/render.png"));
  const auto stats = read_json(dir + "/render.stats.json");
  EXPECT_EQ(stats.at("settings").at("output"), "render.png");
  EXPECT_EQ(stats.at("frames").size(), 1u);
  // Again: the one file the user named is replaced (as Cycles' -o and pbrt's --outfile
  // do), with or without --overwrite; only folders are protected.
  const auto again = render_in(dir, "-q -o render.png --seed 7");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(read_json(dir + "/render.stats.json").at("settings").at("seed"), 7);
  EXPECT_EQ(render_in(dir, "-q -o render.png --overwrite").code, 0);
  // Six frames into one file: refused before rendering, with the pattern to use.
  const auto six = render_in(dir, "-q -o six.png --frames 6");
  EXPECT_EQ(six.code, 2);
  EXPECT_THAT(six.out, ::testing::HasSubstr("six_####.png"));
  EXPECT_FALSE(fs::exists(dir + "/six.png"));
}

TEST(OutputNames, HashesNumberTheFramesAndExrNamesWriteLinearFiles) {
  const std::string dir = fresh_dir("pattern");
  const auto r = render_in(dir, "-q --frames 3 -o shots/shot_##.png");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"shot_00.png", "shot_01.png", "shot_02.png", "shot.stats.json"})
    EXPECT_TRUE(fs::is_regular_file(dir + "/shots/" + f)) << f;
  const auto exr = render_in(dir, "-q --frames 2 -o lin_####.exr");
  ASSERT_EQ(exr.code, 0) << exr.out;
  EXPECT_TRUE(fs::exists(dir + "/lin_0001.exr"));
  EXPECT_FALSE(fs::exists(dir + "/lin_0001.png"));
  // A pattern names its files too: they are replaced without --overwrite.
  EXPECT_EQ(render_in(dir, "-q --frames 1 -o shots/shot_##.png").code, 0);
  // --overwrite removes only this pattern's files: other files in the folder stay.
  std::ofstream(dir + "/shots/notes.txt") << "mine";
  ASSERT_EQ(render_in(dir, "-q --frames 1 -o shots/shot_##.png --overwrite").code, 0);
  EXPECT_TRUE(fs::exists(dir + "/shots/notes.txt"));
  EXPECT_FALSE(fs::exists(dir + "/shots/shot_02.png"));
}

// --exposure auto (the default) meters the first frame: a dim sky is brought up to middle
// grey, and the metered stops are recorded; a number is used as given.
TEST(OutputNames, AutoExposureMetersAndRecordsTheStops) {
  const std::string dir = fresh_dir("exposure");
  std::ofstream(dir + "/tri.obj") << "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nf 1 2 3\n";
  const auto r = render_in(dir, "tri.obj --env 0.01 -o auto.png");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("metered on frame 0"));
  const auto a = read_json(dir + "/auto.stats.json").at("settings");
  EXPECT_EQ(a.at("exposure"), "auto");
  EXPECT_GT(a.at("exposure_ev").get<double>(), 3.0);  // the sky alone: log2(0.18 / 0.01)
  ASSERT_EQ(render_in(dir, "tri.obj --env 0.01 -q --exposure -1.5 -o fixed.png").code, 0);
  const auto f = read_json(dir + "/fixed.stats.json").at("settings");
  EXPECT_EQ(f.at("exposure"), "fixed");
  EXPECT_EQ(f.at("exposure_ev"), -1.5);
}

// Issue 51: --overlay writes the picture of the split beside the image, the run ends with
// the balance summary, and the picture counts as the run's output (a second run into the
// folder is refused, --overwrite removes it).
TEST(OutputNames, TheOverlayAndTheBalanceSummary) {
  const std::string dir = fresh_dir("overlay");
  const auto r =
      render_in(dir, "--devices cpu:threads=1,cpu:threads=1:speed=0.5 --overlay -o out");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::is_regular_file(dir + "/out/frame_0000_split.png"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("balance over 1 frame:"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("cpu:threads=1:speed=0.5"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("% of the samples"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("the split: out/frame_0000_split.png"));
  fs::remove(dir + "/out/frame_0000.png");
  fs::remove(dir + "/out/stats.json");
  EXPECT_EQ(render_in(dir, "-q -o out").code, 2);  // the overlay alone is an earlier output
  const auto one = render_in(dir, "--devices cpu:threads=1 -o one.png");
  ASSERT_EQ(one.code, 0) << one.out;
  EXPECT_THAT(one.out, ::testing::HasSubstr("one device (cpu:threads=1) rendered everything"));
}

}  // namespace output_names_cli_test
