// The compact scene against full precision (issue 11; Seo, Park & Ihm 2022, Tables 6-7).
//
// For each scene: bytes of the mesh, the acceleration structure and both, full precision
// (the textbook indexed mesh and the same tree with float boxes, compact_scene.h
// SceneBytes) against compact; bytes the CPU device really holds (Embree's BVH as its
// memory monitor counts it plus 64-byte shading records, against the compact mesh and
// tree); render time of the path tracer on each representation, alternately `reps` times,
// one thread of this process, steady_clock around each whole-frame render_rect call
// (median reported); and PSNR of the compact image against the full-precision one (same
// seeds). Writes one JSON object per scene to stdout's last lines and a table to stderr.
//
// With --opencl (when the OpenCL backend is built and a device is found), the paper's
// like-for-like comparison as well: the same OpenCL path-tracing kernel on the flat BVH
// and on the compact scene (opencl:0 against opencl:0:compact=1), alternately `reps`
// times, each frame's busy time as the device measures it around its kernel launches
// (median reported), the scene buffers each device uploaded, and the PSNR between them.
//
// Usage: compact_bench [--res WxH] [--spp N] [--bounces N] [--reps N]
//                      [--subdivide K] [--opencl] SCENE...
// --subdivide K splits every triangle of the scenes into 4^K (a generated large mesh).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "core/image_metrics.h"
#include "render/compact_scene.h"
#include "render/default_view.h"
#include "render/path_tracer.h"
#include "scene/builders.h"
#include "scene/loaders.h"

#ifdef MULTIRAY_HAS_OPENCL
#include "device/opencl/opencl_device.h"
#include "device/opencl/opencl_platform.h"
#include "device/work_list.h"
#endif

using namespace multiray;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Each triangle into four (midpoints), flat: attributes interpolated linearly.
Scene subdivide(const Scene& s) {
  Scene out = s;
  out.indices.clear();
  out.material_ids.clear();
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    uint32_t v[6];
    for (int k = 0; k < 3; ++k) v[k] = s.indices[3 * t + k];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % 3];
      v[3 + k] = uint32_t(out.positions.size());
      out.positions.push_back((out.positions[a] + out.positions[b]) * 0.5f);
      if (!out.normals.empty()) out.normals.push_back(normalize(out.normals[a] + out.normals[b]));
      if (!out.uvs.empty())
        out.uvs.push_back(
            Vec2{(out.uvs[a].x + out.uvs[b].x) * 0.5f, (out.uvs[a].y + out.uvs[b].y) * 0.5f});
    }
    const uint32_t tris[4][3] = {
        {v[0], v[3], v[5]}, {v[3], v[1], v[4]}, {v[5], v[4], v[2]}, {v[3], v[4], v[5]}};
    for (const auto& tri : tris) {
      out.indices.insert(out.indices.end(), tri, tri + 3);
      out.material_ids.push_back(s.material_ids[t]);
    }
  }
  return out;
}

struct Options {
  int w = 480, h = 270, spp = 4, bounces = 4, reps = 3, subdivide = 0;
  bool opencl = false;
};

#ifdef MULTIRAY_HAS_OPENCL
// One whole frame on `device`; returns its busy time (ms, measured by the device).
double render_frame(Device& device, const ViewSetup& view, const RenderSettings& settings,
                    Framebuffer& out) {
  ListWorkSource source({WorkItem{{0, 0, view.width, view.height}, 0}});
  std::vector<Framebuffer> outputs{Framebuffer(view.width, view.height)};
  const FrameJob job{{view}, settings, &outputs};
  const DeviceReport r = device.render(job, source, 0);
  if (r.failed) throw std::runtime_error(r.error);
  out = outputs[0];
  return r.busy_ms;
}

nlohmann::json opencl_comparison(const Scene& scene, const ViewSetup& view,
                                 const RenderSettings& settings, const Options& o) {
  if (list_opencl_devices().empty()) return {{"skipped", "no OpenCL device"}};
  SceneCache cache(scene);
  OpenClDevice flat(cache, {}, "opencl:0");
  OpenClDevice compact(cache, {.compact = true}, "opencl:0:compact=1");
  Framebuffer a(view.width, view.height), b(view.width, view.height);
  std::vector<double> tf, tc;
  for (int r = 0; r < o.reps; ++r) {
    tf.push_back(render_frame(flat, view, settings, a));
    tc.push_back(render_frame(compact, view, settings, b));
  }
  return {{"device", flat.info().name},
          {"scene_bytes",
           {{"flat", flat.info().scene_bytes}, {"compact", compact.info().scene_bytes}}},
          {"scene_ratio", double(flat.info().scene_bytes) / double(compact.info().scene_bytes)},
          {"busy_ms", {{"flat", median(tf)}, {"compact", median(tc)}}},
          {"render_time_increase", median(tc) / median(tf) - 1.0},
          {"psnr_db", image_error(b, a).psnr_db}};
}
#else
nlohmann::json opencl_comparison(const Scene&, const ViewSetup&, const RenderSettings&,
                                 const Options&) {
  return {{"skipped", "built without OpenCL"}};
}
#endif

