#include "device/opencl/opencl_volume.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "core/error.h"
#include "device/opencl/kernels/volume_params.h"
#include "device/opencl/volume_kernel_source.h"
#include "render/path_tracer.h"

namespace multiray {

namespace {

std::string megabytes(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20); }

class ClVolumeRaycaster : public ClKernelRunner {
 public:
  ClVolumeRaycaster(const ClRuntime& rt, const VolumeScene& vs)
      : rt_(rt), vs_(vs), out_(rt), params_block_(rt) {
    // Division and sqrt correctly rounded, as on the CPU (OpenCL allows 2.5 and 3 ulp).
    built_ = rt.build_kernel(kVolumeSource, "render_volume", MR_VARG_COUNT,
                             "-cl-fp32-correctly-rounded-divide-sqrt");
    from_cache = built_.from_cache;
    work_group = built_.local;
    work_group_limit = built_.limit;
    cl::Kernel& k = built_.kernel;
    const Volume& v = vs.volume;
    values_ = rt.upload(v.values.data(), v.values.size() * sizeof(float), "the volume");
    opacity_ = cl::Buffer(rt.context, CL_MEM_READ_ONLY,
                          std::max<size_t>(1, vs.blocks.count()) * sizeof(float));
    k.setArg(MR_VARG_values, values_);
    k.setArg(MR_VARG_block_opacity, opacity_);
    k.setArg(MR_VARG_params, params_block_.buffer);
    k.setArg(MR_VARG_batch, out_.batch);
    k.setArg(MR_VARG_spp_map, out_.spp_map);
    k.setArg(MR_VARG_radiance, out_.radiance);
    k.setArg(MR_VARG_steps, out_.counts);
    // MR_VARG_table is set by use_style, before the first launch.
    params_.lower = cl_f4(v.lower());
    params_.spacing = cl_f4(v.spacing);
    params_.dims = mr_int4{v.nx, v.ny, v.nz, 0};
    params_.blocks = mr_int4{vs.blocks.bx, vs.blocks.by, vs.blocks.bz, 0};
  }

  std::vector<KernelStats> render_rects(const ViewSetup& view, const RenderSettings& st,
                                        std::span<const Rect> rects, Framebuffer& out) override {
    if (!st.volume_style)
      throw std::invalid_argument("the volume kernel needs a transfer function (volume_style)");
    use_style(st.volume_style);
    set_frame_params(view, st);
    const std::vector<ClRectCounts> counts = out_.render(rt_, view, st, rects, out, [&] {
      // Always `launch_items` work-items (see ClRuntime::build_kernel).
      params_block_.write(rt_, params_);
      rt_.queue.enqueueNDRangeKernel(built_.kernel, cl::NullRange,
                                     cl::NDRange(built_.launch_items), cl::NDRange(built_.local));
    });
    std::vector<KernelStats> stats(counts.size());
    for (size_t k = 0; k < counts.size(); ++k) {
      stats[k].samples = counts[k].samples;
      stats[k].rays = counts[k].samples;  // one camera ray per sample
      stats[k].steps = counts[k].counts;
    }
    return stats;
  }

 private:
  // Uploads the table and the block opacities of `style` unless they are on the device
  // already (the same shared_ptr: styles are immutable; holding it keeps its address from
  // being reused by another style).
  void use_style(const std::shared_ptr<const VolumeStyle>& style) {
    if (style == style_) return;
    const size_t entries = style->table.rgba.size();
    if (entries < 2 || style->colour_log_transparency.size() != entries ||
        style->opacity.max_opacity.size() != vs_.blocks.count())
      throw std::invalid_argument("the volume style does not belong to this volume");
    const size_t table_bytes = entries * sizeof(cl_float4);
    static_assert(sizeof(style->colour_log_transparency[0]) == sizeof(cl_float4));
    if (table_bytes != table_bytes_) {
      table_ = cl::Buffer(rt_.context, CL_MEM_READ_ONLY, table_bytes);
      table_bytes_ = table_bytes;
      built_.kernel.setArg(MR_VARG_table, table_);
    }
    rt_.queue.enqueueWriteBuffer(table_, CL_TRUE, 0, table_bytes,
                                 style->colour_log_transparency.data());
    if (vs_.blocks.count() > 0)
      rt_.queue.enqueueWriteBuffer(opacity_, CL_TRUE, 0, vs_.blocks.count() * sizeof(float),
                                   style->opacity.max_opacity.data());
    style_ = style;
  }

