// Outputs under hostile conditions, round two (issue "Nothing lost, nothing crashes, round
// two"): output paths that are not files, two runs into one folder at once, names that are
// not UTF-8, a reader that has gone away, a trace that cannot be written, a read-only
// folder, and memory that must not grow with the number of frames. Each case failed
// (replaced /dev/null, interleaved frames, exit 4, SIGPIPE, lost stats.json, ...) before.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_cli.h"

namespace outputs_cli_test {

namespace fs = std::filesystem;
using multiray::testing::run_cli;

std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/outputs_" + name;
  fs::remove_all(dir);
  return dir;
}

void expect_refused(const multiray::testing::CliResult& r, const std::string& word) {
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, ::testing::StartsWith("multiray: error: "));
  EXPECT_THAT(r.out, ::testing::HasSubstr(word));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// Starts multiray with `args` (stdout and stderr to /dev/null unless `out_fd` >= 0) and
// returns its pid.
pid_t spawn(const std::vector<std::string>& args, int out_fd = -1) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  if (out_fd >= 0) {
    dup2(out_fd, STDOUT_FILENO);
    dup2(out_fd, STDERR_FILENO);
  } else {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
  }
  std::vector<char*> argv{const_cast<char*>(MULTIRAY_BIN)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  execv(MULTIRAY_BIN, argv.data());
  _exit(127);
}

// Waits (at most 60 s) until `path` exists.
bool wait_for(const std::string& path) {
  for (int i = 0; i < 600 && !fs::exists(path); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  return fs::exists(path);
}

// The character device is a private null device made in the test's folder, never the
// system's /dev/null: if this check ever broke, the code under test would replace it.
TEST(Outputs, PathsThatAreNotRegularFilesAreRefusedAndLeftAlone) {
  const std::string dir = fresh_dir("special");
  fs::create_directories(dir);
  const std::string fifo = dir + "/fifo", device = dir + "/null";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
  const bool have_device = mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0;
  // Each refused before anything renders (a FIFO would otherwise block or be replaced).
  if (have_device)
    expect_refused(
        run_cli(MULTIRAY_BIN, "render -q --res 8x8 --trace " + device + " --out " + dir + "/a"),
        "character device");
  expect_refused(
      run_cli(MULTIRAY_BIN, "render -q --res 8x8 --trace " + fifo + " --out " + dir + "/b"),
      "FIFO");
  expect_refused(run_cli(MULTIRAY_BIN, "bench --res 8x8 --frames 2 --json " + fifo), "FIFO");
  expect_refused(
      run_cli(MULTIRAY_BIN, "render -q --res 8x8 --trace " + dir + " --out " + dir + "/c"),
      "folder");
  if (have_device) {
    EXPECT_TRUE(fs::is_character_file(device));
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_FALSE(fs::exists(dir + "/a/stats.json"));
}

TEST(Outputs, ASecondRunIntoAFolderInUseIsRefused) {
  const std::string dir = fresh_dir("busy");
  const pid_t first =
      spawn({"render", "-q", "--res", "32x18", "--spp", "2", "--frames", "100000", "--out", dir});
  ASSERT_GT(first, 0);
  ASSERT_TRUE(wait_for(dir + "/frame_0001.png"));
  const auto second = run_cli(MULTIRAY_BIN, "render -q --res 8x8 --overwrite --out " + dir);
  kill(first, SIGINT);
  int status = 0;
  waitpid(first, &status, 0);
  expect_refused(second, "in use by another multiray run");
  // The first run's folder is its own: every frame in stats.json is its image, and none is
  // the second run's (8x8 would make a far smaller PNG and another hash).
  std::ifstream in(dir + "/stats.json");
  ASSERT_TRUE(in);
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("settings").at("resolution"), nlohmann::json::array({32, 18}));
  size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(dir)) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, doc.at("frames").size());
}

TEST(Outputs, NamesThatAreNotUtf8RenderAndAreRecordedEscaped) {
  const std::string dir = fresh_dir("bytes");
  fs::create_directories(dir);
  const std::string scene = dir + "/tri_\xE9\xFF.obj";
  std::ofstream(scene) << "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";
  const std::string out = dir + "/out_\xE9\xFF", trace = dir + "/run_\xE9\xFF.trace";
  const auto r = run_cli(MULTIRAY_BIN, "render -q --res 16x16 --spp 1 '" + scene + "' --out '" +
                                           out + "' --trace '" + trace + "'");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(out + "/stats.json");
  ASSERT_TRUE(in);
  const auto doc = nlohmann::json::parse(in);  // valid JSON, hence valid UTF-8
  EXPECT_THAT(doc.at("settings").at("scene").get<std::string>(),
              ::testing::HasSubstr("tri_\\xE9\\xFF.obj"));
  EXPECT_TRUE(fs::exists(trace));
  EXPECT_TRUE(fs::exists(out + "/frame_0000.png"));
}

