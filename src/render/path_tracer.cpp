#include "render/path_tracer.h"

#include <cmath>

#include "render/bsdf.h"
#include "render/path_state.h"
#include "render/shared/sampling.h"
#include "render/surface.h"

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

namespace {

struct Shading {
  Vec3 p, ng, ns;  // position, geometric normal (winding), shading normal
  Vec2 uv;
  uint32_t material;
};

Vec2 interpolate_uv(const TriangleShading& d, const Hit& hit) {
  const float w = 1.0f - hit.u - hit.v;
  return {d.uv[0].x * w + d.uv[1].x * hit.u + d.uv[2].x * hit.v,
          d.uv[0].y * w + d.uv[1].y * hit.u + d.uv[2].y * hit.v};
}

Shading shade_point(const TriangleShading& d, const Ray& ray, const Hit& hit) {
  const float w = 1.0f - hit.u - hit.v;
  Shading sh;
  sh.p = ray.org + ray.dir * hit.t;
  sh.ng = normalize(hit.ng);
  const Vec3 n = d.normal[0] * w + d.normal[1] * hit.u + d.normal[2] * hit.v;
  sh.ns = dot(n, n) > 0 ? normalize(n) : sh.ng;
  if (dot(sh.ns, sh.ng) < 0) sh.ns = -sh.ns;
  sh.uv = interpolate_uv(d, hit);
  sh.material = d.material;
  return sh;
}

}  // namespace

// Adds light arriving at the path's vertex from outside the scene along the ray that
// just escaped, weighted against next-event estimation from the previous vertex.
void PathTracer::escape(PathState& p, float p_env) const {
  p.L += escape_contribution(p, p_env);
  p.alive = false;
}

Vec3 PathTracer::escape_contribution(const PathState& p, float p_env) const {
  const Vec3 Le = rs_.environment.radiance(p.ray.dir);
  float w = 1.0f;
  if (!p.prev_specular && p_env > 0) {
    const float pdf_env = p_env * rs_.environment.pdf(p.ray.dir, p.prev_normal);
    w = power_heuristic(p.prev_pdf, pdf_env);
  }
  return p.beta * Le * w;
}

// Next-event estimation from a vertex with BSDF `bsdf` in `frame`: one sample of either
// the environment or an emissive triangle (three random numbers either way); the shadow
// ray is traced by the caller and adds `shadow_contribution` if unoccluded.
void PathTracer::sample_light(PathState& p, float p_env, const Bsdf& bsdf, const Frame& frame,
                              Vec3 wo, Vec3 pos, Vec3 ng) const {
  float ul = sample_1d(&p.u);
  const Vec2 uv = sample_2d(&p.u);
  const float u1 = uv.x, u2 = uv.y;
  if (ul < p_env) {
    const EnvSample es = rs_.environment.sample(ng, ul / p_env, u1, u2);
    if (!(es.pdf > 0) || dot(es.dir, ng) <= 0) return;
    const Vec3 wi = frame.to_local(es.dir);
    const Vec3 f = bsdf.eval(wo, wi);
    if (!(max_component(f) > 0)) return;
    const float pdf_light = p_env * es.pdf;
    p.shadow = Ray{pos + ng * eps_, es.dir, 0.0f, INFINITY};
    p.shadow_contribution =
        p.beta * f * es.radiance * (power_heuristic(pdf_light, bsdf.pdf(wo, wi)) / pdf_light);
    p.has_shadow = true;
    return;
  }
  ul = (ul - p_env) / (1.0f - p_env);  // exactly ul when there is no environment
  const LightSample ls = rs_.lights.sample(ul, u1, u2);
  const Vec3 d = ls.point - pos;
  const float dist2 = dot(d, d), dist = std::sqrt(dist2);
  const Vec3 wi_world = d / dist;
  const float cos_l = -dot(ls.normal, wi_world);
  if (!(cos_l > 0) || dot(wi_world, ng) <= 0) return;
  const Vec3 wi = frame.to_local(wi_world);
  const Vec3 f = bsdf.eval(wo, wi);
  if (!(max_component(f) > 0)) return;
  const float pdf_light = (1.0f - p_env) * ls.pdf_area * dist2 / cos_l;
  p.shadow = Ray{pos + ng * eps_, wi_world, 0.0f, dist * (1.0f - 1e-4f) - eps_};
  p.shadow_contribution =
      p.beta * f * ls.radiance * (power_heuristic(pdf_light, bsdf.pdf(wo, wi)) / pdf_light);
  p.has_shadow = true;
}