  // The scalars of every launch of these rects, computed as VolumeRaycaster does.
  void set_frame_params(const ViewSetup& view, const RenderSettings& st) {
    const VolumeStyle& style = *style_;
    params_.camera = PinholeCamera(view.camera, view.width, view.height).block();
    params_.background = cl_f4(style.background);
    params_.blocks.w = style.skip_empty ? 1 : 0;
    params_.seed = cl_ulong(st.seed);
    params_.width = cl_uint(view.width);
    params_.spp = cl_int(st.spp);
    params_.frame = cl_uint(view.seed_frame());
    params_.first_sample = cl_uint(view.first_sample);
    params_.view = cl_uint(view.view);
    params_.use_spp_map = view.spp_map ? 1 : 0;
    const TransferTable& table = style.table;
    params_.table_size = cl_uint(table.rgba.size());
    params_.dt = style.step * st.step_scale * vs_.volume.voxel_length();
    params_.step_ratio = style.step * st.step_scale / style.reference_step;
    params_.table_lo = table.lo;
    params_.table_to_index = float(table.rgba.size() - 1) / std::max(table.hi - table.lo, 1e-30f);
    params_.ert_threshold = style.ert_threshold;
  }

  const ClRuntime& rt_;
  const VolumeScene& vs_;
  ClBuiltKernel built_;
  cl::Buffer values_, opacity_, table_;
  size_t table_bytes_ = 0;
  std::shared_ptr<const VolumeStyle> style_;  // whose table and opacities are on the device
  ClLaunchBuffers out_;
  ClParamBlock<VolumeParams> params_block_;  // `params_` on the device
  VolumeParams params_{};
};

}  // namespace

ClVolumeMemory cl_volume_memory(const VolumeScene& vs, int tile, size_t table_entries) {
  ClVolumeMemory m;
  m.values = uint64_t(vs.volume.voxel_count()) * sizeof(float);
  const uint64_t pixels = uint64_t(tile) * uint64_t(tile);
  m.total = m.values + uint64_t(vs.blocks.count()) * sizeof(float) +
            uint64_t(table_entries) * sizeof(cl_float4) +
            pixels * (sizeof(cl_float4) + sizeof(cl_uint) + sizeof(cl_uchar)) +
            sizeof(VolumeParams) + sizeof(BatchRects);
  return m;
}

std::string cl_volume_memory_problem(const ClVolumeMemory& need, uint64_t max_alloc,
                                     uint64_t global_mem) {
  if (need.values <= max_alloc && need.total <= global_mem) return "";
  return "the volume needs " + megabytes(need.total) + " MB of device memory (" +
         megabytes(need.values) + " MB of values in one buffer); the device has " +
         std::to_string(global_mem >> 20) + " MB and allows " + std::to_string(max_alloc >> 20) +
         " MB per buffer";
}

std::unique_ptr<ClKernelRunner> make_cl_volume_raycaster(const ClRuntime& rt,
                                                         const VolumeScene& vs) {
  const std::string problem =
      cl_volume_memory_problem(cl_volume_memory(vs, rt.tile), rt.max_alloc, rt.global_mem);
  if (!problem.empty())
    throw DeviceError("opencl device " + std::to_string(rt.index) + ": " + problem);
  return std::make_unique<ClVolumeRaycaster>(rt, vs);
}

}  // namespace multiray
