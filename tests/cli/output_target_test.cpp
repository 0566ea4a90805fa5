// -o/--out's forms (app/output_target.h): a folder, one file, a #### pattern.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/output_target.h"
#include "core/error.h"

namespace output_target_test {

using multiray::InputError;
using multiray::app::first_free_folder;
using multiray::app::OutputTarget;
using multiray::app::parse_output_target;

TEST(OutputTarget, AFolderHoldsFrameFilesAndStatsJson) {
  const OutputTarget t = parse_output_target("renders/out", 3, true);
  EXPECT_FALSE(t.pattern);
  EXPECT_EQ(t.image_base(12), "renders/out/frame_0012");
  EXPECT_EQ(t.image_base(0, "_view03"), "renders/out/frame_0000_view03");
  EXPECT_EQ(t.stats_path(), "renders/out/stats.json");
  EXPECT_TRUE(t.png && t.exr);
  EXPECT_TRUE(t.owns("frame_0003.png") && t.owns("stats.json"));
  EXPECT_FALSE(t.owns("notes.txt"));
}

TEST(OutputTarget, OneFileForOneFrame) {
  const OutputTarget t = parse_output_target("render.png", 1, false);
  EXPECT_TRUE(t.pattern);
  EXPECT_EQ(t.image_base(0), "./render");
  EXPECT_EQ(t.stats_path(), "./render.stats.json");
  EXPECT_TRUE(t.png && !t.exr);
  EXPECT_TRUE(t.owns("render.png") && t.owns("render_quilt.png") && t.owns("render_view02.png"));
  // --aov's layers beside the PNG (of a view too).
  EXPECT_TRUE(t.owns("render_aov.exr") && t.owns("render_view02_aov.exr"));
  EXPECT_FALSE(t.owns("render2.png") || t.owns("render.jpg") || t.owns("stats.json"));
  EXPECT_FALSE(t.owns("render_aov.png.txt") || t.owns("render2_aov.exr"));
  // Several frames cannot go to one file: the error shows the pattern to use.
  try {
    parse_output_target("shots/render.png", 6, false);
    FAIL() << "accepted one file for six frames";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("render_####.png"), std::string::npos) << e.what();
  }
}

TEST(OutputTarget, HashesAreTheFrameNumber) {
  const OutputTarget t = parse_output_target("shots/shot_###_beauty.EXR", 20, false);
  EXPECT_EQ(t.image_base(7), "shots/shot_007_beauty");
  EXPECT_EQ(t.image_base(1234), "shots/shot_1234_beauty");  // wider when it must be
  EXPECT_EQ(t.stats, "shot_beauty.stats.json");
  EXPECT_TRUE(t.exr && !t.png);  // .exr: linear files only
  EXPECT_TRUE(t.owns("shot_007_beauty.exr") && t.owns("shot_12345_beauty_view00.png"));
  EXPECT_FALSE(t.owns("shot__beauty.exr") || t.owns("shot_0x7_beauty.exr"));
  EXPECT_EQ(parse_output_target("f####.png", 2, false).image_base(1), "./f0001");
}

TEST(OutputTarget, ContradictionsAreRefused) {
  EXPECT_THROW(parse_output_target("a_##_b_##.png", 2, false), InputError);
  EXPECT_THROW(parse_output_target("a_##.exr", 2, true), InputError);  // --exr and .exr
}

// Without -o: out/ while it is free, then out-2/, out-3/, ...
TEST(OutputTarget, TheDefaultFolderIsNeverOneWithAnEarlierRun) {
  namespace fs = std::filesystem;
  const std::string base = ::testing::TempDir() + "/output_target_out";
  for (const char* d : {"", "-2", "-3"}) fs::remove_all(base + d);
  EXPECT_EQ(first_free_folder(base), base);
  fs::create_directories(base);
  std::ofstream(base + "/notes.txt") << "mine";  // not an output: still free
  EXPECT_EQ(first_free_folder(base), base);
  std::ofstream(base + "/stats.json") << "{}";
  EXPECT_EQ(first_free_folder(base), base + "-2");
  fs::create_directories(base + "-2");
  std::ofstream(base + "-2/frame_0000.png") << "x";
  EXPECT_EQ(first_free_folder(base), base + "-3");
}

}  // namespace output_target_test
