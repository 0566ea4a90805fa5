// The kernels as standard OpenCL C 1.2, checked by a compiler that is not the one running
// them: PoCL accepts things vendor drivers (NVIDIA, AMD, Intel) refuse, and we cannot run
// those here. clang's OpenCL front end (clang-15, which the test dependencies install)
// parses each embedded program for a generic SPIR device without the optional doubles
// (cl_khr_fp64, which some GPUs lack), with the build options the device uses, and every
// warning is an error. Needs no OpenCL device; skips with a message without clang-15.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <unistd.h>

#include "device/opencl/kernel_source.h"
#include "device/opencl/volume_kernel_source.h"

namespace opencl_strict_test {

bool have_clang() { return std::system("command -v clang-15 > /dev/null 2>&1") == 0; }

// clang-15's verdict on `source` built with `options` (besides the device's own): its
// exit code, and what it printed in `out`.
int strict_check(const char* source, const std::string& options, std::string& out) {
  const std::string dir = ::testing::TempDir() + "/opencl_strict_" + std::to_string(getpid());
  std::system(("mkdir -p '" + dir + "'").c_str());
  const std::string file = dir + "/program.cl", log = dir + "/clang.log";
  std::ofstream(file) << source;
  const std::string cmd =
      "clang-15 -x cl -cl-std=CL1.2 -target spir64 -Xclang -cl-ext=-cl_khr_fp64 "
      "-Xclang -finclude-default-header -fsyntax-only -Wall -Werror -DMR_GROUP_ITEMS=64 "
      "-DMR_LAUNCH_ITEMS=4096 " +
      options + " '" + file + "' > '" + log + "' 2>&1";
  const int code = std::system(cmd.c_str());
  std::ifstream in(log);
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return code;
}

TEST(OpenClStrict, EveryProgramIsStandardOpenClC12) {
  if (!have_clang()) GTEST_SKIP() << "clang-15 not found (the test dependencies install it)";
  const struct {
    const char* name;
    const char* source;
    const char* options;
  } programs[] = {{"path tracer", kPathTracerSource, ""},
                  {"path tracer, compact scene", kPathTracerSource, "-DMR_COMPACT=1"},
                  {"volume raycaster", kVolumeSource, ""}};
  for (const auto& p : programs) {
    std::string out;
    EXPECT_EQ(strict_check(p.source, p.options, out), 0) << p.name << ":\n" << out;
  }
}

// The check can fail: an undeclared function, and doubles without their extension, are
// refused.
TEST(OpenClStrict, TheCheckRefusesWhatAVendorCompilerWould) {
  if (!have_clang()) GTEST_SKIP() << "clang-15 not found (the test dependencies install it)";
  std::string out;
  EXPECT_NE(
      strict_check("__kernel void k(__global float* a) { a[0] = undeclared(a[1]); }", "", out), 0);
  EXPECT_NE(strict_check("__kernel void k(__global double* a) { a[0] = 1.0; }", "", out), 0)
      << "doubles need cl_khr_fp64, which not every device has\n"
      << out;
}

}  // namespace opencl_strict_test
