// The hostile user of the issue "Nothing lost, nothing crashes": numbers that overflow
// after conversion, full disks, signals mid-run, a reused output folder, memory bombs.
// Each case failed (crash, hang, rc 0 with a wrong or lost output) before it was fixed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/png_bytes.h"
#include "support/run_cli.h"

namespace robustness_cli_test {

namespace fs = std::filesystem;
using multiray::testing::run_cli;

std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/robust_" + name;
  fs::remove_all(dir);
  return dir;
}

// One line on stderr naming `word`, exit code 2.
void expect_refused(const std::string& args, const std::string& word) {
  const auto r = run_cli(MULTIRAY_BIN, args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
  EXPECT_THAT(r.out, ::testing::StartsWith("multiray: error: ")) << args;
  EXPECT_THAT(r.out, ::testing::HasSubstr(word)) << args;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << args << "\n" << r.out;
}

TEST(Hostile, NumbersThatOverflowAfterConversionAreRefused) {
  const std::string out = " --res 8x8 --out " + fresh_dir("numbers");
  expect_refused("render --camera 3e38,0,3,-3e38,0,0,0,1,0,45" + out, "--camera");
  expect_refused("render --camera 1e39,0,3,0,0,0,0,1,0,45" + out, "--camera");
  expect_refused("render --camera 0,0,3,0,0,3,0,1,0,45" + out, "--camera");
  expect_refused("render --camera 0,0,3,0,0,0,0,0,0,45" + out, "--camera");
  expect_refused("render --env 1e39" + out, "--env");
  expect_refused("render --devices cpu:speed=1e-9" + out, "speed");
  expect_refused("render --devices cpu:speed=1e-300" + out, "speed");
  expect_refused("render --perturb 1e20:0:0.5" + out, "--perturb");
  expect_refused("render --seed -1" + out, "--seed");
  expect_refused("bench --probe-ms 0 --devices cpu,cpu --lane-order random", "--lane-order");
  expect_refused("render --camera-path orbit:1e-50" + out, "--camera-path");
  expect_refused("render --sampling foveated --gaze-path orbit:1e-50" + out, "--gaze-path");
}

TEST(Hostile, MemoryIsEstimatedBeforeItIsTaken) {
  const std::string out = " --out " + fresh_dir("memory");
  expect_refused("render --views 64x64 --res 512x512" + out, "needs about");
  expect_refused("render --res 512x512 --max-memory 1M" + out, "--max-memory");
  expect_refused("render --max-memory plenty" + out, "--max-memory");
}

TEST(Hostile, AnEarlierRunsOutputsAreRefusedOrReplacedAsAWhole) {
  const std::string dir = fresh_dir("reuse");
  ASSERT_EQ(run_cli(MULTIRAY_BIN, "render -q --res 8x8 --frames 3 --out " + dir).code, 0);
  expect_refused("render -q --res 8x8 --out " + dir, "--overwrite");
  ASSERT_EQ(run_cli(MULTIRAY_BIN, "render -q --res 8x8 --frames 1 --overwrite --out " + dir).code,
            0);
  EXPECT_TRUE(fs::exists(dir + "/frame_0000.png"));
  EXPECT_FALSE(fs::exists(dir + "/frame_0002.png"));  // no leftover of the first run
}

TEST(Hostile, AFullDiskIsOneLineAndLeavesNoPartialFile) {
  const std::string dir = fresh_dir("full");
  fs::create_directories(dir);
  if (mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=32k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): " << std::strerror(errno);
  const auto r = run_cli(MULTIRAY_BIN, "render -q --res 256x256 --frames 2 --out " + dir + "/o");
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir + "/o")) left.push_back(e.path().filename());
  umount(dir.c_str());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("No space left on device"));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_TRUE(left.empty()) << left.front();  // no truncated PNG, no temporary file
}

TEST(Hostile, AnOutputLinkedToDevFullIsReplacedWhole) {
  const std::string dir = fresh_dir("devfull");
  fs::create_directories(dir);
  fs::create_symlink("/dev/full", dir + "/frame_0000.png");
  const auto r = run_cli(MULTIRAY_BIN, "render -q --res 16x16 --overwrite --out " + dir);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(fs::is_symlink(dir + "/frame_0000.png"));
  EXPECT_GT(fs::file_size(dir + "/frame_0000.png"), 100u);
}