nlohmann::json run(const std::string& path, const Options& o) {
  Scene scene = load_scene(path);
  for (int k = 0; k < o.subdivide; ++k) scene = subdivide(scene);
  bool lit = max_component(scene.environment) > 0;
  for (const Material& m : scene.materials) lit |= max_component(m.emission) > 0;
  if (!lit) scene.environment = Vec3(1.0f);
  set_fast_float_mode();
  const RenderScene full(scene);
  const CompactScene compact = build_compact_scene(scene);
  const RenderScene small(scene, &compact);
  const SceneBytes fb = full_precision_bytes(scene, compact.bvh.nodes.size());
  const SceneBytes cb = compact_bytes(compact);

  ViewSetup view;
  view.camera = choose_default_camera(full, float(o.w) / float(o.h), scene.up);
  view.width = o.w, view.height = o.h;
  const RenderSettings settings{.spp = o.spp, .max_bounces = o.bounces};
  const PathTracer pf(full), pc(small);
  Framebuffer a(o.w, o.h), b(o.w, o.h);
  std::vector<double> tf, tc;
  for (int r = 0; r < o.reps; ++r) {
    Stopwatch s1;
    pf.render_rect(view, settings, {0, 0, o.w, o.h}, a);
    tf.push_back(s1.elapsed_ms());
    Stopwatch s2;
    pc.render_rect(view, settings, {0, 0, o.w, o.h}, b);
    tc.push_back(s2.elapsed_ms());
  }
  const ImageError err = image_error(b, a);
  nlohmann::json j = {
      {"scene", path},
      {"subdivide", o.subdivide},
      {"triangles", scene.triangle_count()},
      {"vertices", scene.positions.size()},
      {"normals", !scene.normals.empty()},
      {"uvs", !scene.uvs.empty()},
      {"full_bytes", {{"mesh", fb.mesh}, {"structure", fb.structure}, {"both", fb.total()}}},
      {"compact_bytes", {{"mesh", cb.mesh}, {"structure", cb.structure}, {"both", cb.total()}}},
      {"ratio",
       {{"mesh", double(fb.mesh) / double(cb.mesh)},
        {"structure", double(fb.structure) / double(cb.structure)},
        {"both", double(fb.total()) / double(cb.total())}}},
      {"cpu_device_bytes", {{"embree", full.bytes()}, {"compact", small.bytes()}}},
      {"cpu_device_ratio", double(full.bytes()) / double(small.bytes())},
      {"render_ms", {{"embree", median(tf)}, {"compact", median(tc)}}},
      {"render_time_increase", median(tc) / median(tf) - 1.0},
      {"psnr_db", err.psnr_db},
      {"settings",
       {{"res", fmt::format("{}x{}", o.w, o.h)},
        {"spp", o.spp},
        {"bounces", o.bounces},
        {"reps", o.reps}}}};
  if (o.opencl) {
    j["opencl"] = opencl_comparison(scene, view, settings, o);
    const nlohmann::json& c = j["opencl"];
    if (c.contains("skipped"))
      fmt::print(stderr, "opencl: skipped ({})\n", c["skipped"].get<std::string>());
    else
      fmt::print(
          stderr,
          "opencl: buffers {:.2f}x smaller, busy {:.0f} -> {:.0f} ms ({:+.0f}%), PSNR {:.1f} dB\n",
          c["scene_ratio"].get<double>(), c["busy_ms"]["flat"].get<double>(),
          c["busy_ms"]["compact"].get<double>(), 100 * c["render_time_increase"].get<double>(),
          c["psnr_db"].get<double>());
  }
  fmt::print(stderr,
             "{:<40} {:>9} tris  mesh {:.2f}x  structure {:.2f}x  both {:.2f}x  (cpu device "
             "{:.2f}x)  time {:+.0f}%  PSNR {:.1f} dB\n",
             path.substr(path.find_last_of('/') + 1) +
                 (o.subdivide ? fmt::format(" x4^{}", o.subdivide) : ""),
             scene.triangle_count(), j["ratio"]["mesh"].get<double>(),
             j["ratio"]["structure"].get<double>(), j["ratio"]["both"].get<double>(),
             j["cpu_device_ratio"].get<double>(), 100 * j["render_time_increase"].get<double>(),
             err.psnr_db);
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    try {
      if (a == "--res") {
        if (std::sscanf(next().c_str(), "%dx%d", &o.w, &o.h) != 2 || o.w < 1 || o.h < 1 ||
            o.w > 8192 || o.h > 8192)
          throw std::invalid_argument("--res wants WxH");
      } else if (a == "--spp") {
        o.spp = std::clamp(std::stoi(next()), 1, 4096);
      } else if (a == "--bounces") {
        o.bounces = std::clamp(std::stoi(next()), 0, 64);
      } else if (a == "--reps") {
        o.reps = std::clamp(std::stoi(next()), 1, 100);
      } else if (a == "--opencl") {
        o.opencl = true;
      } else if (a == "--subdivide") {
        o.subdivide = std::clamp(std::stoi(next()), 0, 6);
      } else {
        scenes.push_back(a);
      }
    } catch (const std::exception& e) {
      fmt::print(stderr, "compact_bench: {}: {}\n", a, e.what());
      return 2;
    }
  }
  if (scenes.empty()) {
    fmt::print(stderr,
               "usage: compact_bench [--res WxH] [--spp N] [--bounces N] [--reps N] "
               "[--subdivide K] [--opencl] SCENE...\n");
    return 2;
  }
  for (const std::string& s : scenes) {
    try {
      fmt::print("{}\n", run(s, o).dump());
      std::fflush(stdout);
    } catch (const std::exception& e) {
      fmt::print(stderr, "compact_bench: {}: {}\n", s, e.what());
      return 1;
    }
  }
  return 0;
}
