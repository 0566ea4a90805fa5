#include "device/opencl/opencl_device.h"

#include <pthread.h>
#include <sched.h>

#include <array>
#include <atomic>
#include <stdexcept>
#include <thread>

#include "core/clock.h"
#include "core/error.h"
#include "device/opencl/cl_common.h"
#include "device/opencl/cl_program.h"
#include "device/opencl/kernel_source.h"
#include "device/opencl/kernels/launch_params.h"
#include "device/opencl/scene_buffers.h"

namespace multiray {

namespace {

cl_float4 f4(Vec3 v, float w = 0) { return cl_float4{{v.x, v.y, v.z, w}}; }

void pin_current_thread(const std::vector<int>& cores) {
  if (cores.empty()) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cores) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

}  // namespace

struct OpenClDevice::Impl {
  OpenClDeviceOptions opts;
  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;
  cl::Kernel kernel;
  std::vector<cl::Buffer> scene;  // kept alive while the kernel refers to them
  cl::Buffer radiance, rays;      // one launch's output: tile x tile pixels
  cl::Buffer spp_map;             // one launch's samples per pixel, when the view has a map
  cl::Buffer params_buffer;       // `params`, rewritten before every launch
  LaunchParams params{};          // its host copy
  std::vector<cl_float4> host_radiance;
  std::vector<cl_uint> host_rays;
  std::vector<cl_uchar> host_spp;
  size_t local = 64;        // work-group size
  size_t launch_items = 0;  // global size of every launch: tile^2 rounded up to `local`
  bool from_cache = false;
  std::atomic<double> speed{1.0};
  int units_done = 0;  // over the device's lifetime, for fail_after

  // Uploads `v` read-only; OpenCL has no empty buffers, so an empty table becomes one
  // zeroed element that the kernel never reads.
  template <class T>
  cl::Buffer upload(const std::vector<T>& v, uint64_t max_alloc) {
    static const T zero{};
    const size_t bytes = std::max<size_t>(1, v.size()) * sizeof(T);
    if (bytes > max_alloc)
      throw DeviceError("OpenCL: the scene needs a " + std::to_string(bytes >> 20) +
                        " MB buffer, the device allows " + std::to_string(max_alloc >> 20) +
                        " MB");
    void* data = const_cast<T*>(v.empty() ? &zero : v.data());
    scene.emplace_back(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, data);
    return scene.back();
  }

  void setup(const RenderScene& rs) {
    context = cl::Context(device);
    queue = cl::CommandQueue(context, device);
    local = std::max<size_t>(1, std::min<size_t>(size_t(opts.work_group),
                                                 device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>()));
    launch_items = (size_t(opts.tile) * size_t(opts.tile) + local - 1) / local * local;
    // Every launch has the same global size, and the program is built for that size.
    // Why: PoCL 3.1 caches compiled work-group functions per (program, local size, grid
    // width) but releases them by (program, local size) only, so two devices launching
    // one program with different global sizes at the same moment corrupt its reference
    // counts and abort (assertion in pocl_release_dlhandle_cache, seen with
    // POCL_DEVICES="basic basic"). One size per program keeps one cache entry per program.
    const std::string options = "-cl-std=CL1.2 -DMR_GROUP_ITEMS=" + std::to_string(local) +
                                " -DMR_LAUNCH_ITEMS=" + std::to_string(launch_items);
    const cl_util::BuiltProgram built =
        cl_util::build_program(context, device, kPathTracerSource, options);
    from_cache = built.from_cache;
    kernel = cl::Kernel(built.program, "render_rect");
    const size_t kernel_max = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device);
    if (kernel_max < local)
      throw DeviceError("opencl device " + std::to_string(opts.index) + ": work-group size " +
                        std::to_string(local) + " is too large for the kernel here (at most " +
                        std::to_string(kernel_max) + "); use :wg=" + std::to_string(kernel_max));

    // Every argument is a buffer, set once here; the arguments are listed once, in
    // kernels/launch_params.h.
    const cl_uint kernel_args = kernel.getInfo<CL_KERNEL_NUM_ARGS>();
    if (kernel_args != MR_ARG_COUNT)
      throw DeviceError("OpenCL: render_rect has " + std::to_string(kernel_args) +
                        " arguments, the host sets " + std::to_string(int(MR_ARG_COUNT)));
    std::array<cl::Buffer, MR_ARG_COUNT> args;
    const ClScene s = build_cl_scene(rs);
    const uint64_t max_alloc = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
    args[MR_ARG_nodes] = upload(s.bvh.nodes, max_alloc);
    args[MR_ARG_tris] = upload(s.bvh.triangles, max_alloc);
    args[MR_ARG_shading] = upload(s.shading, max_alloc);
    args[MR_ARG_materials] = upload(s.materials, max_alloc);
    args[MR_ARG_lights] = upload(s.lights, max_alloc);
    args[MR_ARG_light_cdf] = upload(s.light_cdf, max_alloc);
    args[MR_ARG_light_pdf_by_prim] = upload(s.light_pdf_by_prim, max_alloc);
    args[MR_ARG_texels] = upload(s.texels, max_alloc);
    args[MR_ARG_textures] = upload(s.textures, max_alloc);
    args[MR_ARG_srgb_lut] = upload(s.srgb_to_linear, max_alloc);
    params.light_count = cl_uint(s.lights.size());
    params.environment_eps = f4(s.environment, s.ray_eps);