TEST(Outputs, AReaderThatHasGoneDoesNotEndTheRun) {
  // stdout and stderr are a pipe whose reading end is already closed: every write fails
  // (EPIPE, or SIGPIPE if not ignored), as with `multiray render ... | head -c1`.
  const std::string dir = fresh_dir("pipe");
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  close(fds[0]);
  const pid_t pid =
      spawn({"render", "--res", "16x16", "--spp", "1", "--frames", "3", "--out", dir}, fds[1]);
  close(fds[1]);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  std::ifstream in(dir + "/stats.json");
  ASSERT_TRUE(in);
  EXPECT_EQ(nlohmann::json::parse(in).at("frames").size(), 3u);
}

// A small file system of our own (root only; skipped elsewhere), unmounted on scope exit.
struct SmallDisk {
  std::string dir;
  bool mounted = false;
  SmallDisk(const std::string& name, const char* options, unsigned long flags = 0)
      : dir(fresh_dir(name)) {
    fs::create_directories(dir);
    mounted = mount("tmpfs", dir.c_str(), "tmpfs", flags, options) == 0;
  }
  ~SmallDisk() {
    if (mounted) umount(dir.c_str());
  }
};

TEST(Outputs, AFailedTraceKeepsStatsJsonAndSaysWhy) {
  SmallDisk disk("trace_disk", "size=8k");
  if (!disk.mounted) GTEST_SKIP() << "cannot mount a small tmpfs here (needs root)";
  const std::string out = fresh_dir("trace_out");
  // 4-px tiles: 16 items a frame, a trace far larger than the 8 KiB disk whatever the
  // default balancer (one device's `auto` renders a frame as one item).
  const auto r = run_cli(
      MULTIRAY_BIN, "render -q --res 16x16 --spp 1 --frames 40 --balancer queue:tile=4 --out " +
                        out + " --trace " + disk.dir + "/run.trace");
  expect_refused(r, "No space left on device");
  EXPECT_THAT(r.out, ::testing::HasSubstr("writing trace"));
  std::ifstream in(out + "/stats.json");
  ASSERT_TRUE(in) << "stats.json lost with the trace";
  EXPECT_EQ(nlohmann::json::parse(in).at("frames").size(), 40u);
  EXPECT_TRUE(fs::is_empty(disk.dir));  // no partial trace
}

TEST(Outputs, AReadOnlyFolderIsRefusedBeforeAnythingRenders) {
  SmallDisk disk("readonly", "size=64k", MS_RDONLY);
  if (!disk.mounted) GTEST_SKIP() << "cannot mount a read-only tmpfs here (needs root)";
  const auto r = run_cli(MULTIRAY_BIN, "render --res 16x16 --out " + disk.dir);
  expect_refused(r, "not writable");
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("frame ")));  // nothing rendered
}

// Peak memory of a render of `frames` tiny frames into `dir` (the child's maximum
// resident set, in KiB).
long peak_kib(int frames, const std::string& dir) {
  const long kib = multiray::testing::peak_rss_kb(
      MULTIRAY_BIN, {"render", "-q", "--res", "4x4", "--spp", "1", "--devices", "cpu:threads=1",
                     "--frames", std::to_string(frames), "--out", dir});
  EXPECT_GE(kib, 0) << "the render of " << frames << " frames did not exit 0";
  return kib;
}

TEST(Outputs, MemoryStaysFlatHoweverManyFrames) {
  // A frame's record is a few KB; kept in memory, 3000 frames would add over 10 MB.
  const std::string many = fresh_dir("many");
  const long few_kib = peak_kib(30, fresh_dir("few"));
  const long many_kib = peak_kib(3000, many);
  EXPECT_LT(many_kib - few_kib, 4 * 1024)
      << "30 frames: " << few_kib << " KiB, 3000: " << many_kib << " KiB";
  std::ifstream in(many + "/stats.json");
  ASSERT_TRUE(in);
  EXPECT_EQ(nlohmann::json::parse(in).at("frames").size(), 3000u);
}

TEST(Outputs, WhatBenchKeepsPerFrameIsInTheEstimate) {
  // bench keeps every lane's records (its summaries need them): 10^6 frames of eleven
  // balancers grew past any limit before; now it is refused before anything loads.
  expect_refused(run_cli(MULTIRAY_BIN, "bench --res 8x8 --frames 1000000 --max-memory 2G"),
                 "per-frame records");
}

}  // namespace outputs_cli_test
