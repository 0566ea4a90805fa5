// The noise of the viewer's refined image (app/viewer/refinement.h): the mean of N frames
// of a still camera, each of S samples per pixel, rendered as `multiray view` renders them,
// by a Session, with progressive sampling (each frame continues the first one's sample
// sequence, Session::set_progressive) or without (each frame begins its own, as before).
// An image quality measurement, not a timing: the figure is the variance of the mean
// image, estimated from two runs that differ only in their seed (bench/noise_pair.cpp's
// estimator, (A - B)^2 / 2 averaged over pixels and channels), so no reference enters it.
//
// Usage: progressive_noise [SCENE] [--res WxH] [--frame-spp S] [--frames N,N,...]
// Default scene: the Dabrovic Sponza from ../shared/data (inside the atrium, as
// bench_throughput looks), else the built-in Cornell box. Prints one JSON object a line
// (frames, frame_spp, variance_independent, variance_progressive, ratio) and a table on
// stderr. Exits 2 with one line on a bad argument.
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "balance/balancer.h"
#include "bench_scene.h"
#include "device/cpu/cpu_device.h"
#include "engine/session.h"
#include "scene/builders.h"
#include "scene/loaders.h"

using namespace multiray;

namespace {

struct Mean : FrameObserver {
  std::vector<Vec3> sum;
  int frames = 0;
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    const Framebuffer& img = r->images.at(0);
    if (sum.empty()) sum.assign(img.pixels.size(), Vec3(0.0f));
    for (size_t i = 0; i < sum.size(); ++i) sum[i] = sum[i] + img.pixels[i];
    ++frames;
  }
};

// The mean image of `frames` frames of `spp` samples, seeded by `seed`.
std::vector<Vec3> refined(SceneCache& cache, const Camera& camera, int w, int h, int spp,
                          int frames, bool progressive, uint64_t seed) {
  CpuDevice cpu(cache, {}, "cpu");
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  lanes.push_back(balance::make_balancer("queue", 1));
  Session session({&cpu}, std::move(lanes), FrameViews(CameraRig::single(), w, h, {}),
                  CameraPath::fixed(camera), RenderSettings{.spp = spp, .seed = seed});
  session.set_progressive(progressive);
  Mean mean;
  session.run(0, frames, mean);
  for (Vec3& p : mean.sum) p = p * (1.0f / float(frames));
  return mean.sum;
}

double variance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double v = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const Vec3 d = a[i] - b[i];
    v += 0.5 * (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
  }
  return v / (3.0 * double(a.size()));
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = bench::default_bench_scene();
  bool given = false;  // a SCENE on the command line: refused if missing, no fallback
  int w = 320, h = 180, spp = 1;
  std::vector<int> counts = {4, 16, 64};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const std::string v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--res") {
      if (std::sscanf(v.c_str(), "%dx%d", &w, &h) != 2 || w < 1 || h < 1 || w > 4096 || h > 4096)
        return std::fprintf(stderr, "progressive_noise: --res wants WxH\n"), 2;
      ++i;
    } else if (a == "--frame-spp") {
      spp = std::atoi(v.c_str());
      if (spp < 1 || spp > 1024)
        return std::fprintf(stderr, "progressive_noise: --frame-spp wants 1..1024\n"), 2;
      ++i;
    } else if (a == "--frames") {
      counts.clear();
      std::stringstream list(v);
      for (std::string n; std::getline(list, n, ',');) counts.push_back(std::atoi(n.c_str()));
      if (counts.empty()) counts.push_back(0);  // refused below, with the others
      for (int n : counts)
        if (n < 1 || n > 4096)
          return std::fprintf(stderr, "progressive_noise: --frames wants counts 1..4096\n"), 2;
      ++i;
    } else if (a == "--help" || a == "-h") {
      std::printf(
          "usage: progressive_noise [SCENE] [--res WxH] [--frame-spp S] [--frames N,N,...]\n"
          "The variance of the mean of N frames of a still camera (the viewer's refined\n"
          "image), with frames that each begin their own sample sequence and with frames\n"
          "that continue one (progressive), from two runs that differ only in their seed.\n"
          "Default: Sponza from ../shared/data (else the Cornell box), 320x180, 1 spp a\n"
          "frame, 4,16,64 frames. JSON lines on stdout, a table on stderr.\n");
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      return std::fprintf(stderr, "progressive_noise: unknown option %s\n", a.c_str()), 2;
    } else {
      path = a, given = true;
    }
  }
  std::optional<Scene> loaded = bench::load_bench_scene("progressive_noise", path, given);
  if (!loaded) return 1;
  Scene& scene = *loaded;
  const Camera camera = bench::bench_camera(scene, float(w) / float(h));
  bench::light_if_unlit(scene);
  SceneCache cache(scene);
  fmt::print(stderr, "{} {}x{}, {} spp a frame: variance of the mean of N frames\n", scene.name, w,
             h, spp);
  fmt::print(stderr, "{:>6} {:>16} {:>16} {:>8}\n", "frames", "independent", "progressive",
             "ratio");
  for (int n : counts) {
    double var[2];
    for (int progressive = 0; progressive < 2; ++progressive)
      var[progressive] = variance(refined(cache, camera, w, h, spp, n, progressive, 1),
                                  refined(cache, camera, w, h, spp, n, progressive, 2));
    fmt::print(stderr, "{:>6} {:>16.6g} {:>16.6g} {:>8.2f}\n", n, var[0], var[1], var[0] / var[1]);
    fmt::print(
        "{{\"scene\": \"{}\", \"res\": \"{}x{}\", \"frames\": {}, \"frame_spp\": {}, "
        "\"variance_independent\": {:.8g}, \"variance_progressive\": {:.8g}, \"ratio\": "
        "{:.4f}}}\n",
        scene.name, w, h, n, spp, var[0], var[1], var[0] / var[1]);
    std::fflush(stdout);
  }
  return 0;
}
