#include "render/path_tracer.h"

#include <cmath>
#include <stdexcept>

#include "render/path_state.h"

namespace multiray {

PinholeCamera::PinholeCamera(const Camera& cam, int width, int height)
    : eye(cam.eye), forward(normalize(cam.target - cam.eye)) {
  right = normalize(cross(forward, cam.up));
  up = cross(right, forward);
  const float tan_half = std::tan(0.5f * cam.fov_y_deg * kPi / 180.0f);
  scale_y = tan_half;
  scale_x = tan_half * float(width) / float(height);
  const auto f4 = [](Vec3 v) { return mr_float4{v.x, v.y, v.z, 0.0f}; };
  block_ = CameraBlock{f4(eye), f4(forward), f4(right), f4(up),
                       mr_float4{scale_x, scale_y, 2.0f / float(width), 2.0f / float(height)}};
}

PathTracer::PathTracer(const RenderScene& rs) : rs_(rs) {
  const Bounds3 b = rs.scene.bounds();
  eps_ = 2e-5f * std::max(1.0f, max_component(b.extent()));
}

void PathTracer::step(WavefrontPath& p, const Hit* hit, const SceneData& sd,
                      const RenderSettings& settings, const TexFootprint* base_footprint) const {
  AovSample* aov = settings.feature_buffers ? &p.aov : nullptr;
  if (!hit) return path_escape(&sd, &p, aov);
  if (hit->prim == kCatcherPrim) return catcher_step(p, *hit, sd, settings);
  if (p.depth == 0) p.kind = SampleKind::object;
  path_shade(&sd, &p, hit, PathSettings{settings.max_bounces, settings.rr_start}, base_footprint,
             aov);
}

namespace {

// Writes pixel (x, y)'s feature buffers from its `spp` samples, paths[0..spp), each with
// its radiance as the beauty averages it (render/shared/aov.h). A pass of its own beside
// the beauty's, so that a frame without feature buffers runs the loop it always ran.
void write_features(const WavefrontPath* paths, int spp, const RenderSettings& settings,
                    Framebuffer& out, int x, int y) {
  if (out.features.width != out.width || out.features.height != out.height)
    throw std::logic_error("feature buffers asked for, and the framebuffer has none");
  AovPixel px;
  aov_pixel_init(&px);
  for (int s = 0; s < spp; ++s) {
    const Vec3 L = paths[s].L;
    aov_pixel_add(&px, &paths[s].aov, L,
                  clamp_sample(is_finite(L) ? L : Vec3(0.0f), settings.sample_clamp),
                  settings.sample_clamp);
  }
  float v[MR_AOV_FLOATS];
  aov_pixel_result(&px, v);
  out.features.set_packed(size_t(y) * size_t(out.width) + size_t(x), v);
}

// A batch's per-path scratch, one per thread, reused from batch to batch (no allocation
// once the first batch is done).
struct BatchScratch {
  std::vector<Hit> hits;
  std::vector<uint8_t> found, has_footprint, blocked;
  std::vector<TexFootprint> footprints;  // of each hit's base colour texture
  std::vector<Ray> shadows;
  std::vector<uint32_t> casters;  // the path of each shadow ray
};

// Starts loading the base colour texels (the hot ones) of every hit before any hit is
// shaded, and keeps their footprints for the shading.
void prefetch_base_colours(const RenderScene& rs, const std::vector<WavefrontPath>& paths,
                           BatchScratch& b) {
  for (size_t i = 0; i < paths.size(); ++i) {
    b.has_footprint[i] = false;
    if (!paths[i].alive || !b.found[i] || b.hits[i].prim == kCatcherPrim) continue;
    const Hit& hit = b.hits[i];
    const TriangleShading d = rs.shading_of(hit.prim);
    const int tex = rs.materials[d.material].texture;
    if (tex < 0 || texture_empty(&rs.textures[size_t(tex)])) continue;
    const TextureView& t = rs.textures[size_t(tex)];
    b.footprints[i] = texture_footprint(&t, shading_uv(&d, 1.0f - hit.u - hit.v, hit.u, hit.v));
    __builtin_prefetch(t.texels + b.footprints[i].row0 + b.footprints[i].x0);
    __builtin_prefetch(t.texels + b.footprints[i].row1 + b.footprints[i].x0);
    b.has_footprint[i] = true;
  }
}

// Traces the shadow rays the batch's paths are waiting on, eight at a time, and adds the
// light of those that arrive.
void trace_shadows(const Accel& accel, const CatcherPlane& catcher,
                   std::vector<WavefrontPath>& paths, BatchScratch& b, KernelStats& stats,
                   RayLog* log) {
  b.shadows.clear();
  b.casters.clear();
  for (size_t i = 0; i < paths.size(); ++i)
    if (paths[i].has_shadow) {
      b.shadows.push_back(paths[i].shadow);
      b.casters.push_back(uint32_t(i));
    }
  stats.rays += b.shadows.size();
  if (log) log->shadow.insert(log->shadow.end(), b.shadows.begin(), b.shadows.end());
  b.blocked.resize(b.shadows.size());
  accel.occluded_batch(b.shadows.data(), b.shadows.size(), b.blocked.data());
  for (size_t k = 0; k < b.shadows.size(); ++k) {
    WavefrontPath& p = paths[b.casters[k]];
    path_shadow_done(&p, b.blocked[k] || (catcher.on() &&
                                          catcher.intersect(p.shadow, p.shadow.tmax) < INFINITY));
  }
}

}  // namespace

void PathTracer::trace_batch(std::vector<WavefrontPath>& paths, const RenderSettings& settings,
                             KernelStats& stats, RayLog* log) const {
  const size_t n = paths.size();
  const CatcherPlane catcher(settings);
  const SceneData sd =
      rs_.scene_data(settings.sample_environment ? rs_.environment_choice() : 0.0f, eps_);
  thread_local BatchScratch b;
  b.hits.resize(n);
  b.found.resize(n);
  b.footprints.resize(n);
  b.has_footprint.resize(n);
  for (bool any = true; any;) {
    for (size_t i = 0; i < n; ++i)
      if (paths[i].alive) {
        ++stats.rays;
        if (log) log->closest.push_back(paths[i].ray);
        b.found[i] = rs_.accel.intersect(paths[i].ray, b.hits[i]);
        if (catcher.on()) find_catcher(catcher, paths[i].ray, b.hits[i], b.found[i]);
        if (b.found[i] && b.hits[i].prim != kCatcherPrim && !rs_.compact)
          __builtin_prefetch(&rs_.shading[b.hits[i].prim]);
      }
    prefetch_base_colours(rs_, paths, b);
    for (size_t i = 0; i < n; ++i)
      if (paths[i].alive)
        step(paths[i], b.found[i] ? &b.hits[i] : nullptr, sd, settings,
             b.has_footprint[i] ? &b.footprints[i] : nullptr);
    trace_shadows(rs_.accel, catcher, paths, b, stats, log);
    any = false;
    for (const WavefrontPath& p : paths) any |= p.alive;
  }
}

KernelStats PathTracer::render_rect_logged(const ViewSetup& view, const RenderSettings& settings,
                                           Rect rect, Framebuffer& out, RayLog* log) const {
  KernelStats stats;
  if (rect.area() == 0) return stats;
  const PinholeCamera camera(view.camera, view.width, view.height);
  // A batch holds whole pixels (all their samples), about kBatch paths.
  constexpr size_t kBatch = 64;
  const int rect_w = rect.x1 - rect.x0;
  const bool catcher = CatcherPlane(settings).on();
  std::vector<WavefrontPath> paths;
  std::vector<int> counts;  // samples of each pixel of the batch
  for (int64_t first = 0; first < rect.area();) {
    paths.clear();
    counts.clear();
    int64_t last = first;
    for (; last < rect.area() && (paths.empty() || paths.size() < kBatch); ++last) {
      const int x = rect.x0 + int(last % rect_w), y = rect.y0 + int(last / rect_w);
      const uint32_t pixel = uint32_t(y) * uint32_t(view.width) + uint32_t(x);
      const int spp = view.samples_at(pixel, settings);
      counts.push_back(spp);
      for (int s = 0; s < spp; ++s) {
        WavefrontPath& p = paths.emplace_back(sample_stream_for_path(
            pixel, view.first_sample + uint32_t(s), view.seed_frame(), view.view, settings.seed));
        const Vec2 j = sample_2d(&p.u);
        p.ray = camera.ray(float(x) + j.x, float(y) + j.y);
        if (settings.feature_buffers) aov_init(&p.aov, p.ray.dir, camera.forward);
      }
    }
    trace_batch(paths, settings, stats, log);
    size_t next = 0;
    for (int64_t k = first; k < last; ++k) {
      const int spp = counts[size_t(k - first)];
      const int x = rect.x0 + int(k % rect_w), y = rect.y0 + int(k / rect_w);
      if (catcher) {
        write_catcher_pixel(&paths[next], spp, settings, out, x, y);
        next += size_t(spp);
        continue;
      }
      if (settings.feature_buffers) write_features(paths.data() + next, spp, settings, out, x, y);
      Vec3 sum(0.0f);
      for (int s = 0; s < spp; ++s, ++next) {
        const Vec3 L = paths[next].L;
        sum += clamp_sample(is_finite(L) ? L : Vec3(0.0f), settings.sample_clamp);
      }
      out.at(x, y) = spp > 0 ? sum * (1.0f / float(spp)) : Vec3(0.0f);
    }
    stats.samples += paths.size();
    first = last;
  }
  return stats;
}

KernelStats PathTracer::render_samples(const ViewSetup& view, const RenderSettings& settings,
                                       const ImageSample* samples, size_t n,
                                       Vec3* radiance) const {
  KernelStats stats;
  const PinholeCamera camera(view.camera, view.width, view.height);
  constexpr size_t kBatch = 64;
  std::vector<WavefrontPath> paths;
  for (size_t first = 0; first < n; first += kBatch) {
    const size_t last = std::min(n, first + kBatch);
    paths.clear();
    for (size_t i = first; i < last; ++i) {
      const ImageSample& s = samples[i];
      WavefrontPath& p = paths.emplace_back(
          sample_stream_for_path(s.key, 0, view.frame, view.view, settings.seed));
      p.ray = camera.ray(s.x, s.y);
      // Point samples record no feature buffers (run/ refuses them with foveated
      // sampling); the state is set so that path_shade reads defined values.
      if (settings.feature_buffers) aov_init(&p.aov, p.ray.dir, camera.forward);
    }
    trace_batch(paths, settings, stats, nullptr);
    for (size_t i = first; i < last; ++i) {
      const Vec3 L = paths[i - first].L;
      radiance[i] = clamp_sample(is_finite(L) ? L : Vec3(0.0f), settings.sample_clamp);
    }
    stats.samples += last - first;
  }
  return stats;
}

}  // namespace multiray
