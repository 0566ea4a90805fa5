#include "device/opencl/cl_runtime.h"

#include <cstddef>
#include <stdexcept>

#include "core/error.h"
#include "device/opencl/cl_program.h"

namespace multiray {

ClRuntime::ClRuntime(const cl::Device& d, int device_index, int tile_side, int work_group)
    : device(d), context(d), queue(context, d), index(device_index), tile(tile_side) {
  local = std::max<size_t>(
      1, std::min<size_t>(size_t(work_group), device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>()));
  max_alloc = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
  global_mem = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
}

size_t fit_work_group(size_t local, size_t limit, size_t multiple) {
  if (limit >= local) return local;
  if (multiple > 1 && multiple <= limit) return limit / multiple * multiple;
  size_t p = 1;
  while (p * 2 <= limit) p *= 2;
  return p;
}

ClBuiltKernel ClRuntime::build_kernel(const char* source, const char* name, cl_uint arg_count,
                                      const std::string& extra_options) const {
  ClBuiltKernel out;
  out.local = local;
  // A rebuild at a smaller size can only lower the size again, so this ends; 1 always fits.
  for (;;) {
    // Every launch has the same global size, and the program is built for that size.
    // Why: PoCL 3.1 caches compiled work-group functions per (program, local size, grid
    // width) but releases them by (program, local size) only, so two devices launching
    // one program with different global sizes at the same moment corrupt its reference
    // counts and abort (assertion in pocl_release_dlhandle_cache, seen with
    // POCL_DEVICES="basic basic"). One size per program keeps one cache entry per program.
    out.launch_items = (size_t(tile) * size_t(tile) + out.local - 1) / out.local * out.local;
    std::string options = "-cl-std=CL1.2 -DMR_GROUP_ITEMS=" + std::to_string(out.local) +
                          " -DMR_LAUNCH_ITEMS=" + std::to_string(out.launch_items);
    if (!extra_options.empty()) options += " " + extra_options;
    const cl_util::BuiltProgram built = cl_util::build_program(context, device, source, options);
    out.from_cache = built.from_cache;
    out.kernel = cl::Kernel(built.program, name);
    const cl_uint args = out.kernel.getInfo<CL_KERNEL_NUM_ARGS>();
    if (args != arg_count)
      throw DeviceError(std::string("OpenCL: ") + name + " has " + std::to_string(args) +
                        " arguments, the host sets " + std::to_string(arg_count));
    // The kernels declare no __local memory; a driver that still needs more than the
    // device has cannot run them at any size.
    const cl_ulong local_mem = out.kernel.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(device);
    if (local_mem > device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>())
      throw DeviceError("opencl device " + std::to_string(index) + ": " + name + " needs " +
                        std::to_string(local_mem) + " bytes of local memory, the device has " +
                        std::to_string(device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>()));
    const size_t limit = out.kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device);
    out.limit = limit;
    if (limit >= out.local || out.local == 1) return out;
    const size_t multiple =
        out.kernel.getWorkGroupInfo<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(device);
    out.local = std::min(out.local - 1, fit_work_group(out.local, limit, multiple));
    out.local = std::max<size_t>(1, out.local);
  }
}

cl::Buffer ClRuntime::upload(const void* data, size_t bytes, const std::string& what) const {
  static const cl_float16 zero{};
  if (bytes > max_alloc)
    throw DeviceError("OpenCL: " + what + " needs a " + std::to_string(bytes >> 20) +
                      " MB buffer, the device allows " + std::to_string(max_alloc >> 20) + " MB");
  if (bytes == 0) data = &zero, bytes = 1;
  return cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes,
                    const_cast<void*>(data));
}

std::vector<std::vector<ClLaunchRect>> plan_launches(std::span<const Rect> rects, int tile,
                                                     size_t max_pieces) {
  const size_t capacity = size_t(tile) * size_t(tile);
  max_pieces = std::clamp<size_t>(max_pieces, 1, MR_BATCH_MAX);
  std::vector<std::vector<ClLaunchRect>> launches;
  size_t pixels = 0;  // of the last launch
  for (size_t k = 0; k < rects.size(); ++k)
    for_each_launch(rects[k], tile, [&](ClLaunchRect piece) {
      piece.rect = k;
      if (launches.empty() || launches.back().size() >= max_pieces ||
          pixels + piece.pixels() > capacity) {
        launches.emplace_back();
        pixels = 0;
      }
      launches.back().push_back(piece);
      pixels += piece.pixels();
    });
  return launches;
}

ClLaunchBuffers::ClLaunchBuffers(const ClRuntime& rt) {
  const size_t pixels = size_t(rt.tile) * size_t(rt.tile);
  host_radiance.resize(pixels);
  host_counts.resize(pixels);
  host_spp.resize(pixels);
  batch = cl::Buffer(rt.context, CL_MEM_READ_ONLY, sizeof(BatchRects));
  radiance = cl::Buffer(rt.context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_float4));
  counts = cl::Buffer(rt.context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_uint));
  spp_map = cl::Buffer(rt.context, CL_MEM_READ_ONLY, pixels * sizeof(cl_uchar));
  features = cl::Buffer(rt.context, CL_MEM_WRITE_ONLY, sizeof(cl_float4));  // a placeholder
}

