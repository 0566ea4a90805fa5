// The kernels as standard OpenCL C 1.2, checked by a compiler that is not the one running
// them: PoCL accepts things vendor drivers (NVIDIA, AMD, Intel) refuse, and we cannot run
// those here. clang's OpenCL front end (clang-15, which the test dependencies install)
// parses each embedded program for a generic SPIR device without the optional doubles
// (cl_khr_fp64, which some GPUs lack), with the build options the device uses, and every
// warning is an error. And it compiles each to LLVM IR as an optimising driver would, to
// refuse intrinsics an IR interpreter (Oclgrind) cannot run. Needs no OpenCL device;
// skips with a message without clang-15.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <string>

#include <unistd.h>

#include "device/opencl/denoise_kernel_source.h"
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

// Every program the devices build, with the options that make its variants.
struct Program {
  const char* name;
  const char* source;
  const char* options;
};
const Program kPrograms[] = {{"path tracer", kPathTracerSource, ""},
                             {"path tracer, compact scene", kPathTracerSource, "-DMR_COMPACT=1"},
                             {"volume raycaster", kVolumeSource, ""},
                             {"denoiser", kDenoiseSource, ""}};

TEST(OpenClStrict, EveryProgramIsStandardOpenClC12) {
  if (!have_clang()) GTEST_SKIP() << "clang-15 not found (the test dependencies install it)";
  for (const Program& p : kPrograms) {
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

// The intrinsics (llvm.*) clang-15 at -O3 calls in `source` built with `options`, less
// those Oclgrind 21.10 runs (the names its library knows: lifetime and debug markers,
// memcpy/memmove/memset, fmuladd, fabs, integer min/max, bswap) and the alias-scope
// markers that inlining a struct-returning function leaves (llvm.experimental.noalias.
// scope.decl: no effect on semantics, and made only by an LLVM that also consumes it; the
// shared integrator returns its records by value). Empty when clang fails
// (`out` says why). The vectorisers are off: they make vector intrinsics
// (llvm.vector.reduce.*) that every native backend lowers, and an interpreter such as
// Oclgrind compiles without them; the idioms that matter (bit reversal, rotations, bit
// counts) come from the scalar passes.
std::set<std::string> foreign_intrinsics(const char* source, const std::string& options,
                                         std::string& out) {
  const std::string dir = ::testing::TempDir() + "/opencl_ir_" + std::to_string(getpid());
  std::system(("mkdir -p '" + dir + "'").c_str());
  const std::string file = dir + "/program.cl", ir = dir + "/program.ll", log = dir + "/log";
  std::ofstream(file) << source;
  const std::string cmd =
      "clang-15 -x cl -cl-std=CL1.2 -target spir64 -Xclang -cl-ext=-cl_khr_fp64 "
      "-Xclang -finclude-default-header -O3 -fno-vectorize -fno-slp-vectorize -emit-llvm -S "
      "-DMR_GROUP_ITEMS=64 -DMR_LAUNCH_ITEMS=4096 " +
      options + " '" + file + "' -o '" + ir + "' > '" + log + "' 2>&1";
  std::set<std::string> found;
  if (std::system(cmd.c_str()) != 0) {
    std::ifstream in(log);
    out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    found.insert("(clang failed)");
    return found;
  }
  std::ifstream in(ir);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  static const std::regex call(R"(@(llvm\.[A-Za-z0-9_.]+))");
  static const std::regex known(
      R"(llvm\.(lifetime|dbg|memcpy|memmove|memset|fmuladd|fabs|smax|smin|umax|umin|bswap|experimental\.noalias\.scope)\..*)");
  for (std::sregex_iterator m(text.begin(), text.end(), call), end; m != end; ++m)
    if (!std::regex_match((*m)[1].str(), known)) found.insert((*m)[1].str());
  return found;
}

std::string joined(const std::set<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += " " + n;
  return s;
}

// Oclgrind refused the path tracer with "Undefined external function:
// llvm.bitreverse.i32": clang had recognised sobol.h's bit reversal. Every program must
// reach an LLVM-based driver without such idioms turned into intrinsics.
TEST(OpenClStrict, NoProgramCallsAnIntrinsicAnInterpreterLacks) {
  if (!have_clang()) GTEST_SKIP() << "clang-15 not found (the test dependencies install it)";
  for (const Program& p : kPrograms) {
    std::string out;
    EXPECT_EQ(joined(foreign_intrinsics(p.source, p.options, out)), "") << p.name << "\n" << out;
  }
}

// The check can fail: the masked swaps sobol.h keeps for C++ become llvm.bitreverse, and
// a rotation llvm.fshl.
TEST(OpenClStrict, TheIntrinsicCheckSeesABitReversalAndARotation) {
  if (!have_clang()) GTEST_SKIP() << "clang-15 not found (the test dependencies install it)";
  std::string out;
  const std::set<std::string> found = foreign_intrinsics(R"(
    uint rev(uint x) {
      x = (x << 16) | (x >> 16);
      x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
      x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
      x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
      return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    }
    __kernel void k(__global uint* a) { a[0] = rev(a[1]); a[2] = (a[3] << 7) | (a[3] >> 25); })",
                                                         "", out);
  EXPECT_EQ(joined(found), " llvm.bitreverse.i32 llvm.fshl.i32") << out;
}

}  // namespace opencl_strict_test
