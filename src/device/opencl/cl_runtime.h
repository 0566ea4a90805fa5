// What the kernels of one OpenCL device share (context, queue, launch shape, the buffers
// one launch writes, how rects are packed into launches), and the interface each kernel's host
// side implements. Private to src/device/opencl.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "device/opencl/cl_common.h"
#include "device/opencl/kernels/batch_rects.h"
#include "render/render_types.h"
#include "render/shared/language.h"
#include "util/rect.h"

namespace multiray {

// A kernel built for its launch shape: every launch of it uses exactly `launch_items`
// work-items in groups of `local` (one global size per program, see
// ClRuntime::build_kernel). Kernels of one device may have different shapes: each is
// fitted to its own limit.
struct ClBuiltKernel {
  cl::Kernel kernel;
  size_t local = 1;         // work-group size, fitted to the kernel (fit_work_group)
  size_t launch_items = 0;  // global size of every launch: tile^2 rounded up to `local`
  size_t limit = 0;         // CL_KERNEL_WORK_GROUP_SIZE of the kernel as built (>= local)
  bool from_cache = false;  // the program binary came from the disk cache
};

// The work-group size to rebuild a kernel at when, built for `local`, it allows only
// `limit` (CL_KERNEL_WORK_GROUP_SIZE, which depends on the compiled code: Mesa's rusticl
// on llvmpipe allows 32 where the device allows 1024): `local` when it fits, else the
// largest multiple of `multiple` (CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE, the
// SIMD width) not above `limit`, else the largest power of two not above it; at least 1.
size_t fit_work_group(size_t local, size_t limit, size_t multiple);

// One OpenCL device, set up once: every kernel of the device uses its queue.
struct ClRuntime {
  // Creates the context and queue of `device`; kernels are built for launches of at most
  // tile x tile pixels with work groups of `work_group`, clamped to the device's maximum
  // and then fitted to each kernel (build_kernel).
  ClRuntime(const cl::Device& device, int index, int tile, int work_group);

  // Builds `source` (from the disk cache when it can, cl_program.h) with the launch-shape
  // options plus `extra_options` and returns its kernel `name`, after checking that it has
  // `arg_count` arguments. The program is built for work groups of `local`; when the
  // compiled kernel allows fewer (CL_KERNEL_WORK_GROUP_SIZE), it is rebuilt at
  // fit_work_group's size, never refused: the size changes no pixel (each work-item
  // renders its own pixel alone; the kernels use no local memory and no barrier). Throws
  // DeviceError on a build error or a kernel that does not match the host.
  ClBuiltKernel build_kernel(const char* source, const char* name, cl_uint arg_count,
                             const std::string& extra_options) const;

