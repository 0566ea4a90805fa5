// Spatial reprojection with hole filling (issue 13; Leria et al. §6.3, Tables 1-2) against
// full path tracing of every view. For each grid it renders the same frames of a camera
// path on the same devices and balancer: every view path-traced (seed 0), again with seed 1
// (how far two correct renders are apart: the noise floor), and reprojected once per
// reference spacing (0: the centre view alone, as the paper; K: every K-th view from the
// centre; the references and the holes path-traced, seed 0). Also once: the centre view
// alone (what "a grid costs little more than one view" compares with).
//
// Frame time is the engine's (devices started -> all finished, steady_clock on the host
// around the devices' work); host set-up (the references' G-buffers and the reprojection)
// is reported apart and added in `total`. Image error is the mean over the frames and the
// views that are not references of image_error() (MSE and PSNR over clamped linear RGB);
// moved/seed compares the squared error over the reprojected pixels alone with the other
// seed's over the same pixels. Exit 1 when a hole or a reference differs in any bit from
// the full render's pixel.
//
//   reprojection_bench SCENE [--res 320x180] [--spp 1] [--bounces 8] [--spacing 0.2]
//       [--grids 3x3,5x5,9x9] [--reference-spacings 0,3] [--frames 10]
//       [--camera-path FILE] [--devices SPEC] [--balancer dlb] [--json FILE] [--images DIR]
//       [--holes-only]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_io.h"
#include "core/image_metrics.h"
#include "engine/session.h"
#include "render/gbuffer.h"
#include "render/path_tracer.h"
#include "run/run.h"

namespace multiray {
namespace {

// What one run of a grid kept: per frame the images and times.
struct GridRun {
  std::vector<std::vector<Framebuffer>> images;  // [frame][view]
  std::vector<std::shared_ptr<const ReprojectedFrame>> reprojection;
  std::vector<double> frame_ms, host_ms;
  double mean(const std::vector<double>& v) const {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0 : s / double(v.size());
  }
};

class Keeper : public FrameObserver {
 public:
  explicit Keeper(GridRun& run) : run_(run) {}
  void before_frame(int, const FrameInput& in) override {
    run_.reprojection.push_back(in.reprojection);
  }
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    run_.images.push_back(r->images);
    run_.frame_ms.push_back(r->record.frame_ms);
    run_.host_ms.push_back(r->sampling_ms);
  }

