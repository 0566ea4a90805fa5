// Hostile traces for `multiray simulate` (issue 53, "Nothing lost, nothing crashes, round
// three"): a trace without frames crashed it (SIGSEGV, rc 139; --validate: rc 4), and items
// that did not tile their frame were simulated as if they did. Each is now one line, rc 2,
// whichever mode reads the trace.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/run_cli.h"

namespace trace_input_cli_test {

namespace fs = std::filesystem;
using multiray::testing::run_cli;

// `text` written as a trace file in a fresh folder; its path.
std::string trace_file(const std::string& name, const std::string& text) {
  const std::string dir = ::testing::TempDir() + "/trace_input_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir + "/t.trace", std::ios::binary) << text;
  return dir + "/t.trace";
}

// `simulate TRACE MODE` refuses in one line naming `word`, exit code 2.
void expect_refused(const std::string& trace, const std::string& word) {
  for (const char* mode : {"", " --validate", " --calibrate", " --devices 2 --balancers queue"}) {
    const auto r = run_cli(MULTIRAY_BIN, "simulate " + trace + mode);
    EXPECT_EQ(r.code, 2) << mode << "\n" << r.out;
    EXPECT_THAT(r.out, ::testing::StartsWith("multiray: error: ")) << mode;
    EXPECT_THAT(r.out, ::testing::HasSubstr(word)) << mode << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << mode << "\n" << r.out;
  }
}

TEST(TraceInput, ATraceWithoutFramesIsRefused) {
  expect_refused(trace_file("header", "multiray-trace 1\nbalancer queue\ndevice 0 1 a\n"),
                 "has no frames");
  expect_refused(trace_file("cut", "multiray-trace 1\nbalancer queue\n"), "has no frames");
}

TEST(TraceInput, ItemsThatDoNotTileAFrameAreRefused) {
  const std::string head = "multiray-trace 1\nbalancer uniform\ndevice 0 1 a\ndevice 1 1 b\n";
  expect_refused(
      trace_file("twice", head + "frame 0 8 4 1\ntime 0 1 2 2\nitem 0 0 0 0 0 8 4 32 2 2\n"
                                 "time 1 1 2 2\nitem 1 1 0 0 0 8 4 32 2 2\n"),
      "is covered twice");
  expect_refused(
      trace_file("half", head + "frame 0 8 4 1\ntime 0 1 2 2\nitem 0 0 0 0 0 8 2 16 2 2\n"
                                "time 1 1 0 0\n"),
      "is not covered");
}

}  // namespace trace_input_cli_test
