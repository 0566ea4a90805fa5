#include "device/opencl/opencl_denoise.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "device/opencl/cl_runtime.h"
#include "device/opencl/denoise_kernel_source.h"
#include "render/path_tracer.h"
#include "render/shared/denoise.h"

namespace multiray {

namespace {
// kernels/denoise.cl's passes and argument count.
enum DenoisePass : cl_int { kPrepare = 0, kVariance = 1, kAtrous = 2, kRemodulate = 3 };
constexpr cl_uint kDenoiseArgs = 26, kTemporalArgs = 24;
// The device buffers, kept from frame to frame (reallocated when the size changes).
enum Slot {
  kBeauty,
  kAlbedo,
  kNormal,
  kDepth,
  kGivenVariance,
  kEmission,
  kColor0,
  kColor1,
  kVariance0,
  kVariance1,
  kLuminance0,
  kLuminance1,
  kGuides,
  kSlopes,
  kOut,
  kCameras,
  kPrevColor,
  kPrevMoments,
  kPrevHistory,
  kPrevDepth,
  kPrevNormal,
  kAccColor,
  kAccMoments,
  kAccHistory,
  kAccVariance,
  kAccLuminance,
  kSlots
};
}  // namespace

struct OpenClDenoiser::Impl {
  // Every launch has tile x tile work-items (one global size for every launch of the
  // program, see ClRuntime::build_kernel).
  Impl(const cl::Device& device, int index, int work_group, int tile)
      : rt(device, index, tile, work_group),
        built(rt.build_kernel(kDenoiseSource, "denoise_pass", kDenoiseArgs, "")),
        temporal(rt.build_kernel(kDenoiseSource, "denoise_temporal", kTemporalArgs, "")) {}

  // The buffer of `slot`, holding at least one and exactly max(1, floats) floats; kept
  // between calls, so a frame of the size of the last allocates nothing. (Buffers freed
  // while a kernel object still names them also upset Oclgrind's --uninitialized check.)
  const cl::Buffer& buffer(Slot slot, size_t floats) {
    floats = std::max<size_t>(1, floats);
    if (sizes[slot] != floats) {
      if (floats * sizeof(float) > rt.max_alloc)
        throw DeviceError(
            "OpenCL: the denoiser needs a " + std::to_string((floats * sizeof(float)) >> 20) +
            " MB buffer, the device allows " + std::to_string(rt.max_alloc >> 20) + " MB");
      buffers[slot] = cl::Buffer(rt.context, CL_MEM_READ_WRITE, floats * sizeof(float));
      sizes[slot] = floats;
    }
    return buffers[slot];
  }
  // The buffer of `slot` holding `floats` floats of `data` (written before the call returns).
  const cl::Buffer& upload(Slot slot, const void* data, size_t floats) {
    const cl::Buffer& b = buffer(slot, floats);
    if (floats > 0) rt.queue.enqueueWriteBuffer(b, CL_TRUE, 0, floats * sizeof(float), data);
    return b;
  }

  // Enqueues `k` over every pixel of a `pixels`-pixel frame, in launches of
  // k.launch_items work-items, setting argument `offset_arg` to each launch's first pixel.
  void launch(ClBuiltKernel& k, cl_uint offset_arg, size_t pixels) {
    for (size_t offset = 0; offset < pixels; offset += k.launch_items) {
      k.kernel.setArg(offset_arg, cl_int(offset));
      rt.queue.enqueueNDRangeKernel(k.kernel, cl::NullRange, cl::NDRange(k.launch_items),
                                    cl::NDRange(k.local));
    }
  }

  // Enqueues denoise_pass's `pass` over a width x height frame. Arguments 5 and up are
  // set by the caller.
  void run(cl_int pass, int width, int height, int step) {
    cl::Kernel& k = built.kernel;
    k.setArg(0, pass);
    k.setArg(2, cl_int(width));
    k.setArg(3, cl_int(height));
    k.setArg(4, cl_int(step));
    launch(built, 1, size_t(width) * size_t(height));
  }