 private:
  GridRun& run_;
};

struct Config {
  std::string scene, res = "320x180", grids = "3x3,5x5,9x9", camera_path = "fixed";
  std::string devices = "cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.5";
  std::string balancer = "dlb", json, images;
  std::string reference_spacings = "0";
  int spp = 1, bounces = 8, frames = 10;
  bool holes_only = false;
  float spacing = 0.2f;
};

GridRun run_grid(const multiray::Run& s, const Config& c, CameraRig rig, Sampling mode,
                 uint64_t seed, int reference_spacing = 0) {
  SamplingSetup sampling;
  sampling.mode = mode;
  sampling.reproject_spp = c.spp;
  sampling.reference_spacing = reference_spacing;
  FrameViews views(rig, s.res.width, s.res.height, sampling, &s.scenes->embree());
  RenderSettings settings = s.settings;
  settings.seed = seed;
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  lanes.push_back(balance::make_balancer(c.balancer, int(s.devices.size())));
  Session session(s.device_ptrs(), std::move(lanes), std::move(views), s.path, settings);
  GridRun run;
  Keeper keeper(run);
  session.run(0, c.frames, keeper);
  return run;
}

// Bits of the holes and the centre that differ from the full render (must be none).
size_t mismatches(const GridRun& full, const GridRun& r) {
  size_t bad = 0;
  for (size_t f = 0; f < r.images.size(); ++f) {
    const ReprojectedFrame& rf = *r.reprojection[f];
    for (size_t v = 0; v < r.images[f].size(); ++v)
      for (size_t i = 0; i < r.images[f][v].pixels.size(); ++i) {
        const bool traced = rf.is_reference(v) || rf.maps[v].source[i] == ReprojectionMap::kHole;
        bad += traced && std::memcmp(&r.images[f][v].pixels[i], &full.images[f][v].pixels[i],
                                     sizeof(Vec3)) != 0;
      }
  }
  return bad;
}

// Mean image error of `x` against `full` over the frames and the views that `r` did not
// path-trace in full (its references are excluded for every x alike).
ImageError error(const GridRun& full, const GridRun& x, const GridRun& r) {
  ImageError e{0, 0, 0};
  int n = 0;
  for (size_t f = 0; f < x.images.size(); ++f)
    for (size_t v = 0; v < x.images[f].size(); ++v) {
      if (r.reprojection[f]->is_reference(v)) continue;
      const ImageError one = image_error(x.images[f][v], full.images[f][v]);
      e.mse += one.mse, e.psnr_db += one.psnr_db, e.ssim += one.ssim, ++n;
    }
  e.mse /= n, e.psnr_db /= n, e.ssim /= n;
  return e;
}

// Mean squared error (clamped linear RGB, as image_error) of `r` and of `other` against
// `full` over the pixels that `moved` took from the centre, in every frame and view: the
// error of reprojected pixels against that of a full render with another seed there.
std::pair<double, double> moved_pixel_mse(const GridRun& full, const GridRun& other,
                                          const GridRun& moved) {
  const auto sq = [](const Vec3& a, const Vec3& b) {
    double e = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = std::clamp(double(a[c]), 0.0, 1.0) - std::clamp(double(b[c]), 0.0, 1.0);
      e += d * d;
    }
    return e / 3;
  };
  double e_moved = 0, e_other = 0;
  size_t n = 0;
  for (size_t f = 0; f < moved.images.size(); ++f) {
    const ReprojectedFrame& rf = *moved.reprojection[f];
    for (size_t v = 0; v < moved.images[f].size(); ++v) {
      if (rf.is_reference(v)) continue;
      for (size_t i = 0; i < rf.maps[v].source.size(); ++i) {
        if (rf.maps[v].source[i] == ReprojectionMap::kHole) continue;
        const Vec3& ref = full.images[f][v].pixels[i];
        e_moved += sq(moved.images[f][v].pixels[i], ref);
        e_other += sq(other.images[f][v].pixels[i], ref);
        ++n;
      }
    }
  }
  return {n ? e_moved / double(n) : 0, n ? e_other / double(n) : 0};
}

// The last frame's first view that is not a reference: full, reprojected, and with its
// holes in red (files GRID_viewV_*.png).
void write_images(const std::string& dir, const std::string& grid, const GridRun& full,
                  const GridRun& r) {
  const ReprojectedFrame& rf = *r.reprojection.back();
  size_t v = 0;
  while (rf.is_reference(v)) ++v;
  Framebuffer holes = r.images.back()[v];
  const ReprojectionMap& m = rf.maps[v];
  for (size_t i = 0; i < m.source.size(); ++i)
    if (m.source[i] == ReprojectionMap::kHole) holes.pixels[i] = Vec3(1, 0, 0);
  const std::string base = fmt::format("{}/{}_view{}", dir, grid, v);
  write_png(base + "_full.png", full.images.back()[v]);
  write_png(base + "_reprojected.png", r.images.back()[v]);
  write_png(base + "_holes.png", holes);
}

// One entry of --grids, "KxL".
CameraRig parse_grid(const std::string& grid, float spacing) {
  int columns = 0, rows = 0;
  char end = 0;
  if (std::sscanf(grid.c_str(), "%dx%d%c", &columns, &rows, &end) != 2 || columns < 1 ||
      rows < 1 || columns * rows < 2 || columns > 64 || rows > 64)
    throw InputError("--grids: '" + grid + "' must be KxL with 2..4096 views");
  return CameraRig::grid(columns, rows, spacing);
}

// One entry of --reference-spacings: 0..64.
int parse_spacing(const std::string& text) {
  const double k = to_number(text, "--reference-spacings");
  if (k < 0 || k > 64 || k != std::floor(k))
    throw InputError("--reference-spacings: '" + text + "' must be a whole number in 0..64");
  return int(k);
}

