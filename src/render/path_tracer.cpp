#include "render/path_tracer.h"

#include <cmath>

#include "core/rng.h"
#include "render/bsdf.h"
#include "render/sampling.h"

namespace multiray {

PinholeCamera::PinholeCamera(const Camera& cam, int width, int height)
    : eye(cam.eye), forward(normalize(cam.target - cam.eye)) {
  right = normalize(cross(forward, cam.up));
  up = cross(right, forward);
  const float tan_half = std::tan(0.5f * cam.fov_y_deg * kPi / 180.0f);
  scale_y = tan_half;
  scale_x = tan_half * float(width) / float(height);
  inv_w_ = 2.0f / float(width);
  inv_h_ = 2.0f / float(height);
}

Ray PinholeCamera::ray(float px, float py) const {
  const float sx = (px * inv_w_ - 1.0f) * scale_x;
  const float sy = (1.0f - py * inv_h_) * scale_y;
  return Ray{eye, normalize(forward + right * sx + up * sy)};
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

Shading shade_point(const std::vector<TriangleShading>& data, const Ray& ray, const Hit& hit) {
  const TriangleShading& d = data[hit.prim];
  const float w = 1.0f - hit.u - hit.v;
  Shading sh;
  sh.p = ray.org + ray.dir * hit.t;
  sh.ng = normalize(hit.ng);
  const Vec3 n = d.normal[0] * w + d.normal[1] * hit.u + d.normal[2] * hit.v;
  sh.ns = dot(n, n) > 0 ? normalize(n) : sh.ng;
  if (dot(sh.ns, sh.ng) < 0) sh.ns = -sh.ns;
  sh.uv = {d.uv[0].x * w + d.uv[1].x * hit.u + d.uv[2].x * hit.v,
           d.uv[0].y * w + d.uv[1].y * hit.u + d.uv[2].y * hit.v};
  sh.material = d.material;
  return sh;
}

}  // namespace

Vec3 PathTracer::radiance(Ray ray, Rng& rng, const RenderSettings& settings, KernelStats& stats,
                          RayLog* log) const {
  const Scene& scene = rs_.scene;
  Vec3 L(0.0f), beta(1.0f);
  float prev_pdf = 0;
  bool prev_specular = true;  // the camera ray counts as specular: emission seen directly
  for (int depth = 0;; ++depth) {
    Hit hit;
    ++stats.rays;
    if (log) log->closest.push_back(ray);
    if (!rs_.accel.intersect(ray, hit)) {
      L += beta * scene.environment;  // the environment is never light-sampled: weight 1
      break;
    }
    Shading sh = shade_point(rs_.shading, ray, hit);
    const Material& mat = scene.materials[sh.material];
    const Vec3 wo_world = -ray.dir;
    const bool front = dot(sh.ng, wo_world) > 0;

    if (front && max_component(mat.emission) > 0) {
      if (prev_specular) {
        L += beta * mat.emission;
      } else {
        const float cos_l = dot(sh.ng, wo_world);
        const float pdf_light = rs_.lights.pdf_area(hit.prim) * hit.t * hit.t / cos_l;
        L += beta * mat.emission * power_heuristic(prev_pdf, pdf_light);
      }
    }
    if (depth >= settings.max_bounces) break;

    Vec3 color = mat.base_color;
    if (mat.base_color_texture >= 0) color *= scene.textures[mat.base_color_texture].sample(sh.uv);
    const Bsdf bsdf(mat, color);
    // Opaque surfaces are two-sided: face the normals towards the viewer. Dielectrics keep
    // their outward normal so the BSDF knows whether the path is inside.
    if (bsdf.has_diffuse_or_glossy() && !front) sh.ng = -sh.ng, sh.ns = -sh.ns;
    Frame frame = Frame::from_normal(sh.ns);
    Vec3 wo = frame.to_local(wo_world);
    if (bsdf.has_diffuse_or_glossy() && wo.z <= 0) {
      frame = Frame::from_normal(sh.ng);  // shading normal faces away: fall back
      wo = frame.to_local(wo_world);
    }

    // Next-event estimation towards one point on one emissive triangle.
    if (bsdf.has_diffuse_or_glossy() && !rs_.lights.empty()) {
      const float ul = rng.next(), u1 = rng.next(), u2 = rng.next();
      const LightSample ls = rs_.lights.sample(ul, u1, u2);
      const Vec3 d = ls.point - sh.p;
      const float dist2 = dot(d, d), dist = std::sqrt(dist2);
      const Vec3 wi_world = d / dist;
      const float cos_l = -dot(ls.normal, wi_world);
      if (cos_l > 0 && dot(wi_world, sh.ng) > 0) {
        const Vec3 wi = frame.to_local(wi_world);
        const Vec3 f = bsdf.eval(wo, wi);
        if (max_component(f) > 0) {
          const Ray shadow{sh.p + sh.ng * eps_, wi_world, 0.0f, dist * (1.0f - 1e-4f) - eps_};
          ++stats.rays;
          if (log) log->shadow.push_back(shadow);
          if (!rs_.accel.occluded(shadow)) {
            const float pdf_light = ls.pdf_area * dist2 / cos_l;
            L += beta * f * ls.radiance *
                 (power_heuristic(pdf_light, bsdf.pdf(wo, wi)) / pdf_light);
          }
        }
      }
    }

    // Continue the path by sampling the BSDF.
    BsdfSample bs;
    const float u_lobe = rng.next(), u1 = rng.next(), u2 = rng.next();
    if (!bsdf.sample(wo, u_lobe, u1, u2, bs)) break;
    const Vec3 wi_world = frame.to_world(bs.wi);
    const float side = dot(wi_world, sh.ng);
    if (bsdf.has_diffuse_or_glossy() && side <= 0) break;  // shading normal leak
    beta *= bs.weight;
    prev_pdf = bs.pdf;
    prev_specular = bs.specular;
    ray = Ray{sh.p + sh.ng * (side > 0 ? eps_ : -eps_), wi_world};

    if (depth + 1 >= settings.rr_start) {
      const float q = std::min(max_component(beta), 0.95f);
      if (rng.next() >= q) break;
      beta = beta / q;
    }
  }
  return is_finite(L) ? L : Vec3(0.0f);
}

KernelStats PathTracer::render_rect(const ViewSetup& view, const RenderSettings& settings,
                                    PixelRect rect, Framebuffer& out, RayLog* log) const {
  KernelStats stats;
  const float inv_spp = 1.0f / float(settings.spp);
  const PinholeCamera camera(view.camera, view.width, view.height);
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const uint32_t pixel = uint32_t(y) * uint32_t(view.width) + uint32_t(x);
      Vec3 sum(0.0f);
      for (int s = 0; s < settings.spp; ++s) {
        Rng rng = Rng::for_path(pixel, uint32_t(s), view.frame, view.view, settings.seed);
        const float jx = rng.next(), jy = rng.next();
        const Ray r = camera.ray(float(x) + jx, float(y) + jy);
        sum += radiance(r, rng, settings, stats, log);
      }
      out.at(x, y) = sum * inv_spp;
      stats.samples += uint64_t(settings.spp);
    }
  return stats;
}

}  // namespace multiray
