#include "device/opencl/opencl_path_tracer.h"

#include <array>
#include <stdexcept>

#include "device/gpu_scene/scene_buffers.h"
#include "device/opencl/kernel_source.h"
#include "device/opencl/kernels/launch_params.h"
#include "render/path_tracer.h"

namespace multiray {

namespace {

class ClPathTracer : public ClKernelRunner {
 public:
  ClPathTracer(const ClRuntime& rt, const RenderScene& rs) : rt_(rt), out_(rt), params_block_(rt) {
    const GpuScene s = build_gpu_scene(rs);
    scene_bytes = gpu_scene_bytes(s);
    // One program per representation: the compact one traverses the quantized tree and
    // decodes the mesh (kernels/shading.cl, traverse_compact.cl).
    built_ = rt.build_kernel(kPathTracerSource, "render_rect", MR_ARG_COUNT,
                             s.is_compact ? "-DMR_COMPACT=1" : "");
    from_cache = built_.from_cache;
    work_group = built_.local;
    work_group_limit = built_.limit;
    // Every argument is a buffer, set once here; the arguments are listed once, in
    // kernels/launch_params.h. The buffers of the representation not in use are empty
    // (one placeholder byte each).
    std::array<cl::Buffer, MR_ARG_COUNT> args;
    args[MR_ARG_nodes] = upload(s.bvh.nodes);
    args[MR_ARG_tris] = upload(s.bvh.triangles);
    args[MR_ARG_shading] = upload(s.shading);
    const GpuCompactScene& k = s.compact;
    args[MR_ARG_cnodes] = upload(k.nodes);
    args[MR_ARG_prims] = upload(k.prims);
    args[MR_ARG_qpos] = upload(k.positions);
    args[MR_ARG_cells] = upload(k.cells);
    args[MR_ARG_indices] = upload(k.indices);
    args[MR_ARG_qnormals] = upload(k.normals);
    args[MR_ARG_quvs] = upload(k.uvs);
    args[MR_ARG_uv_shifts] = upload(k.uv_shifts);
    args[MR_ARG_material_ids] = upload(k.material_ids);
    args[MR_ARG_compact] = upload(std::vector<CompactInfo>{k.info});
    args[MR_ARG_materials] = upload(s.materials);
    args[MR_ARG_lights] = upload(s.lights);
    args[MR_ARG_light_cdf] = upload(s.light_cdf);
    args[MR_ARG_light_pdf_by_prim] = upload(s.light_pdf_by_prim);
    args[MR_ARG_texels] = upload(s.texels);
    args[MR_ARG_textures] = upload(s.textures);
    args[MR_ARG_texel_luts] = upload(s.texel_luts);
    args[MR_ARG_tangents] = upload(s.tangents);
    args[MR_ARG_sky] = upload(std::vector<SkyRecord>{s.sky});
    args[MR_ARG_sky_data] = upload(s.sky_data);
    params_.light_count = cl_uint(s.lights.size());
    sky_choice_ = s.sky.choice;
    ray_eps_ = s.ray_eps;
    params_.has_tangents = s.tangents.empty() ? 0u : 1u;
    params_.cutouts = s.cutouts ? 1u : 0u;
    args[MR_ARG_params] = params_block_.buffer;
    args[MR_ARG_batch] = out_.batch;
    args[MR_ARG_radiance] = out_.radiance;
    args[MR_ARG_rays] = out_.counts;
    args[MR_ARG_spp_map] = out_.spp_map;
    args[MR_ARG_features] = out_.features;  // a placeholder until a frame asks for them
    for (cl_uint i = 0; i < MR_ARG_COUNT; ++i) {
      if (!args[i]())
        throw std::logic_error(std::string("OpenCL: no buffer for render_rect argument ") +
                               kRenderRectArgNames[i]);
      built_.kernel.setArg(i, args[i]);
    }
  }

  std::vector<KernelStats> render_rects(const ViewSetup& view, const RenderSettings& st,
                                        std::span<const Rect> rects, Framebuffer& out) override {
    params_.camera = PinholeCamera(view.camera, view.width, view.height).block();
    params_.width = cl_uint(view.width);
    params_.spp = cl_int(st.spp);
    params_.max_bounces = cl_int(st.max_bounces);
    params_.rr_start = cl_int(st.rr_start);
    params_.frame = cl_uint(view.seed_frame());
    params_.first_sample = cl_uint(view.first_sample);
    params_.view = cl_uint(view.view);
    params_.seed = cl_ulong(st.seed);
    params_.use_spp_map = view.spp_map ? 1 : 0;
    params_.sample_clamp = st.sample_clamp;
    params_.feature_buffers = st.feature_buffers ? 1u : 0u;
    if (st.feature_buffers && out_.allocate_features(rt_))
      built_.kernel.setArg(MR_ARG_features, out_.features);
    // As PathTracer::step's p_env.
    const float p_env = st.sample_environment ? sky_choice_ : 0.0f;
    params_.env_choice_eps = cl_f4(Vec3(p_env, 0.0f, 0.0f), ray_eps_);
    const std::vector<ClRectCounts> counts = out_.render(rt_, view, st, rects, out, [&] {
      // Always `launch_items` work-items (see ClRuntime::build_kernel); those beyond the
      // batch's pixels return at once.
      params_block_.write(rt_, params_);
      rt_.queue.enqueueNDRangeKernel(built_.kernel, cl::NullRange,
                                     cl::NDRange(built_.launch_items), cl::NDRange(built_.local));
    });
    std::vector<KernelStats> stats(counts.size());
    for (size_t k = 0; k < counts.size(); ++k)
      stats[k].samples = counts[k].samples, stats[k].rays = counts[k].counts;
    return stats;
  }

 private:
  template <class T>
  cl::Buffer upload(const std::vector<T>& v) {
    scene_.push_back(rt_.upload(v.data(), v.size() * sizeof(T), "the scene"));
    return scene_.back();
  }

  const ClRuntime& rt_;
  ClBuiltKernel built_;
  std::vector<cl::Buffer> scene_;  // kept alive while the kernel refers to them
  ClLaunchBuffers out_;
  ClParamBlock<LaunchParams> params_block_;  // `params_` on the device
  LaunchParams params_{};
  float sky_choice_ = 0;  // RenderScene::environment_choice()
  float ray_eps_ = 0;     // ray-origin offset
};

}  // namespace

std::unique_ptr<ClKernelRunner> make_cl_path_tracer(const ClRuntime& rt, const RenderScene& rs) {
  return std::make_unique<ClPathTracer>(rt, rs);
}

}  // namespace multiray
