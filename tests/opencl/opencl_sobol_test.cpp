// The path tracer's sample values on the OpenCL device are the CPU's, bit for bit:
// render/shared/sobol.h reverses bits by products in OpenCL C and by masked swaps in C++
// (clang turns the swaps into llvm.bitreverse, which Oclgrind cannot run), so the two
// sides no longer run the same text. A tiny program of the shared headers and one kernel
// computes values of many (pixel, sample, dimension) on device 0 (whichever implementation
// this run of the OpenCL tests is for, see CMakeLists.txt) and the host compares them.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "device/opencl/cl_program.h"
#include "opencl_helpers.h"
#include "opencl_sobol_source.h"
#include "render/shared/sobol.h"

namespace multiray {
namespace opencl_sobol_test {

constexpr const char* kKernel = R"(
__kernel void sobol_values(__global const uint* in, __global uint* out, uint n) {
  const uint i = (uint)get_global_id(0);
  if (i >= n) return;
  SampleStream s = sample_stream_for_path(in[4 * i], in[4 * i + 1], 3u, 1u,
                                          0x0123456789abcdefUL);
  s.dim = in[4 * i + 2];
  const float2 v = sample_2d(&s);
  const float u = sample_1d(&s);
  out[4 * i] = as_uint(v.x);
  out[4 * i + 1] = as_uint(v.y);
  out[4 * i + 2] = as_uint(u);
  out[4 * i + 3] = reverse_bits32(in[4 * i + 3]);
}
)";

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

TEST(OpenClSobol, SampleValuesAndBitReversalAreTheCpusBitForBit) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  // Inputs: pixel, sample, dimension, a word to reverse (every byte value in each byte
  // position, then pseudo-random words).
  std::vector<cl_uint> in;
  uint32_t x = 99;
  for (uint32_t k = 0; k < 4096; ++k) {
    x = x * 1664525u + 1013904223u;
    const uint32_t word = k < 1024 ? (k % 256) << (8 * (k / 256)) : x;
    in.insert(in.end(), {x % 100000u, k % 300u, k % 23u, word});
  }
  const cl_uint n = cl_uint(in.size() / 4);
  const cl::Device device = cl_util::all_devices().at(0);
  const cl::Context context(device);
  const cl::CommandQueue queue(context, device);
  const std::string source = std::string(kSobolSource) + kKernel;
  const cl::Program program =
      cl_util::build_program(context, device, source, "-cl-std=CL1.2").program;
  cl::Kernel kernel(program, "sobol_values");
  cl::Buffer in_buf(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * 4, in.data());
  cl::Buffer out_buf(context, CL_MEM_WRITE_ONLY, in.size() * 4);
  kernel.setArg(0, in_buf);
  kernel.setArg(1, out_buf);
  kernel.setArg(2, n);
  queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(n), cl::NullRange);
  std::vector<cl_uint> out(in.size());
  queue.enqueueReadBuffer(out_buf, CL_TRUE, 0, out.size() * 4, out.data());

  int wrong = 0;
  for (cl_uint i = 0; i < n && wrong < 5; ++i) {
    SampleStream s =
        sample_stream_for_path(in[4 * i], in[4 * i + 1], 3u, 1u, 0x0123456789abcdefull);
    s.dim = in[4 * i + 2];
    const Vec2 v = sample_2d(&s);
    const float u = sample_1d(&s);
    const uint32_t want[4] = {bits(v.x), bits(v.y), bits(u), reverse_bits32(in[4 * i + 3])};
    for (int c = 0; c < 4; ++c)
      if (out[4 * i + size_t(c)] != want[c]) {
        ADD_FAILURE() << "input " << i << " (pixel " << in[4 * i] << ", sample " << in[4 * i + 1]
                      << ", dim " << in[4 * i + 2] << ") value " << c << ": OpenCL "
                      << out[4 * i + size_t(c)] << ", CPU " << want[c];
        ++wrong;
      }
  }
}

}  // namespace opencl_sobol_test
}  // namespace multiray
