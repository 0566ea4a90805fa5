// Every kernel under Oclgrind, an OpenCL device simulator that checks each memory access
// of each work-item: out-of-bounds and misaligned accesses, reads of uninitialised memory
// (--uninitialized), data races between work-items (--data-races) and misuse of the API
// (--check-api). Debian's oclgrind is a wrapper command that preloads its runtime, which
// replaces the OpenCL library of the process it starts: that process then sees one
// device, the simulator, as opencl:0. A tiny frame per kernel (8x8, 1 sample, one launch
// of 64 work-items): the simulator interprets every instruction.
//
// Two runs, because Oclgrind 21.10's --uninitialized crashes (SIGSEGV in its shadow
// memory pool) when a thread other than the process's main one writes a buffer, which
// multiray's device threads do: the multiray binary renders each kernel with
// --check-api --data-races, and this test program renders each kernel on its main thread
// (OpenClMainThread.*) with all three checks. Skips with a message without oclgrind.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/run_cli.h"

namespace multiray {
namespace opencl_oclgrind_test {

#ifdef MULTIRAY_BIN
namespace fs = std::filesystem;

bool have_oclgrind() { return std::system("command -v oclgrind > /dev/null 2>&1") == 0; }

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A 8^3 uint8 raw volume: a ramp with a ball.
std::string ball_raw() {
  const std::string path = ::testing::TempDir() + "/multiray_oclgrind_ball.raw";
  std::string bytes;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const int dx = x - 4, dy = y - 4, dz = z - 4;
        bytes.push_back(char(dx * dx + dy * dy + dz * dz < 8 ? 200 : 16 * x));
      }
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// Runs `command` under the simulator with `checks`; Oclgrind's reports go to `log`.
testing::CliResult under_oclgrind(const std::string& checks, const std::string& command,
                                  const std::string& log, const std::string& env = "") {
  return testing::run_cli("oclgrind " + checks + " --log '" + log + "' " + command, "", env, 600);
}

// Runs `command` on the simulator with `checks` and expects a clean run: exit 0 and
// nothing in Oclgrind's log.
void expect_clean(const std::string& name, const std::string& checks, const std::string& command,
                  const std::string& env = "") {
  const std::string log = ::testing::TempDir() + "/multiray_oclgrind.log";
  fs::remove(log);
  const testing::CliResult r = under_oclgrind(checks, command, log, env);
  EXPECT_EQ(r.code, 0) << name << ":\n" << r.out;
  const std::string reports = read(log);
  EXPECT_TRUE(reports.empty()) << name << ": Oclgrind reported (first lines):\n"
                               << reports.substr(0, 3000);
}

TEST(OpenClOclgrind, EveryKernelRunsCleanOnTheSimulator) {
  if (!have_oclgrind()) GTEST_SKIP() << "oclgrind not found (apt-get install oclgrind)";
  const std::string log = ::testing::TempDir() + "/multiray_oclgrind_devices.log";
  const testing::CliResult devices = under_oclgrind("", MULTIRAY_BIN " devices", log);
  ASSERT_NE(devices.out.find("Oclgrind"), std::string::npos) << "not the simulator:\n"
                                                             << devices.out;
  const std::string out = ::testing::TempDir() + "/multiray_oclgrind";
  const std::string render = MULTIRAY_BIN
                             " render --res 8x8 --spp 1 --frames 1 -q --overwrite "
                             "--out " +
                             out;
  const std::string checks = "--check-api --data-races";
  expect_clean("path", checks, render + " --devices opencl:0:tile=8");
  expect_clean("path, compact scene", checks, render + " --devices opencl:0:tile=8:compact=1");
  expect_clean("adaptive sampling", checks,
               render + " --sampling adaptive --edge-spp 2 --devices opencl:0:tile=8");
  expect_clean("reprojected sampling", checks,
               render + " --views 3x1 --sampling reproject --devices opencl:0:tile=8");
  expect_clean(
      "volume", checks,
      render + " " + ball_raw() + " --raw 8x8x8:uint8 --tf grey --devices opencl:0:tile=8");
  // The same kernels on this program's main thread, with --uninitialized too. Built
  // without optimisation: the checker stops at LLVM's `freeze` ("Unsupported instruction",
  // which clang's optimiser puts in the volume kernel's division), and unoptimised code is
  // closer to the source anyway. A fresh program cache, so the kernels are compiled with
  // that option instead of loaded from an optimised binary (cl_program.h).
  const std::string cache = ::testing::TempDir() + "/multiray_oclgrind_cache";
  fs::remove_all(cache);
  expect_clean("every kernel on the main thread",
               "--check-api --uninitialized --data-races --build-options -cl-opt-disable",
               fs::read_symlink("/proc/self/exe").string() +
                   " --gtest_filter=OpenClMainThread.* --gtest_brief=1",
               "XDG_CACHE_HOME='" + cache + "'");
  fs::remove_all(cache);
  fs::remove_all(out);
}
#endif

}  // namespace opencl_oclgrind_test
}  // namespace multiray