    const size_t pixels = size_t(opts.tile) * size_t(opts.tile);
    host_radiance.resize(pixels);
    host_rays.resize(pixels);
    host_spp.resize(pixels);
    params_buffer = cl::Buffer(context, CL_MEM_READ_ONLY, sizeof(LaunchParams));
    radiance = cl::Buffer(context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_float4));
    rays = cl::Buffer(context, CL_MEM_WRITE_ONLY, pixels * sizeof(cl_uint));
    spp_map = cl::Buffer(context, CL_MEM_READ_ONLY, pixels * sizeof(cl_uchar));
    args[MR_ARG_params] = params_buffer;
    args[MR_ARG_radiance] = radiance;
    args[MR_ARG_rays] = rays;
    args[MR_ARG_spp_map] = spp_map;
    for (cl_uint i = 0; i < MR_ARG_COUNT; ++i) {
      if (!args[i]())
        throw std::logic_error(std::string("OpenCL: no buffer for render_rect argument ") +
                               kRenderRectArgNames[i]);
      kernel.setArg(i, args[i]);
    }
  }

  // Renders `r` of `view` into `out` in launches of at most tile x tile pixels.
  KernelStats render_rect(const ViewSetup& view, const RenderSettings& st, Rect r,
                          Framebuffer& out) {
    KernelStats stats;
    const PinholeCamera cam(view.camera, view.width, view.height);
    params.eye = f4(cam.eye);
    params.forward = f4(cam.forward);
    params.right = f4(cam.right);
    params.up = f4(cam.up);
    params.scale =
        cl_float4{{cam.scale_x, cam.scale_y, 2.0f / float(view.width), 2.0f / float(view.height)}};
    params.width = cl_uint(view.width);
    params.spp = cl_int(st.spp);
    params.max_bounces = cl_int(st.max_bounces);
    params.rr_start = cl_int(st.rr_start);
    params.frame = cl_uint(view.frame);
    params.view = cl_uint(view.view);
    params.seed = cl_ulong(st.seed);
    params.use_spp_map = view.spp_map ? 1 : 0;
    const int t = opts.tile;
    for (int y0 = r.y0; y0 < r.y1; y0 += t)
      for (int x0 = r.x0; x0 < r.x1; x0 += t) {
        const int w = std::min(t, r.x1 - x0), h = std::min(t, r.y1 - y0);
        const size_t n = size_t(w) * size_t(h);
        // Always `launch_items` work-items (see setup); those beyond the `n` pixels return
        // at once.
        // Non-blocking writes: the host copies stay unchanged until finish() below.
        params.rect = cl_int4{{x0, y0, w, h}};
        queue.enqueueWriteBuffer(params_buffer, CL_FALSE, 0, sizeof(LaunchParams), &params);
        // Irregular sampling: this launch's slice of the view's samples-per-pixel map.
        uint64_t samples = uint64_t(n) * uint64_t(std::max(0, st.spp));
        if (view.spp_map) {
          samples = 0;
          for (size_t i = 0; i < n; ++i) {
            const int x = x0 + int(i % size_t(w)), y = y0 + int(i / size_t(w));
            host_spp[i] = (*view.spp_map)[size_t(y) * size_t(view.width) + size_t(x)];
            samples += host_spp[i];
          }
          queue.enqueueWriteBuffer(spp_map, CL_FALSE, 0, n, host_spp.data());
        }
        queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(launch_items),
                                   cl::NDRange(local));
        queue.enqueueReadBuffer(radiance, CL_FALSE, 0, n * sizeof(cl_float4),
                                host_radiance.data());
        queue.enqueueReadBuffer(rays, CL_FALSE, 0, n * sizeof(cl_uint), host_rays.data());
        queue.finish();
        for (size_t i = 0; i < n; ++i) {
          const cl_float4& p = host_radiance[i];
          out.at(x0 + int(i % size_t(w)), y0 + int(i / size_t(w))) = Vec3(p.s[0], p.s[1], p.s[2]);
          stats.rays += host_rays[i];
        }
        stats.samples += samples;
      }
    return stats;
  }
};

DeviceCapabilities OpenClDevice::capabilities() {
  DeviceCapabilities caps;
  caps.kernels = {"path"};
  caps.sampling = {"uniform", "adaptive"};  // per-pixel sample maps; no foveated patterns
  caps.representation = "opencl-flat-bvh";
  return caps;
}