// --holes-only: per grid, the hole fraction and what the holes see, from each target
// view's own G-buffer: no surface (sky: one ray each), a surface outside every reference's
// image (the border), or a surface no reference sees (a disocclusion). No path tracing.
void measure_holes(const multiray::Run& s, const Config& c, CameraRig rig, int reference_spacing) {
  SamplingSetup sampling;
  sampling.mode = Sampling::Reprojected;
  sampling.reproject_spp = c.spp;
  sampling.reference_spacing = reference_spacing;
  const FrameViews views(rig, s.res.width, s.res.height, sampling, &s.scenes->embree());
  double holes = 0, sky = 0, border = 0, pixels = 0;
  for (int f = 0; f < c.frames; ++f) {
    const FrameInput in = views.make(f, s.path.at(f));
    const ReprojectedFrame& rf = *in.reprojection;
    for (size_t v = 0; v < in.views.size(); ++v) {
      if (rf.is_reference(v)) continue;
      const ViewSetup& view = in.views[v];
      const GBuffer g = render_gbuffer(s.scenes->embree(), view);
      const PinholeCamera cam(view.camera, view.width, view.height);
      const ReprojectionMap& m = in.reprojection->maps[v];
      for (size_t i = 0; i < m.source.size(); ++i) {
        if (m.source[i] != ReprojectionMap::kHole) continue;
        holes += 1;
        if (!std::isfinite(g.depth[i])) {
          sky += 1;
          continue;
        }
        const float x = float(i % size_t(view.width)) + 0.5f,
                    y = float(i / size_t(view.width)) + 0.5f;
        const Ray r = cam.ray(x, y);
        float px, py;
        const Vec3 p = r.org + r.dir * (g.depth[i] / dot(r.dir, cam.forward));
        bool seen = false;  // inside some reference's image
        for (uint32_t k : rf.references)
          seen |= project_to_image(in.views[k], p, px, py) && px >= 0 && py >= 0 &&
                  px < float(view.width) && py < float(view.height);
        border += !seen;
      }
      pixels += double(m.source.size());
    }
  }
  const double other = std::max(1.0, holes);
  fmt::print(
      "{:>5} refs every {}: holes {:5.1f}% of the other views' pixels: sky {:4.1f}%, outside "
      "the references' images {:4.1f}%, disoccluded {:4.1f}%\n",
      fmt::format("{}x{}", rig.columns, rig.rows), reference_spacing, 100 * holes / pixels,
      100 * sky / other, 100 * border / other, 100 * (holes - sky - border) / other);
}

// One row of the table: `r` against the full render and the other seed's.
nlohmann::json compare(const std::string& label, const GridRun& full, const GridRun& other,
                       const GridRun& r, double one_view_ms) {
  const ImageError e = error(full, r, r), floor = error(full, other, r);
  double holes = 0;
  for (const auto& rf : r.reprojection) holes += rf->hole_fraction() / double(r.images.size());
  const double full_ms = full.mean(full.frame_ms), r_ms = r.mean(r.frame_ms),
               host_ms = r.mean(r.host_ms), total = r_ms + host_ms;
  const size_t bad = mismatches(full, r);
  const auto [mse_moved, mse_moved_seed] = moved_pixel_mse(full, other, r);
  fmt::print(
      "{:>16} {:>10.1f} {:>10.1f} {:>9.1f} {:>7.2f}x {:>7.1f}% {:>6.2f}x {:>9.2f} {:>9.2f} "
      "{:>9.2f}x{}\n",
      label, full_ms, r_ms, host_ms, full_ms / total, 100 * holes, total / one_view_ms, e.psnr_db,
      floor.psnr_db, mse_moved / mse_moved_seed,
      bad ? fmt::format("  {} traced pixels differ from the full render!", bad) : "");
  return {{"grid", label},
          {"full_ms", full_ms},
          {"reprojected_ms", r_ms},
          {"host_ms", host_ms},
          {"speedup", full_ms / total},
          {"hole_fraction", holes},
          {"cost_in_views", total / one_view_ms},
          {"mse", e.mse},
          {"psnr_db", e.psnr_db},
          {"ssim", e.ssim},
          {"seed_mse", floor.mse},
          {"seed_psnr_db", floor.psnr_db},
          {"seed_ssim", floor.ssim},
          {"moved_mse", mse_moved},
          {"moved_seed_mse", mse_moved_seed},
          {"traced_mismatches", bad}};
}