bool ClLaunchBuffers::allocate_features(const ClRuntime& rt) {
  if (!host_features.empty()) return false;
  const size_t values = kFeatureFloat4s * size_t(rt.tile) * size_t(rt.tile);
  features = cl::Buffer(rt.context, CL_MEM_WRITE_ONLY, values * sizeof(cl_float4));
  host_features.resize(values);
  return true;
}

void ClLaunchBuffers::write(const ClRuntime& rt, const ViewSetup& view, const RenderSettings& st,
                            std::span<const ClLaunchRect> pieces,
                            std::vector<ClRectCounts>& out_counts) {
  // The writes are non-blocking: the host copies stay unchanged until read() waits for
  // the queue.
  host_batch.count = cl_uint(pieces.size());
  size_t n = 0;  // pixels so far
  for (size_t k = 0; k < pieces.size(); ++k) {
    const ClLaunchRect& r = pieces[k];
    host_batch.rects[k] = mr_int4{r.x, r.y, r.w, r.h};
    uint64_t samples = 0;
    if (!view.spp_map) {
      samples = uint64_t(r.pixels()) * uint64_t(std::max(0, st.spp));
    } else {
      // Irregular sampling: this piece's slice of the view's samples-per-pixel map, at
      // the piece's place in the batch.
      for (size_t i = 0; i < r.pixels(); ++i) {
        const int x = r.x + int(i % size_t(r.w)), y = r.y + int(i / size_t(r.w));
        host_spp[n + i] = (*view.spp_map)[size_t(y) * size_t(view.width) + size_t(x)];
        samples += host_spp[n + i];
      }
    }
    n += r.pixels();
    host_batch.ends[k] = cl_uint(n);
    out_counts.at(r.rect).samples += samples;
  }
  // Only the entries in use: the rest of the device's copy is never read.
  const size_t bytes = offsetof(BatchRects, rects) + pieces.size() * sizeof(mr_int4);
  rt.queue.enqueueWriteBuffer(batch, CL_FALSE, 0, bytes, &host_batch);
  if (view.spp_map) rt.queue.enqueueWriteBuffer(spp_map, CL_FALSE, 0, n, host_spp.data());
}

void ClLaunchBuffers::read_features(std::span<const ClLaunchRect> pieces, Framebuffer& out) const {
  size_t first = 0;  // of the piece, in the batch
  for (const ClLaunchRect& r : pieces) {
    for (size_t i = 0; i < r.pixels(); ++i) {
      // Three float4 per pixel: (albedo, depth), (normal, variance), (emission, unused);
      // kernels/path_tracer.cl.
      const cl_float4& a = host_features[kFeatureFloat4s * (first + i)];
      const cl_float4& b = host_features[kFeatureFloat4s * (first + i) + 1];
      const cl_float4& e = host_features[kFeatureFloat4s * (first + i) + 2];
      const float v[FeatureBuffers::kFloats] = {a.s[0], a.s[1], a.s[2], b.s[0], b.s[1], b.s[2],
                                                a.s[3], b.s[3], e.s[0], e.s[1], e.s[2]};
      const size_t x = size_t(r.x) + i % size_t(r.w), y = size_t(r.y) + i / size_t(r.w);
      out.features.set_packed(y * size_t(out.width) + x, v);
    }
    first += r.pixels();
  }
}

void ClLaunchBuffers::read(const ClRuntime& rt, std::span<const ClLaunchRect> pieces,
                           Framebuffer& out, std::vector<ClRectCounts>& out_counts,
                           bool with_features) {
  size_t n = 0;
  for (const ClLaunchRect& r : pieces) n += r.pixels();
  rt.queue.enqueueReadBuffer(radiance, CL_FALSE, 0, n * sizeof(cl_float4), host_radiance.data());
  rt.queue.enqueueReadBuffer(counts, CL_FALSE, 0, n * sizeof(cl_uint), host_counts.data());
  if (with_features) {
    if (host_features.size() < kFeatureFloat4s * n || out.features.width != out.width ||
        out.features.height != out.height)
      throw std::logic_error("feature buffers asked for, and nothing to hold them");
    rt.queue.enqueueReadBuffer(features, CL_FALSE, 0, kFeatureFloat4s * n * sizeof(cl_float4),
                               host_features.data());
  }
  rt.queue.finish();
  if (with_features) read_features(pieces, out);
  size_t first = 0;  // of the piece, in the batch
  for (const ClLaunchRect& r : pieces) {
    uint64_t total = 0;
    for (size_t i = 0; i < r.pixels(); ++i) {
      const cl_float4& p = host_radiance[first + i];
      out.at(r.x + int(i % size_t(r.w)), r.y + int(i / size_t(r.w))) =
          Vec3(p.s[0], p.s[1], p.s[2]);
      total += host_counts[first + i];
    }
    out_counts.at(r.rect).counts += total;
    first += r.pixels();
  }
}

}  // namespace multiray
