#include "device/opencl/opencl_denoise.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
#include "device/opencl/cl_runtime.h"
#include "device/opencl/denoise_kernel_source.h"

namespace multiray {

namespace {
// kernels/denoise.cl's passes and argument count.
enum DenoisePass : cl_int { kDemodulate = 0, kVariance = 1, kAtrous = 2, kRemodulate = 3 };
constexpr cl_uint kDenoiseArgs = 19;
}  // namespace

struct OpenClDenoiser::Impl {
  // Every launch has tile x tile work-items (one global size for every launch of the
  // program, see ClRuntime::build_kernel).
  Impl(const cl::Device& device, int index, int work_group, int tile)
      : rt(device, index, tile, work_group),
        built(rt.build_kernel(kDenoiseSource, "denoise_pass", kDenoiseArgs, "")) {}

  cl::Buffer scratch(size_t floats) const {
    return cl::Buffer(rt.context, CL_MEM_READ_WRITE, std::max<size_t>(1, floats) * sizeof(float));
  }

  // Enqueues `pass` over every pixel of a width x height frame, in launches of
  // built.launch_items work-items. Arguments 10 and up are set by the caller.
  void run(cl_int pass, int width, int height, int step) {
    cl::Kernel& k = built.kernel;
    k.setArg(0, pass);
    k.setArg(2, cl_int(width));
    k.setArg(3, cl_int(height));
    k.setArg(4, cl_int(step));
    const size_t pixels = size_t(width) * size_t(height);
    for (size_t offset = 0; offset < pixels; offset += built.launch_items) {
      k.setArg(1, cl_int(offset));
      rt.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(built.launch_items),
                                    cl::NDRange(built.local));
    }
  }

  // Binds the buffers a pass reads and writes.
  void bind(const cl::Buffer& color_in, const cl::Buffer& variance_in, const cl::Buffer& color_out,
            const cl::Buffer& variance_out) {
    built.kernel.setArg(15, color_in);
    built.kernel.setArg(16, variance_in);
    built.kernel.setArg(17, color_out);
    built.kernel.setArg(18, variance_out);
  }

  void atrous(const DenoiseInput& in, float* out_rgb, const DenoiseParams& p);

  ClRuntime rt;
  ClBuiltKernel built;
};

void OpenClDenoiser::Impl::atrous(const DenoiseInput& in, float* out_rgb, const DenoiseParams& p) {
  const size_t n = size_t(in.width) * size_t(in.height);
  const cl::Buffer beauty = rt.upload(in.beauty, 3 * n * sizeof(float), "the beauty");
  const cl::Buffer albedo = rt.upload(in.albedo, 3 * n * sizeof(float), "the albedo");
  const cl::Buffer normal = rt.upload(in.normal, 3 * n * sizeof(float), "the normals");
  const cl::Buffer depth = rt.upload(in.depth, n * sizeof(float), "the depth");
  const cl::Buffer variance =
      in.variance ? rt.upload(in.variance, n * sizeof(float), "the variance") : scratch(1);
  // Two colours and two variances, ping-pong: each pass reads one and writes the other.
  cl::Buffer color[2] = {scratch(3 * n), scratch(3 * n)};
  cl::Buffer var[2] = {scratch(n), scratch(n)};
  cl::Kernel& k = built.kernel;
  k.setArg(5, cl_int(in.variance != nullptr));
  k.setArg(6, p.sigma_luminance);
  k.setArg(7, p.sigma_normal);
  k.setArg(8, p.sigma_depth);
  k.setArg(9, p.sigma_albedo);
  k.setArg(10, beauty);
  k.setArg(11, albedo);
  k.setArg(12, normal);
  k.setArg(13, depth);
  k.setArg(14, variance);
  bind(color[1], var[1], color[0], var[0]);
  run(kDemodulate, in.width, in.height, 0);
  if (!in.variance) {
    bind(color[0], var[1], color[1], var[0]);  // writes var[0] only
    run(kVariance, in.width, in.height, 0);
  }
  int cur = 0;
  for (int it = 0; it < p.iterations; ++it, cur ^= 1) {
    bind(color[cur], var[cur], color[cur ^ 1], var[cur ^ 1]);
    run(kAtrous, in.width, in.height, 1 << it);
  }
  const cl::Buffer out = scratch(3 * n);
  bind(color[cur], var[cur], out, var[cur ^ 1]);  // writes `out` only
  run(kRemodulate, in.width, in.height, 0);
  rt.queue.enqueueReadBuffer(out, CL_TRUE, 0, 3 * n * sizeof(float), out_rgb);
}

OpenClDenoiser::OpenClDenoiser(int device_index, int work_group, int tile) {
  if (work_group < 1 || work_group > 4096 || tile < 1 || tile > 4096)
    throw InputError("opencl denoiser: work group and tile must be in 1..4096");
  const std::vector<cl::Device> all = cl_util::all_devices();
  if (device_index < 0 || size_t(device_index) >= all.size())
    throw InputError("opencl denoiser: there is no OpenCL device " + std::to_string(device_index) +
                     " (found " + std::to_string(all.size()) + "; see `multiray devices`)");
  try {
    impl_ = std::make_unique<Impl>(all[size_t(device_index)], device_index, work_group, tile);
  } catch (const cl::Error& e) {
    throw DeviceError("opencl denoiser on device " + std::to_string(device_index) +
                      ": setting up failed: " + cl_util::describe(e));
  }
}

OpenClDenoiser::~OpenClDenoiser() = default;

void OpenClDenoiser::atrous(const DenoiseInput& in, float* out_rgb, const DenoiseParams& params) {
  check_denoise_input(in, DenoiseMethod::atrous, nullptr, out_rgb);
  try {
    impl_->atrous(in, out_rgb, params);
  } catch (const cl::Error& e) {
    throw DeviceError("opencl denoiser on device " + std::to_string(impl_->rt.index) + ": " +
                      cl_util::describe(e));
  }
}

size_t OpenClDenoiser::work_group_size() const { return impl_->built.local; }
size_t OpenClDenoiser::launch_items() const { return impl_->built.launch_items; }

}  // namespace multiray
