// `multiray bench` run as a user would: a short run needs no --warmup, the JSON holds each
// frame's image hash (every view) and the comparison's verdict, the printed ideal frame
// time is the one efficiency uses, and a bad --balancers entry is named as such.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli_expect.h"

namespace bench_cli_test {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

constexpr const char* kSmall = "bench --res 24x16 --spp 1 --devices cpu:threads=1,cpu:threads=1 ";

// The bench's line "ideal frame time X ms" for `ms`.
std::string ideal_line(double ms) {
  char text[64];
  std::snprintf(text, sizeof text, "ideal frame time %.1f ms", ms);
  return text;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(BenchCli, TwoFramesRunWithoutChoosingAWarmup) {
  const std::string json = ::testing::TempDir() + "/bench_two.json";
  const Result r =
      run(std::string(kSmall) + "--frames 2 --balancers uniform,queue --json " + json);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json doc = read_json(json);
  for (const auto& lane : doc.at("runs")) {
    EXPECT_EQ(lane.at("frames").size(), 2u);
    EXPECT_EQ(lane.at("summary").at("from_frame"), 0);  // min(10, 2 / 4)
  }
  EXPECT_THAT(run("bench --help-all").out, ::testing::HasSubstr("min(10, frames / 4)"));
}

TEST(BenchCli, EveryViewOfEveryFrameIsHashedAndCompared) {
  const std::string json = ::testing::TempDir() + "/bench_views.json";
  const Result r = run(std::string(kSmall) +
                       "--views 2x1 --frames 3 --warmup 1 --balancers uniform,hybrid,dlb "
                       "--json " +
                       json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("every view of every frame bit-identical"));
  const nlohmann::json doc = read_json(json);
  EXPECT_EQ(doc.at("images_identical"), true);
  const auto& runs = doc.at("runs");
  ASSERT_EQ(runs.size(), 3u);
  for (const auto& lane : runs) {
    EXPECT_EQ(lane.at("image_matches_first_run"), true);
    ASSERT_EQ(lane.at("frames").size(), 3u);
    for (size_t f = 0; f < 3; ++f)
      EXPECT_EQ(lane.at("frames")[f].at("image_hash"), runs[0].at("frames")[f].at("image_hash"))
          << lane.at("lane") << " frame " << f;
  }
  // The camera orbits: each frame's hash is its own.
  EXPECT_NE(runs[0].at("frames")[0].at("image_hash"), runs[0].at("frames")[2].at("image_hash"));
}

TEST(BenchCli, PrintedIdealIsTheOneEfficiencyUses) {
  const std::string json = ::testing::TempDir() + "/bench_ideal.json";
  const Result r =
      run(std::string(kSmall) +
          "--frames 8 --warmup 2 --ideal-frames 3 --balancers uniform,queue --json " + json);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json doc = read_json(json);
  const double ideal = doc.at("ideal_ms").get<double>();
  EXPECT_THAT(r.out, ::testing::HasSubstr(ideal_line(ideal)));
  for (const auto& lane : doc.at("runs")) {
    const auto& s = lane.at("summary");
    EXPECT_NEAR(s.at("ideal_ms").get<double>(), ideal, 1e-9 * ideal) << lane.at("lane");
    EXPECT_NEAR(s.at("efficiency").get<double>(), ideal / s.at("mean_frame_ms").get<double>(),
                1e-9)
        << lane.at("lane");
  }
}

// --repeats K: K blocks, each lane's frame time and efficiency as a median inside its 95%
// interval, the best lane's ratio absent and every other lane's present, a verdict line
// that the JSON repeats; the per-frame JSON is block 1's (frames, not frames x K).
TEST(BenchCli, RepeatsGiveIntervalsAndAVerdict) {
  const std::string json = ::testing::TempDir() + "/bench_repeats.json";
  const Result r =
      run(std::string(kSmall) +
          "--frames 6 --warmup 1 --repeats 3 --balancers uniform,queue --json " + json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("3 repeat blocks"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("verdict: "));
  const nlohmann::json doc = read_json(json);
  const auto& rep = doc.at("repeats");
  EXPECT_EQ(rep.at("blocks"), 3);
  ASSERT_EQ(rep.at("lanes").size(), 2u);
  int with_ratio = 0;
  for (const auto& lane : rep.at("lanes")) {
    const auto& t = lane.at("frame_ms");
    EXPECT_LE(t.at("lo").get<double>(), t.at("median").get<double>()) << lane;
    EXPECT_GE(t.at("hi").get<double>(), t.at("median").get<double>()) << lane;
    EXPECT_GT(t.at("lo").get<double>(), 0.0) << lane;
    with_ratio += !lane.at("ratio_to_best").is_null();
  }
  EXPECT_EQ(with_ratio, 1);
  EXPECT_THAT(r.out, ::testing::HasSubstr("verdict: " + rep.at("verdict").get<std::string>()));
  for (const auto& lane : doc.at("runs")) EXPECT_EQ(lane.at("frames").size(), 6u);
  for (const char* bad : {"0", "101", "x"}) {
    const std::string args =
        std::string(kSmall) + "--frames 2 --balancers uniform --repeats " + bad;
    const Result e = run(args);
    EXPECT_NE(e.code, 0) << args;
    EXPECT_THAT(e.out, ::testing::HasSubstr("--repeats")) << args;
  }
}

// Where the time goes: per balancer the parts add up to the frame time (which is the
// table's), efficiency is the ideal over it; the run is judged by the noise gate, with the
// probe's numbers in the JSON; with two devices Harada's deviation is said to equal the
// imbalance rather than shown as a second identical column.
TEST(BenchCli, BreakdownAddsUpAndTheRunIsJudged) {
  const std::string json = ::testing::TempDir() + "/bench_breakdown.json";
  const Result r =
      run(std::string(kSmall) +
          "--frames 6 --warmup 1 --repeats 2 --balancers uniform,queue --json " + json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("where the time goes"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("deviation, max |time - mean| / mean, equals the"));
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("recovery")));  // not perturbed
  const nlohmann::json doc = read_json(json);
  for (const auto& lane : doc.at("runs")) {
    const auto& s = lane.at("summary");
    const auto& b = s.at("breakdown");
    const double frame = b.at("frame_ms").get<double>();
    const double parts = b.at("ideal_ms").get<double>() + b.at("balance_loss_ms").get<double>() +
                         b.at("overhead_ms").get<double>() + b.at("stolen_ms").get<double>() +
                         b.at("host_ms").get<double>();
    EXPECT_NEAR(parts, frame, 1e-9 * frame) << lane.at("lane");
    EXPECT_NEAR(frame, s.at("mean_frame_ms").get<double>(), 1e-9 * frame) << lane.at("lane");
    EXPECT_NEAR(s.at("efficiency").get<double>(), b.at("ideal_ms").get<double>() / frame, 1e-12);
    EXPECT_GE(b.at("balance_loss_ms").get<double>(), 0);
    EXPECT_GT(b.at("engine_wall_ms").get<double>(), 0);
    EXPECT_EQ(b.at("stolen_measured"), true);  // single-threaded CPU devices
  }
  const auto& noise = doc.at("noise");
  EXPECT_TRUE(doc.at("trustworthy").is_boolean());
  EXPECT_EQ(doc.at("trustworthy"), noise.at("trustworthy"));
  for (const char* probe : {"contention_probe_before", "contention_probe_after"})
    EXPECT_GT(noise.at(probe).get<double>(), 0) << probe;
  EXPECT_EQ(noise.at("trustworthy").get<bool>(), noise.at("reason").get<std::string>().empty());
  for (const auto& lane : doc.at("repeats").at("lanes"))
    EXPECT_FALSE(lane.at("imbalance").is_null());
  const Result bad = run(std::string(kSmall) + "--frames 2 --balancers uniform --probe-ms -1");
  EXPECT_NE(bad.code, 0);
  EXPECT_THAT(bad.out, ::testing::HasSubstr("--probe-ms"));
}

// Recovery appears with --perturb only, per repeat lane with the number of blocks that
// recovered (its interval is over those).
TEST(BenchCli, RecoveryIsShownWhenPerturbed) {
  const std::string json = ::testing::TempDir() + "/bench_perturb.json";
  const Result r = run(std::string(kSmall) +
                       "--frames 6 --warmup 1 --repeats 2 --perturb 3:1:0.5 --probe-ms 0 "
                       "--balancers uniform,queue --json " +
                       json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("recovery: frames after --perturb"));
  const nlohmann::json doc = read_json(json);
  for (const auto& lane : doc.at("repeats").at("lanes")) {
    const int blocks = lane.at("recovered_blocks").get<int>();
    EXPECT_GE(blocks, 0) << lane;
    EXPECT_LE(blocks, 2) << lane;
    EXPECT_EQ(lane.at("recovery_frames").is_null(), blocks == 0) << lane;
  }
  EXPECT_TRUE(doc.at("noise").at("contention_probe_before").is_null());  // --probe-ms 0
}

// A frame count out of range is named as such, not as the --warmup range it implies.
TEST(BenchCli, BadFrameCountIsNamedAsSuch) {
  for (const char* frames : {"0", "-1", "1000001"}) {
    const std::string args = std::string(kSmall) + "--frames " + frames;
    multiray::testing::expect_input_error(run(args), args, "--frames must be in 1..1000000");
  }
}

TEST(BenchCli, BadBalancersEntryIsNamedAsSuch) {
  for (const std::string mapping : {"", "--mapping strips "}) {
    const std::string args = std::string(kSmall) + "--frames 2 --warmup 0 " + mapping +
                             "--balancers uniform,dlb:interval";
    const Result r = run(args);
    multiray::testing::expect_input_error(r, args, "--balancers: ");
    EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("--balancer:"))) << args;
  }
}

}  // namespace bench_cli_test