void PathTracer::step(PathState& p, const Hit* hit, const RenderSettings& settings,
                      const Texture::Footprint* base_footprint) const {
  const Scene& scene = rs_.scene;
  const float p_env = settings.sample_environment ? rs_.environment_choice() : 0.0f;
  if (!hit) return escape(p, p_env);
  if (hit->prim == kCatcherPrim) return catcher_step(p, *hit, settings, p_env);
  if (p.depth == 0) p.kind = SampleKind::object;
  Shading sh = shade_point(rs_.shading_of(hit->prim), p.ray, *hit);
  const Material& mat = scene.materials[sh.material];
  const Vec3 wo_world = -p.ray.dir;
  const bool front = dot(sh.ng, wo_world) > 0;

  if (front && max_component(mat.emission) > 0) {
    const Vec3 Le = emission_at(scene, mat, sh.uv);
    if (p.prev_specular) {
      p.L += p.beta * Le;
    } else {
      const float cos_l = dot(sh.ng, wo_world);
      const float pdf_light =
          (1.0f - p_env) * rs_.lights.pdf_area(hit->prim) * hit->t * hit->t / cos_l;
      p.L += p.beta * Le * power_heuristic(p.prev_pdf, pdf_light);
    }
  }
  if (p.depth >= settings.max_bounces) {
    p.alive = false;
    return;
  }

  const SurfacePoint sp =
      surface_at(scene, mat, sh.uv, sh.ns, sh.ng,
                 rs_.tangents.empty() ? nullptr : &rs_.tangents[hit->prim], base_footprint);
  sh.ns = sp.ns;
  const Bsdf bsdf(mat, sp.base_color, sp.metallic, sp.roughness);
  // Opaque surfaces are two-sided: face the normals towards the viewer. Dielectrics keep
  // their outward normal so the BSDF knows whether the path is inside.
  if (bsdf.has_diffuse_or_glossy() && !front) sh.ng = -sh.ng, sh.ns = -sh.ns;
  Frame frame = Frame::from_normal(sh.ns);
  Vec3 wo = frame.to_local(wo_world);
  if (bsdf.has_diffuse_or_glossy() && wo.z <= 0) {
    frame = Frame::from_normal(sh.ng);  // shading normal faces away: fall back
    wo = frame.to_local(wo_world);
  }
  scatter(p, p_env, bsdf, frame, wo, sh.p, sh.ng, settings);
}

void PathTracer::scatter(PathState& p, float p_env, const Bsdf& bsdf, const Frame& frame, Vec3 wo,
                         Vec3 pos, Vec3 ng, const RenderSettings& settings) const {
  // The bounce's dimensions (render/shared/sobol.h): light choice, light 2D, BSDF lobe,
  // BSDF 2D, roulette; each part starts at its own, whether or not the earlier ones drew.
  sample_stream_at_bounce(&p.u, p.depth);
  if (bsdf.has_diffuse_or_glossy() && (p_env > 0 || !rs_.lights.empty()))
    sample_light(p, p_env, bsdf, frame, wo, pos, ng);

  // Continue the path by sampling the BSDF.
  sample_stream_at_bounce(&p.u, p.depth);
  p.u.dim += MR_SOBOL_BSDF_OFFSET;
  p.alive = false;
  BsdfSample bs;
  // The lobe's value is drawn only when there is a choice (a tenth of a bounce's draws);
  // its dimension is passed over either way, so the values after it do not move.
  const float u_lobe = bsdf.chooses_lobe() ? sample_1d(&p.u) : (++p.u.dim, 0.0f);
  const Vec2 u12 = sample_2d(&p.u);
  if (!bsdf.sample(wo, u_lobe, u12.x, u12.y, bs)) return;
  const Vec3 wi_world = frame.to_world(bs.wi);
  const float side = dot(wi_world, ng);
  if (bsdf.has_diffuse_or_glossy() && side <= 0) return;  // shading normal leak
  p.beta *= bs.weight;
  p.prev_pdf = bs.pdf;
  p.prev_specular = bs.specular;
  p.prev_normal = ng;
  p.ray = Ray{pos + ng * (side > 0 ? eps_ : -eps_), wi_world};
  ++p.depth;
  if (p.depth >= settings.rr_start) {
    const float q = rr_survival(max_component(p.beta));
    if (q < 1.0f && sample_1d(&p.u) >= q) return;  // (q = 1: nothing to draw)
    p.beta = p.beta / q;
  }
  p.alive = true;
}