  // Binds the buffers a pass reads and writes.
  void bind(const cl::Buffer& color_in, const cl::Buffer& luminance_in,
            const cl::Buffer& variance_in, const cl::Buffer& color_out,
            const cl::Buffer& luminance_out, const cl::Buffer& variance_out) {
    built.kernel.setArg(15, color_in);
    built.kernel.setArg(16, variance_in);
    built.kernel.setArg(17, color_out);
    built.kernel.setArg(18, variance_out);
    built.kernel.setArg(21, luminance_in);
    built.kernel.setArg(22, luminance_out);
  }

  void denoise(const DenoiseInput& in, DenoiseState* state, float* out_rgb,
               const DenoiseParams& p);
  // SVGF's temporal step: accumulates `color` (demodulated) with `variance` into `s`
  // and leaves the accumulated colour, its luminance and its variance in `color`,
  // `luminance` and `variance`.
  void accumulate(const DenoiseInput& in, const DenoiseParams& p, const cl::Buffer& depth,
                  const cl::Buffer& normal, cl::Buffer& color, cl::Buffer& luminance,
                  cl::Buffer& variance, DenoiseState& s);

  ClRuntime rt;
  ClBuiltKernel built, temporal;
  cl::Buffer buffers[kSlots];
  size_t sizes[kSlots] = {};
};

void OpenClDenoiser::Impl::denoise(const DenoiseInput& in, DenoiseState* state, float* out_rgb,
                                   const DenoiseParams& p) {
  const size_t n = size_t(in.width) * size_t(in.height);
  const cl::Buffer beauty = upload(kBeauty, in.beauty, 3 * n);
  const cl::Buffer albedo = upload(kAlbedo, in.albedo, 3 * n);
  const cl::Buffer normal = upload(kNormal, in.normal, 3 * n);
  const cl::Buffer depth = upload(kDepth, in.depth, n);
  const cl::Buffer variance =
      in.variance ? upload(kGivenVariance, in.variance, n) : buffer(kGivenVariance, 1);
  const cl::Buffer emission =
      in.emission ? upload(kEmission, in.emission, 3 * n) : buffer(kEmission, 1);
  // Two colours, luminances and variances, ping-pong: each pass reads one and writes the
  // other.
  cl::Buffer color[2] = {buffer(kColor0, 3 * n), buffer(kColor1, 3 * n)};
  cl::Buffer lum[2] = {buffer(kLuminance0, n), buffer(kLuminance1, n)};
  cl::Buffer var[2] = {buffer(kVariance0, n), buffer(kVariance1, n)};
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
  k.setArg(19, buffer(kGuides, MR_DENOISE_GUIDE_FLOATS * n));
  k.setArg(20, buffer(kSlopes, MR_DENOISE_SLOPE_FLOATS * n));
  k.setArg(23, cl_int(in.emission != nullptr));
  k.setArg(24, emission);
  k.setArg(25, cl_int(p.normal_turn ? 1 : 0));
  bind(color[1], lum[1], var[1], color[0], lum[0], var[0]);  // and the guides
  run(kPrepare, in.width, in.height, 0);
  // The variance to start from (denoise_start_variance): var[0] -> var[1], swapped in.
  bind(color[0], lum[0], var[0], color[1], lum[1], var[1]);  // writes var[1] only
  run(kVariance, in.width, in.height, 0);
  std::swap(var[0], var[1]);
  if (state) accumulate(in, p, depth, normal, color[0], lum[0], var[0], *state);
  int cur = 0;
  for (int it = 0; it < p.iterations; ++it, cur ^= 1) {
    bind(color[cur], lum[cur], var[cur], color[cur ^ 1], lum[cur ^ 1], var[cur ^ 1]);
    run(kAtrous, in.width, in.height, 1 << it);
    if (it == 0 && state && svgf_history_from_first_iteration(p))  // svgf's history
      rt.queue.enqueueReadBuffer(color[cur ^ 1], CL_FALSE, 0, 3 * n * sizeof(float),
                                 state->color.data());
  }
  const cl::Buffer out = buffer(kOut, 3 * n);
  bind(color[cur], lum[cur], var[cur], out, lum[cur ^ 1], var[cur ^ 1]);  // writes `out` only
  run(kRemodulate, in.width, in.height, 0);
  rt.queue.enqueueReadBuffer(out, CL_TRUE, 0, 3 * n * sizeof(float), out_rgb);
}

void OpenClDenoiser::Impl::accumulate(const DenoiseInput& in, const DenoiseParams& p,
                                      const cl::Buffer& depth, const cl::Buffer& normal,
                                      cl::Buffer& color, cl::Buffer& luminance,
                                      cl::Buffer& variance, DenoiseState& s) {
  const size_t n = size_t(in.width) * size_t(in.height);
  if (s.width != in.width || s.height != in.height) s.reset();
  CameraBlock cams[2]{};
  if (in.camera) cams[0] = PinholeCamera(*in.camera, in.width, in.height).block();
  cams[1] = s.camera;
  const bool has_previous = !s.empty() && in.camera;
  const auto previous = [&](Slot slot, const std::vector<float>& v) {
    return has_previous ? upload(slot, v.data(), v.size()) : buffer(slot, 1);
  };
  const cl::Buffer cameras = upload(kCameras, cams, 2 * sizeof(CameraBlock) / sizeof(float));
  const cl::Buffer prev[5] = {previous(kPrevColor, s.color), previous(kPrevMoments, s.moments),
                              previous(kPrevHistory, s.history), previous(kPrevDepth, s.depth),
                              previous(kPrevNormal, s.normal)};
  const cl::Buffer acc = buffer(kAccColor, 3 * n), moments = buffer(kAccMoments, 2 * n);
  const cl::Buffer history = buffer(kAccHistory, 2 * n), acc_variance = buffer(kAccVariance, n);
  const cl::Buffer acc_luminance = buffer(kAccLuminance, n);
  cl::Kernel& k = temporal.kernel;
  const cl_float scalars[4] = {p.alpha, p.moments_alpha, p.depth_tolerance, p.normal_tolerance};
  k.setArg(1, cl_int(in.width));
  k.setArg(2, cl_int(in.height));
  k.setArg(3, cl_int(has_previous));
  k.setArg(4, cl_int(in.variance != nullptr));
  for (cl_uint a = 0; a < 4; ++a) k.setArg(5 + a, scalars[a]);
  const cl::Buffer* buffers[] = {&cameras, &color,   &variance, &depth,        &normal,
                                 &prev[0], &prev[1], &prev[2],  &prev[3],      &prev[4],
                                 &acc,     &moments, &history,  &acc_variance, &acc_luminance};
  for (cl_uint a = 0; a < 15; ++a) k.setArg(9 + a, *buffers[a]);
  launch(temporal, 0, n);
  s.width = in.width, s.height = in.height, s.camera = cams[0];
  s.color.resize(3 * n), s.moments.resize(2 * n), s.history.resize(2 * n);
  if (!svgf_history_from_first_iteration(p))  // else read after the first iteration
    rt.queue.enqueueReadBuffer(acc, CL_FALSE, 0, 3 * n * sizeof(float), s.color.data());
  rt.queue.enqueueReadBuffer(moments, CL_FALSE, 0, 2 * n * sizeof(float), s.moments.data());
  rt.queue.enqueueReadBuffer(history, CL_TRUE, 0, 2 * n * sizeof(float), s.history.data());
  s.depth.assign(in.depth, in.depth + n);
  s.normal.assign(in.normal, in.normal + 3 * n);
  color = acc;
  luminance = acc_luminance;
  variance = acc_variance;
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
    impl_->denoise(denoise_input_as_filtered(in), nullptr, out_rgb, params);
  } catch (const cl::Error& e) {
    throw DeviceError("opencl denoiser on device " + std::to_string(impl_->rt.index) + ": " +
                      cl_util::describe(e));
  }
}

void OpenClDenoiser::svgf(const DenoiseInput& in, DenoiseState& state, float* out_rgb,
                          const DenoiseParams& params) {
  check_denoise_input(in, DenoiseMethod::svgf, &state, out_rgb);
  try {
    impl_->denoise(denoise_input_as_filtered(in), &state, out_rgb, params);
  } catch (const cl::Error& e) {
    throw DeviceError("opencl denoiser on device " + std::to_string(impl_->rt.index) + ": " +
                      cl_util::describe(e));
  }
}

size_t OpenClDenoiser::work_group_size() const { return impl_->built.local; }
size_t OpenClDenoiser::launch_items() const { return impl_->built.launch_items; }

}  // namespace multiray