OpenClDevice::OpenClDevice(SceneCache& scenes, OpenClDeviceOptions opts, std::string spec)
    : impl_(std::make_unique<Impl>()) {
  const RenderScene& rs = scenes.embree();  // flattened into this device's own buffers
  if (!(opts.speed > 0 && opts.speed <= 1))
    throw InputError("opencl device: speed must be in (0, 1], got " + std::to_string(opts.speed));
  if (opts.tile < 1 || opts.tile > 4096)
    throw InputError("opencl device: tile must be in 1..4096");
  if (opts.work_group < 1 || opts.work_group > 4096)
    throw InputError("opencl device: wg must be in 1..4096");
  const int ncpu = int(std::thread::hardware_concurrency());
  for (int c : opts.cores)
    if (c < 0 || (ncpu > 0 && c >= ncpu))
      throw InputError("opencl device: core " + std::to_string(c) + " does not exist");
  const std::vector<cl::Device> all = cl_util::all_devices();
  if (all.empty())
    throw InputError(
        "opencl device: no OpenCL device found (is an ICD such as pocl-opencl-icd "
        "installed? `multiray devices` lists what is found)");
  if (opts.index < 0 || size_t(opts.index) >= all.size())
    throw InputError("opencl device: there is no OpenCL device " + std::to_string(opts.index) +
                     " (found " + std::to_string(all.size()) +
                     ", numbered from 0; see `multiray devices`)");
  impl_->opts = opts;
  impl_->speed = opts.speed;
  impl_->device = all[size_t(opts.index)];
  std::string name = "?";
  try {
    name = impl_->device.getInfo<CL_DEVICE_NAME>();
    info_.threads = int(impl_->device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
    impl_->setup(rs);
  } catch (const cl::Error& e) {
    throw DeviceError("opencl device " + std::to_string(opts.index) + " (" + name +
                      "): setting up failed: " + cl_util::describe(e));
  }
  info_.type = "opencl";
  info_.caps = capabilities();
  info_.spec = std::move(spec);
  info_.emulated_speed = opts.speed;
  info_.name = "opencl " + std::to_string(opts.index) + " (" + name;
  if (!opts.cores.empty()) {
    info_.name += ", cores";
    // Appended in two steps: GCC 12 warns (-Wrestrict, falsely) on " " + to_string(c).
    for (int c : opts.cores) info_.name.append(" ").append(std::to_string(c));
  }
  if (opts.speed < 1) info_.name += ", emulated speed " + std::to_string(opts.speed).substr(0, 4);
  info_.name += ")";
}

OpenClDevice::~OpenClDevice() = default;

bool OpenClDevice::kernel_from_cache() const { return impl_->from_cache; }
size_t OpenClDevice::work_group_size() const { return impl_->local; }

void OpenClDevice::set_emulated_speed(double speed) {
  impl_->speed = speed;
  info_.emulated_speed = speed;
}

DeviceReport OpenClDevice::render(const FrameJob& job, WorkSource& source, int index) {
  DeviceReport report;
  // Pin the calling thread once per thread and device, as the CPU device does (the engine
  // keeps one thread per device); the set-up is not part of the frame time.
  thread_local const void* pinned_for = nullptr;
  if (pinned_for != this) {
    pin_current_thread(impl_->opts.cores);
    pinned_for = this;
  }
  const Stopwatch frame_clock;
  // Refuse, before taking any work, what the kernel does not implement: the engine then
  // drops this device and the others render the frame.
  std::string unsupported;
  for (const ViewSetup& v : job.views)
    if (v.foveation) unsupported = unsupported_job(info_, job.settings.kernel, "foveated");
  if (unsupported.empty()) unsupported = unsupported_job(info_, job.settings.kernel, "uniform");
  if (!unsupported.empty()) {
    report.failed = true;
    report.error = unsupported;
    report.time_ms = frame_clock.elapsed_ms();
    return report;
  }
  try {
    SlowdownEmulator slowdown(impl_->speed.load());
    for (uint32_t id; source.next(index, id);) {
      if (impl_->opts.fail_after >= 0 && impl_->units_done >= impl_->opts.fail_after) {
        report.failed = true;
        report.error = "injected failure after " + std::to_string(impl_->units_done) +
                       " units (fail_after, a testing aid)";
        break;
      }
      const Stopwatch item_clock;
      const WorkItem& item = source.item(id);
      const KernelStats ks = impl_->render_rect(job.views.at(size_t(item.view)), job.settings,
                                                item.rect, job.outputs->at(size_t(item.view)));
      const double busy = item_clock.elapsed_ms();
      slowdown.after_unit(busy);
      report.add(ItemReport{item, item_clock.elapsed_ms(), double(ks.samples), busy, id}, ks.rays);
      ++impl_->units_done;
    }
  } catch (const cl::Error& e) {
    report.failed = true;
    report.error = info_.name + ": " + cl_util::describe(e);
  } catch (const std::exception& e) {
    report.failed = true;
    report.error = info_.name + ": " + e.what();
  }
  report.time_ms = frame_clock.elapsed_ms();
  return report;
}

}  // namespace multiray