namespace {

// A batch's per-path scratch, one per thread, reused from batch to batch (no allocation
// once the first batch is done).
struct BatchScratch {
  std::vector<Hit> hits;
  std::vector<uint8_t> found, has_footprint, blocked;
  std::vector<Texture::Footprint> footprints;  // of each hit's base colour texture
  std::vector<Ray> shadows;
  std::vector<uint32_t> casters;  // the path of each shadow ray
};

// Starts loading the base colour texels (the hot ones) of every hit before any hit is
// shaded, and keeps their footprints for the shading.
void prefetch_base_colours(const RenderScene& rs, const std::vector<PathState>& paths,
                           BatchScratch& b) {
  for (size_t i = 0; i < paths.size(); ++i) {
    b.has_footprint[i] = false;
    if (!paths[i].alive || !b.found[i] || b.hits[i].prim == kCatcherPrim) continue;
    const TriangleShading d = rs.shading_of(b.hits[i].prim);
    const int tex = rs.scene.materials[d.material].base_color_texture;
    if (tex < 0 || rs.scene.textures[size_t(tex)].empty()) continue;
    const Texture& t = rs.scene.textures[size_t(tex)];
    b.footprints[i] = t.footprint(interpolate_uv(d, b.hits[i]));
    t.prefetch(b.footprints[i]);
    b.has_footprint[i] = true;
  }
}

// Traces the shadow rays the batch's paths are waiting on, eight at a time, and adds the
// light of those that arrive.
void trace_shadows(const Accel& accel, const CatcherPlane& catcher, std::vector<PathState>& paths,
                   BatchScratch& b, KernelStats& stats, RayLog* log) {
  b.shadows.clear();
  b.casters.clear();
  for (size_t i = 0; i < paths.size(); ++i)
    if (paths[i].has_shadow) {
      b.shadows.push_back(paths[i].shadow);
      b.casters.push_back(uint32_t(i));
      paths[i].has_shadow = false;
    }
  stats.rays += b.shadows.size();
  if (log) log->shadow.insert(log->shadow.end(), b.shadows.begin(), b.shadows.end());
  b.blocked.resize(b.shadows.size());
  accel.occluded_batch(b.shadows.data(), b.shadows.size(), b.blocked.data());
  for (size_t k = 0; k < b.shadows.size(); ++k) {
    PathState& p = paths[b.casters[k]];
    if (!b.blocked[k] && !(catcher.on() && catcher.intersect(p.shadow, p.shadow.tmax) < INFINITY))
      p.L += p.shadow_contribution;
  }
}

}  // namespace

void PathTracer::trace_batch(std::vector<PathState>& paths, const RenderSettings& settings,
                             KernelStats& stats, RayLog* log) const {
  const size_t n = paths.size();
  const CatcherPlane catcher(settings);
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
        step(paths[i], b.found[i] ? &b.hits[i] : nullptr, settings,
             b.has_footprint[i] ? &b.footprints[i] : nullptr);
    trace_shadows(rs_.accel, catcher, paths, b, stats, log);
    any = false;
    for (const PathState& p : paths) any |= p.alive;
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
  std::vector<PathState> paths;
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
        PathState& p = paths.emplace_back(sample_stream_for_path(
            pixel, view.first_sample + uint32_t(s), view.seed_frame(), view.view, settings.seed));
        const Vec2 j = sample_2d(&p.u);
        p.ray = camera.ray(float(x) + j.x, float(y) + j.y);
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
  std::vector<PathState> paths;
  for (size_t first = 0; first < n; first += kBatch) {
    const size_t last = std::min(n, first + kBatch);
    paths.clear();
    for (size_t i = first; i < last; ++i) {
      const ImageSample& s = samples[i];
      PathState& p = paths.emplace_back(
          sample_stream_for_path(s.key, 0, view.frame, view.view, settings.seed));
      p.ray = camera.ray(s.x, s.y);
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