int run(const Config& c) {
  multiray::RunConfig o;
  o.scene_path = c.scene;
  o.resolution = c.res;
  o.spp = c.spp;
  o.bounces = c.bounces;
  o.frames = c.frames;
  o.camera_path = c.camera_path;
  o.devices = c.devices;
  const multiray::Run s = build_run(o);
  if (c.holes_only) {
    for (const std::string& grid : split(c.grids, ','))
      for (const std::string& k : split(c.reference_spacings, ','))
        measure_holes(s, c, parse_grid(grid, c.spacing), parse_spacing(k));
    return 0;
  }
  for (const auto& d : s.devices) fmt::print("device {}\n", d->info().name);
  const GridRun alone =
      run_grid(s, c, CameraRig::single(), Sampling::Uniform, s.settings.seed);  // one view
  fmt::print("one view: {:.1f} ms a frame\n", alone.mean(alone.frame_ms));
  fmt::print("{:>16} {:>10} {:>10} {:>9} {:>8} {:>8} {:>7} {:>9} {:>9} {:>10}\n", "grid",
             "full ms", "reproj ms", "host ms", "speedup", "holes", "x view", "PSNR dB", "seed dB",
             "moved/seed");
  nlohmann::json out = {{"scene", s.scene->name}, {"res", c.res},
                        {"spp", c.spp},           {"bounces", c.bounces},
                        {"frames", c.frames},     {"devices", c.devices},
                        {"balancer", c.balancer}, {"one_view_ms", alone.mean(alone.frame_ms)}};
  int status = 0;
  for (const std::string& grid : split(c.grids, ',')) {
    const CameraRig rig = parse_grid(grid, c.spacing);
    const GridRun full = run_grid(s, c, rig, Sampling::Uniform, s.settings.seed);
    const GridRun other = run_grid(s, c, rig, Sampling::Uniform, s.settings.seed + 1);
    for (const std::string& spacing : split(c.reference_spacings, ',')) {
      const int k = parse_spacing(spacing);
      const GridRun r = run_grid(s, c, rig, Sampling::Reprojected, s.settings.seed, k);
      const std::string label = k ? fmt::format("{} refs every {}", grid, k) : grid;
      out["grids"].push_back(compare(label, full, other, r, alone.mean(alone.frame_ms)));
      out["grids"].back()["reference_spacing"] = k;
      out["grids"].back()["references"] = r.reprojection[0]->references.size();
      if (!c.images.empty()) write_images(c.images, k ? grid + "_every" + spacing : grid, full, r);
      if (out["grids"].back()["traced_mismatches"] != 0) status = 1;
    }
  }
  if (!c.json.empty()) write_file_atomically(c.json, out.dump(2) + "\n");
  return status;
}

}  // namespace
}  // namespace multiray

int main(int argc, char** argv) {
  multiray::Config c;
  CLI::App app{"Spatial reprojection with hole filling against full path tracing of every view"};
  app.add_option("scene", c.scene, "Scene file (omitted: the Cornell box)");
  app.add_option("--res", c.res, "Image size of every view")->capture_default_str();
  app.add_option("--spp", c.spp, "Samples per pixel (1..255)")->capture_default_str();
  app.add_option("--bounces", c.bounces, "Bounces per path")->capture_default_str();
  app.add_option("--spacing", c.spacing, "Distance between views")->capture_default_str();
  app.add_option("--grids", c.grids, "Grids to measure, KxL,...")->capture_default_str();
  app.add_option("--frames", c.frames, "Frames per run")->capture_default_str();
  app.add_option("--camera-path", c.camera_path, "fixed | orbit | FILE.json")
      ->capture_default_str();
  app.add_option("--devices", c.devices, "Devices (as multiray's --devices)")
      ->capture_default_str();
  app.add_option("--balancer", c.balancer, "Balancer spec")->capture_default_str();
  app.add_option("--json", c.json, "Write the results here");
  app.add_option("--images", c.images, "Write the last frame's view 0 here (existing folder)");
  app.add_option("--reference-spacings", c.reference_spacings,
                 "Reference spacings to measure, K,... (0: the centre view alone)")
      ->capture_default_str();
  app.add_flag("--holes-only", c.holes_only,
               "Only count holes (and the share that is sky) per grid; no path tracing");
  CLI11_PARSE(app, argc, argv);
  try {
    if (c.spp < 1 || c.spp > 255) throw multiray::InputError("--spp must be in 1..255");
    if (c.frames < 1 || c.frames > 100000) throw multiray::InputError("--frames: 1..100000");
    return multiray::run(c);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reprojection_bench: %s\n", e.what());
    return 2;
  }
}