  // A read-only buffer holding `bytes` of `data` (at least one byte: OpenCL has no empty
  // buffers). Throws DeviceError "<what> needs a N MB buffer, the device allows M MB"
  // when `bytes` exceeds the device's largest allocation.
  cl::Buffer upload(const void* data, size_t bytes, const std::string& what) const;

  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;
  int index = 0;            // `opencl:N`, for messages
  int tile = 256;           // side of the largest square one launch renders
  size_t local = 64;        // work-group size asked for, within the device's maximum
  uint64_t max_alloc = 0;   // CL_DEVICE_MAX_MEM_ALLOC_SIZE, bytes
  uint64_t global_mem = 0;  // CL_DEVICE_GLOBAL_MEM_SIZE, bytes
};

// A piece of a rect that one launch renders: pixels [x, x + w) x [y, y + h), a piece of
// rect `rect` (an index into the list the launches were planned for).
struct ClLaunchRect {
  int x, y, w, h;
  size_t rect = 0;
  size_t pixels() const { return size_t(w) * size_t(h); }
};

// Calls f(piece) for each launch-sized piece of `r`, row by row.
template <class F>
void for_each_launch(Rect r, int tile, F f) {
  for (int y0 = r.y0; y0 < r.y1; y0 += tile)
    for (int x0 = r.x0; x0 < r.x1; x0 += tile)
      f(ClLaunchRect{x0, y0, std::min(tile, r.x1 - x0), std::min(tile, r.y1 - y0)});
}

// The launches that render `rects`, in order: each rect cut into pieces of at most
// tile x tile pixels (for_each_launch), the pieces packed greedily, in order, into
// launches of at most tile x tile pixels (the output buffers' size) and `max_pieces`
// (<= MR_BATCH_MAX) pieces. With max_pieces = 1, one launch per piece, as before batching.
std::vector<std::vector<ClLaunchRect>> plan_launches(std::span<const Rect> rects, int tile,
                                                     size_t max_pieces = MR_BATCH_MAX);

// What the kernel reported for one rect of a batch: its samples and the sum of the
// kernel's per-pixel counts (rays for the path tracer, volume samples for the raycaster).
struct ClRectCounts {
  uint64_t samples = 0, counts = 0;
};

// The per-launch buffers every kernel here shares: the batch's rect list (batch_rects.h),
// its output (radiance as float4 and one count per pixel, and for the path tracer, when
// asked, kFeatureFloat4s float4 of feature buffers per pixel) and its slice of the view's
// samples-per-pixel map, with host copies.
struct ClLaunchBuffers {
  // The path kernel's float4s of feature buffers a pixel (kernels/path_tracer.cl).
  static constexpr size_t kFeatureFloat4s = 3;
  explicit ClLaunchBuffers(const ClRuntime& rt);
  // Renders `rects` of `view` into `out` in the launches of plan_launches: per launch,
  // enqueues (non-blocking) the rect list and the sample-map slice, then calls
  // `enqueue_kernel` (which writes the kernel's parameters and enqueues it), then reads
  // the outputs back once and waits. Returns one entry per rect.
  template <class F>
  std::vector<ClRectCounts> render(const ClRuntime& rt, const ViewSetup& view,
                                   const RenderSettings& st, std::span<const Rect> rects,
                                   Framebuffer& out, F enqueue_kernel) {
    std::vector<ClRectCounts> counts(rects.size());
    for (const std::vector<ClLaunchRect>& launch : plan_launches(rects, rt.tile)) {
      write(rt, view, st, launch, counts);
      enqueue_kernel();
      read(rt, launch, out, counts, st.feature_buffers);
    }
    return counts;
  }
  // Allocates the feature buffers' device and host memory on the first call (until then
  // `features` is a 16-byte placeholder: frames without them cost nothing). True when it
  // allocated: the caller then sets the kernel argument to the new buffer.
  bool allocate_features(const ClRuntime& rt);
  // Enqueues (non-blocking) the rect list of `pieces` and, when the view has a sample map,
  // its slice for them; adds each piece's samples (settings.spp per pixel without a map)
  // to its rect's entry of `counts`.
  void write(const ClRuntime& rt, const ViewSetup& view, const RenderSettings& st,
             std::span<const ClLaunchRect> pieces, std::vector<ClRectCounts>& counts);
  // Enqueues the reads of the outputs of `pieces`, waits for the queue, writes the
  // radiance (and with `features`, the feature buffers) into `out` and adds the per-pixel
  // counts to their rects' entries.
  void read(const ClRuntime& rt, std::span<const ClLaunchRect> pieces, Framebuffer& out,
            std::vector<ClRectCounts>& counts, bool features = false);
  // The feature buffers of `pieces`, read back into host_features, into `out`.
  void read_features(std::span<const ClLaunchRect> pieces, Framebuffer& out) const;

  cl::Buffer batch, radiance, counts, spp_map, features;
  BatchRects host_batch{};
  std::vector<cl_float4> host_radiance, host_features;
  std::vector<cl_uint> host_counts;
  std::vector<cl_uchar> host_spp;
};

// A kernel's parameter block (LaunchParams, VolumeParams) in its device buffer, written
// only when its bytes differ from the last ones written: every launch of a frame has the
// same block, so most launches skip that command. `P` has no implicit padding (see
// launch_params.h), so comparing bytes compares values.
template <class P>
class ClParamBlock {
 public:
  explicit ClParamBlock(const ClRuntime& rt) : buffer(rt.context, CL_MEM_READ_ONLY, sizeof(P)) {}
  // Enqueues (non-blocking) the write of `p` unless the buffer holds it already. The host
  // copy is next changed by a later call, after the caller has waited for the queue.
  void write(const ClRuntime& rt, const P& p) {
    if (written_ && std::memcmp(&p, &sent_, sizeof(P)) == 0) return;
    sent_ = p;
    written_ = true;
    rt.queue.enqueueWriteBuffer(buffer, CL_FALSE, 0, sizeof(P), &sent_);
  }

  cl::Buffer buffer;

 private:
  P sent_{};
  bool written_ = false;
};

// The host side of one kernel of an OpenCL device.
class ClKernelRunner {
 public:
  virtual ~ClKernelRunner() = default;
  // Renders `rects` of `view` into `out` (the view's full image) in as few launches as
  // plan_launches allows; returns one entry per rect. Throws cl::Error, or
  // std::invalid_argument for settings the kernel cannot render.
  virtual std::vector<KernelStats> render_rects(const ViewSetup& view,
                                                const RenderSettings& settings,
                                                std::span<const Rect> rects, Framebuffer& out) = 0;
  bool from_cache = false;      // the program binary came from the disk cache
  uint64_t scene_bytes = 0;     // bytes of the scene buffers it uploaded
  size_t work_group = 0;        // the work-group size its launches use (ClBuiltKernel::local)
  size_t work_group_limit = 0;  // what the compiled kernel allows (ClBuiltKernel::limit)
};

// `v` and `w` as a float4 of a parameter block (render/shared/language.h).
inline mr_float4 cl_f4(Vec3 v, float w = 0) { return mr_float4{v.x, v.y, v.z, w}; }

}  // namespace multiray
