// Volumes on the command line, as a user would run them: a raw file rendered with each
// adaptation mode, bad volumes, transfer functions, sequences and option mixes refused
// with one line and exit 2, and a bench that compares adaptation modes and writes the
// frame-time plot.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli_expect.h"

namespace volume_cli_test {

using Result = multiray::testing::CliResult;
using multiray::testing::temp_file;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

// A 24^3 uint8 raw volume: a ball of 200 in zeros.
std::string ball_raw() {
  std::string bytes;
  for (int z = 0; z < 24; ++z)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        const int dx = x - 12, dy = y - 12, dz = z - 12;
        bytes.push_back(char(dx * dx + dy * dy + dz * dz < 64 ? 200 : 0));
      }
  return temp_file("ball.raw", bytes);
}

void expect_input_error(const std::string& args, const std::string& word) {
  multiray::testing::expect_input_error(run(args), args, word);
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(VolumeCli, RendersARawVolumeInEveryAdaptationMode) {
  const std::string raw = ball_raw();
  for (const char* mode : {"none", "last-frame", "predict", "predict:q=0.9", "two-pass"}) {
    const std::string dir = ::testing::TempDir() + "/vol_" + mode;
    std::filesystem::remove_all(dir);
    const Result r =
        run("render " + raw + " --raw 24x24x24:uint8 --tf grey --res 40x30 --frames 3 " +
            "--target-ms 5 --adapt " + mode + " --devices cpu:threads=1,cpu:threads=1 " +
            "--out " + dir);
    ASSERT_EQ(r.code, 0) << mode << "\n" << r.out;
    const auto stats = read_json(dir + "/stats.json");
    ASSERT_EQ(stats["frames"].size(), 3u);
    for (const auto& f : stats["frames"]) EXPECT_GE(f["quality"]["step_scale"].get<double>(), 1.0);
    EXPECT_GT(std::filesystem::file_size(dir + "/frame_0002.png"), 100u);
  }
}

TEST(VolumeCli, BadVolumesAndOptionsAreOneLine) {
  const std::string raw = ball_raw();
  const std::string base = "render " + raw + " --raw 24x24x24:uint8 --res 8x8 --out " +
                           ::testing::TempDir() + "/vol_bad ";
  expect_input_error("render " + raw + " --raw 24x24x25:uint8 --res 8x8", "ball.raw");
  expect_input_error("render " + raw + " --raw 24x24:uint8 --res 8x8", "raw volume spec");
  expect_input_error(base + "--integrator path", "volume");
  expect_input_error(base + "--tf nosuchpreset", "nosuchpreset");
  expect_input_error(base + "--step 0", "--step");
  expect_input_error(base + "--adapt predict", "--target-ms");
  expect_input_error(base + "--target-ms 5 --adapt predict:q=1.5", "q must be");
  expect_input_error(base + "--adapt sometimes --target-ms 5", "--adapt");
  expect_input_error(base + "--adapt-space object --target-ms 5", "--adapt");
  expect_input_error(base + "--adapt none,predict --target-ms 5", "one mode");
  expect_input_error(base + "--sampling adaptive", "--sampling");
  expect_input_error(base + "--sequence " + temp_file("bad_seq.json", "{\"zoom\": 3}"), "zoom");
  expect_input_error(
      base + "--sequence " +
          temp_file("bad_seq2.json", "{\"transfer_functions\": [[0, \"nope.json\"]]}"),
      "nope.json");
  expect_input_error("render " +
                         temp_file("short.nhdr",
                                   "NRRD0004\ntype: uint8\ndimension: 3\n"
                                   "sizes: 4 4 4\nencoding: raw\n"
                                   "data file: short.raw\n") +
                         " --res 8x8",
                     "short");
  expect_input_error("render --integrator volume --res 8x8", "volume");
  // Volume options are checked on a mesh too (the built-in Cornell box): a mistyped value
  // is refused, not ignored.
  expect_input_error("render --res 8x8 --cost-model nonsense", "--cost-model");
  expect_input_error("render --res 8x8 --step 0", "--step");
  expect_input_error("render --res 8x8 --result-encoding bogus", "--result-encoding");
}

// A sequence that says how many frames it lasts renders all of them unless --frames says
// otherwise (issue 32: a 6-frame sequence rendered 1 frame without --frames 6).
TEST(VolumeCli, ASequenceSetsTheFrameCountUnlessFramesIsGiven) {
  const std::string raw = ball_raw();
  const std::string seq =
      temp_file("seq6.json", R"({"frames": 4, "orbit_degrees_per_frame": 10})");
  const std::string dir = ::testing::TempDir() + "/vol_seq_frames";
  for (const char* frames : {"", "--frames 2"}) {
    std::filesystem::remove_all(dir);
    const Result r = run("render " + raw + " --raw 24x24x24:uint8 --res 16x12 -q --sequence " +
                         seq + " " + frames + " -o " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(read_json(dir + "/stats.json")["frames"].size(), *frames ? 2u : 4u) << frames;
  }
}

TEST(VolumeCli, BenchComparesAdaptationModesOnASequence) {
  const std::string raw = ball_raw();
  const std::string seq =
      temp_file("seq.json",
                R"({"orbit_degrees_per_frame": 10, "zoom": [[0, 1.0], [4, 0.7]],
          "transfer_functions": [[0, "grey"], [3, "angio"]]})");
  const std::string report = ::testing::TempDir() + "/vol_report";
  const std::string json = ::testing::TempDir() + "/vol_bench.json";
  std::filesystem::remove_all(report);
  const Result r =
      run("bench " + raw + " --raw 24x24x24:uint8 --res 32x24 --frames 6 --warmup 1 " +
          "--ideal-frames 1 --sequence " + seq + " --target-ms 5 " +
          "--adapt none,predict --balancers static,bruder:steal=1 " +
          "--devices cpu:threads=1,cpu:threads=1 --report " + report + " --json " + json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("bruder:steal=1 adapt=predict"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("frame-time target 5.0 ms"));
  const auto doc = read_json(json);
  ASSERT_EQ(doc["runs"].size(), 4u);  // 2 balancers x 2 modes
  for (const auto& run : doc["runs"]) {
    EXPECT_TRUE(run.contains("targeting"));
    EXPECT_TRUE(run["image_matches_first_run"].get<bool>()) << run["lane"];
  }
  EXPECT_GT(std::filesystem::file_size(report + "/targeting.svg"), 500u);
}

TEST(VolumeCli, BenchComparesEveryLaneWithAFineReference) {
  // --reference-step 0.1: every lane, the full-quality one (step 0.5) included, is
  // compared with the frame rendered at step 0.1 (Bruder et al.'s Table 4), so the
  // full-quality lane has an error too. Also the paper's and our cost model and two-pass.
  const std::string raw = ball_raw();
  const std::string json = ::testing::TempDir() + "/vol_fine.json";
  for (const char* cm : {"paper", "ours:tf=0"}) {
    const Result r =
        run("bench " + raw + " --raw 24x24x24:uint8 --tf grey --res 32x24 --frames 4 " +
            "--warmup 1 --ideal-frames 1 --target-ms 5 --reference-step 0.1 --cost-model " + cm +
            " --adapt none,predict,two-pass,two-pass:probe=fixed --balancers bruder " +
            "--devices cpu:threads=1,cpu:threads=1 --json " + json);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto doc = read_json(json);
    EXPECT_THAT(doc["image_reference"].get<std::string>(), ::testing::HasSubstr("step 0.1"));
    ASSERT_EQ(doc["runs"].size(), 4u);
    EXPECT_THAT(doc["runs"][3]["lane"].get<std::string>(), ::testing::HasSubstr("probe=fixed"));
    for (const auto& run : doc["runs"]) {
      const double psnr = run["targeting"]["psnr_db_vs_full_quality"].get<double>();
      EXPECT_GT(psnr, 10) << run["lane"];
      EXPECT_LT(psnr, 200) << run["lane"];  // finite: the reference is finer than any lane
    }
  }
  expect_input_error("bench " + raw + " --raw 24x24x24:uint8 --cost-model krls", "--cost-model");
  expect_input_error("bench " + raw + " --raw 24x24x24:uint8 --reference-step 0.001",
                     "--reference-step");
}

}  // namespace volume_cli_test
