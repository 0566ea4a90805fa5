// Path-tracer throughput against raw Embree on the same rays (issue 2's goal: >= 60%).
//
// 1. Render the frame once with a ray log, single-threaded, to capture every ray the path
//    tracer traces (closest-hit and shadow rays).
// 2. Time, alternately and `reps` times each, (a) the path tracer rendering that frame
//    without the log, (b) Embree alone intersecting the logged rays one at a time
//    (rtcIntersect1 for closest-hit, rtcOccluded1 for shadow rays: the baseline)
//    and (c) the same with the shadow rays eight at a time through
//    Accel::occluded_batch, as the path tracer sends them. All run on one thread of this
//    process; times are wall-clock around each pass (steady_clock).
// 3. Report paths/s and rays/s of each and the ratios of the medians.
//
// Usage: bench_throughput [SCENE] [--res WxH] [--spp N] [--bounces N] [--reps N]
// Default scene: the Dabrovic Sponza from ../shared/data, else the built-in Cornell box.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "bench_scene.h"
#include "core/clock.h"
#include "render/path_tracer.h"
#include "scene/builders.h"
#include "scene/loaders.h"

using namespace multiray;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  std::string scene_path = bench::default_bench_scene();
  int w = 1280, h = 720, spp = 1, bounces = 8, reps = 3;
  bool scene_given = false;
  // A whole number in [lo, hi] from `v`, or -1 (refused by the caller in one line).
  const auto number = [](const std::string& v, int lo, int hi) {
    char* end = nullptr;
    const long n = std::strtol(v.c_str(), &end, 10);
    return v.empty() || *end != '\0' || n < lo || n > hi ? -1 : int(n);
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const std::string v = i + 1 < argc ? argv[i + 1] : "";
    int* target = a == "--spp"       ? &spp
                  : a == "--bounces" ? &bounces
                  : a == "--reps"    ? &reps
                                     : nullptr;
    if (a == "--res") {
      if (std::sscanf(v.c_str(), "%dx%d", &w, &h) != 2 || w < 1 || h < 1 || w > 8192 || h > 8192)
        return std::fprintf(stderr, "bench_throughput: --res wants WxH (1..8192 each)\n"), 2;
      ++i;
    } else if (target) {
      const int hi = a == "--spp" ? 1024 : a == "--bounces" ? 64 : 1000;
      if ((*target = number(v, 1, hi)) < 0)
        return std::fprintf(stderr, "bench_throughput: %s wants a whole number 1..%d\n", a.c_str(),
                            hi),
               2;
      ++i;
    } else if (a == "--help" || a == "-h") {
      std::printf(
          "usage: bench_throughput [SCENE] [--res WxH] [--spp N] [--bounces N] [--reps N]\n"
          "The path tracer against raw Embree on the same rays, one thread (issues 2 and 35):\n"
          "one frame is rendered with a ray log, then the path tracer and Embree alone on the\n"
          "logged rays are timed alternately (medians of N reps). Default: Sponza from\n"
          "../shared/data (else the built-in Cornell box), 1280x720, 1 spp, 8 bounces, 3 reps.\n");
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      return std::fprintf(stderr, "bench_throughput: unknown option %s (see --help)\n", a.c_str()),
             2;
    } else {
      scene_path = a, scene_given = true;
    }
  }
  std::optional<Scene> loaded =
      bench::load_bench_scene("bench_throughput", scene_path, scene_given);
  if (!loaded) return 1;
  Scene& scene = *loaded;
  bench::light_if_unlit(scene);
  set_fast_float_mode();
  const RenderScene rs(scene);
  const PathTracer pt(rs);
  ViewSetup view;
  view.camera = bench::bench_camera(scene, float(w) / float(h));
  view.width = w, view.height = h;
  RenderSettings settings{.spp = spp, .max_bounces = bounces};
  Framebuffer fb(w, h);

  RayLog log;
  pt.render_rect_logged(view, settings, {0, 0, w, h}, fb, &log);
  const double paths = double(w) * h * spp;
  const double rays = double(log.closest.size() + log.shadow.size());
  fmt::print("scene {} ({} triangles), {}x{}, {} spp, {} bounces, 1 thread\n", scene.name,
             scene.triangle_count(), w, h, spp, bounces);
  fmt::print("rays per frame: {} closest-hit + {} shadow = {:.2f} per path\n", log.closest.size(),
             log.shadow.size(), rays / paths);

  std::vector<double> pt_ms, raw_ms, packet_ms;
  std::vector<uint8_t> blocked(log.shadow.size());
  volatile size_t sink = 0;
  for (int r = 0; r < reps; ++r) {
    Stopwatch a;
    pt.render_rect(view, settings, {0, 0, w, h}, fb);
    pt_ms.push_back(a.elapsed_ms());
    Stopwatch b;
    size_t hits = 0;
    Hit hit;
    for (const Ray& ray : log.closest) hits += rs.accel.intersect(ray, hit);
    for (const Ray& ray : log.shadow) hits += rs.accel.occluded(ray);
    raw_ms.push_back(b.elapsed_ms());
    Stopwatch c;
    for (const Ray& ray : log.closest) hits += rs.accel.intersect(ray, hit);
    rs.accel.occluded_batch(log.shadow.data(), log.shadow.size(), blocked.data());
    packet_ms.push_back(c.elapsed_ms());
    sink = sink + hits + blocked[0];
  }
  const double pt_med = median(pt_ms), raw_med = median(raw_ms), packet_med = median(packet_ms);
  fmt::print("path tracer : {:8.1f} ms median of {}  {:6.3f} Mpaths/s  {:6.3f} Mrays/s\n", pt_med,
             reps, paths / pt_med / 1e3, rays / pt_med / 1e3);
  fmt::print("raw Embree  : {:8.1f} ms median of {}                    {:6.3f} Mrays/s\n", raw_med,
             reps, rays / raw_med / 1e3);
  fmt::print("raw Embree, shadow rays 8 at a time: {:8.1f} ms median of {}  {:6.3f} Mrays/s\n",
             packet_med, reps, rays / packet_med / 1e3);
  fmt::print("ratio (path tracer rays/s / raw Embree rays/s): {:.2f}\n", raw_med / pt_med);
  fmt::print("ratio against raw Embree with the shadow rays 8 at a time: {:.2f}\n",
             packet_med / pt_med);
  return 0;
}