TEST(Hostile, SigintKeepsTheFramesDoneAndTheirStats) {
  const std::string dir = fresh_dir("sigint");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {  // the child: multiray, quiet, far more frames than it will get to
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execl(MULTIRAY_BIN, MULTIRAY_BIN, "render", "-q", "--res", "64x36", "--spp", "4", "--frames",
          "100000", "--out", dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Interrupt once a few frames are written (at most 60 s later).
  for (int i = 0; i < 600 && !fs::exists(dir + "/frame_0003.png"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGINT) << status;
  std::ifstream in(dir + "/stats.json");
  ASSERT_TRUE(in) << "stats.json missing";
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.value("interrupted_by", ""), "SIGINT");
  const size_t frames = doc.at("frames").size();
  EXPECT_GE(frames, 4u);
  EXPECT_LT(frames, 100000u);
  size_t pngs = 0, others = 0;
  for (const auto& e : fs::directory_iterator(dir))
    (e.path().extension() == ".png" ? pngs : others) += 1;
  EXPECT_EQ(pngs, frames);  // every frame in stats.json has its image, and no other
  EXPECT_EQ(others, 1u);    // stats.json; no temporary file left
}

// bench stops at SIGINT too (study/bench_run.cpp's run_block) and keeps what finished
// (issue 53, item 6): the frames every balancer finished, summarised and written to --json
// marked "partial", exit 130. Interrupted before any frame finished, it says so and writes
// nothing; the wait then doubles (the machine may be busy), so the test does not depend on
// the load.
TEST(Hostile, SigintKeepsWhatABenchFinished) {
  const std::string dir = fresh_dir("sigint-bench");
  fs::create_directories(dir);
  const std::string json = dir + "/bench.json", err = dir + "/stderr.txt";
  std::string text;
  for (int wait_ms = 1000; wait_ms <= 64000; wait_ms *= 2) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {  // far more frames than it will get to
      freopen("/dev/null", "w", stdout);
      freopen(err.c_str(), "w", stderr);
      execl(MULTIRAY_BIN, MULTIRAY_BIN, "bench", "--res", "32x18", "--spp", "1", "--frames",
            "100000", "--warmup", "0", "--devices", "cpu:threads=1,cpu:threads=1", "--balancers",
            "uniform,hybrid", "--repeats", "1", "--probe-ms", "0", "--json", json.c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGINT) << status;
    std::ifstream in(err);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("multiray: bench interrupted by SIGINT in block 1 of 1"),
              std::string::npos)
        << text;
    if (text.find("nothing to keep") == std::string::npos) break;
    EXPECT_FALSE(fs::exists(json));
  }
  std::ifstream in(json);
  ASSERT_TRUE(in) << text;
  const auto doc = nlohmann::json::parse(in);
  ASSERT_TRUE(doc.contains("partial")) << text;
  EXPECT_EQ(doc["partial"].value("interrupted_by", ""), "SIGINT");
  const int frames = doc["partial"].value("frames", 0);
  EXPECT_GE(frames, 1);
  EXPECT_LT(frames, 100000);
  ASSERT_EQ(doc.at("runs").size(), 2u);
  for (const auto& run : doc.at("runs")) EXPECT_EQ(run.at("frames").size(), size_t(frames));
  EXPECT_NE(text.find("multiray: partial: 1 block of 1"), std::string::npos) << text;
}

// Round two (issue 31), data and memory: decoded images and simulations are estimated
// before they take memory; raw volumes say what cannot be checked.

void write_text(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(DataAndMemory, DecodedImagesAreInTheMemoryEstimate) {
  const std::string dir = fresh_dir("images");
  fs::create_directories(dir);
  // 16 KB that stb_image would decode to 16000 x 16000 RGBA (1 GB, 2 GB at the peak).
  write_text(dir + "/big.png", multiray::test::png_claiming(16000, 16000));
  write_text(dir + "/t.mtl", "newmtl a\nmap_Kd big.png\n");
  write_text(dir + "/t.obj",
             "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl a\n"
             "f 1/1 2/1 3/1\n");
  const std::string out = " --res 8x8 --spp 1 --max-memory 1G --out " + dir + "/o";
  expect_refused("render " + dir + "/t.obj" + out, "t.obj: texture 'big.png' (16000 x 16000");
  expect_refused("render " + dir + "/t.obj" + out, "GB of decoded images), more than the 1.1 GB");
  // An environment map too (a Radiance header claiming as much).
  write_text(dir + "/sky.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16000 +X 16000\n" +
                                   std::string(64, '\x01'));
  expect_refused("render --env " + dir + "/sky.hdr" + out,
                 "sky.hdr: environment map (16000 x 16000 pixels): this run needs about");
}

// One frame of two devices, 8x4 pixels: the smallest trace simulate replays.
const char* const kTwoDeviceTrace =
    "multiray-trace 1\nbalancer uniform\ndevice 0 1 a\ndevice 1 0.5 b\n"
    "frame 0 8 4 1\ntime 0 1 2.5 2.5\nitem 0 0 0 0 0 8 2 16 2.5 2.5\n"
    "time 1 1 2.5 2.5\nitem 1 1 0 0 2 8 4 16 2.5 2.5\n";

TEST(DataAndMemory, SimulateIsEstimatedBeforeItRuns) {
  const std::string dir = fresh_dir("simulate");
  fs::create_directories(dir);
  write_text(dir + "/t.trace", kTwoDeviceTrace);
  expect_refused("simulate " + dir + "/t.trace --devices 4096 --frames 1000000 --max-memory 1M",
                 "this run needs about");
  expect_refused("simulate " + dir + "/t.trace --max-memory lots", "--max-memory");
}

TEST(DataAndMemory, SimulateKeepsOneFrameAtATime) {
  // Issue 31: every simulated frame was kept until the end (4096 devices x 1000 frames of
  // this trace: 400 MB; 10^6 frames grew past 12 GB). Frame by frame it stays small.
  const std::string dir = fresh_dir("simulate_rss");
  fs::create_directories(dir);
  write_text(dir + "/t.trace", kTwoDeviceTrace);
  const long kb = multiray::testing::peak_rss_kb(
      MULTIRAY_BIN, {"simulate", dir + "/t.trace", "--devices", "4096", "--frames", "1000",
                     "--balancers", "uniform"});
  ASSERT_GT(kb, 0) << "simulate failed";
  EXPECT_LT(kb, 150 * 1024) << "peak " << kb / 1024 << " MB";
}

TEST(DataAndMemory, RawVolumesSayWhatCannotBeChecked) {
  const std::string dir = fresh_dir("raw");
  fs::create_directories(dir);
  // 2x2x2 int16 by its name, 16 bytes: --raw 4x2x2:uint8 reads the same bytes otherwise.
  write_text(dir + "/cube_2x2x2_int16.raw", std::string(16, '\x01'));
  write_text(dir + "/cube.raw", std::string(16, '\x01'));
  const std::string out = " --raw 4x2x2:uint8 --res 8x8 --out " + dir + "/o --overwrite";
  auto r = run_cli(MULTIRAY_BIN, "render " + dir + "/cube_2x2x2_int16.raw" + out);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("warning: " + dir +
                                          "/cube_2x2x2_int16.raw: its name "
                                          "says 2x2x2 int16, but --raw reads it as 4x2x2 uint8"));
  r = run_cli(MULTIRAY_BIN, "render " + dir + "/cube.raw" + out);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr("note: 'cube.raw' is read as --raw 4x2x2:uint8 says"));
  // A name that agrees gives neither.
  write_text(dir + "/cube_4x2x2_uint8.raw", std::string(16, '\x01'));
  r = run_cli(MULTIRAY_BIN, "render " + dir + "/cube_4x2x2_uint8.raw" + out);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("--raw reads")));
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("cannot confirm")));
}

}  // namespace robustness_cli_test
