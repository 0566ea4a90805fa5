#include <array>
#include <cmath>

#include "scene/builders.h"

namespace multiray {

uint32_t add_material(Scene& s, Material m) {
  s.materials.push_back(std::move(m));
  return uint32_t(s.materials.size() - 1);
}

uint32_t add_quad(Scene& s, Vec3 a, Vec3 b, Vec3 c, Vec3 d, uint32_t material) {
  const uint32_t first = uint32_t(s.triangle_count());
  // Three corners of its own per triangle, each with the triangle's face normal computed as
  // build_shading_data() computes it for a mesh without normals: flat shading exactly as
  // before, while curved parts of the same scene (add_sphere) keep their smooth normals.
  for (const auto& tri : {std::array<Vec3, 3>{a, b, c}, std::array<Vec3, 3>{a, c, d}}) {
    const Vec3 e = cross(tri[1] - tri[0], tri[2] - tri[0]);
    const Vec3 face = dot(e, e) > 0 ? normalize(e) : Vec3(0, 0, 1);  // never hit if degenerate
    for (Vec3 p : tri) {
      s.indices.push_back(uint32_t(s.positions.size()));
      s.positions.push_back(p);
      s.normals.push_back(face);
    }
    s.material_ids.push_back(material);
  }
  return first;
}

uint32_t add_box(Scene& s, Vec3 c, Vec3 h, float yaw_deg, uint32_t material) {
  const float r = yaw_deg * kPi / 180.0f, cs = std::cos(r), sn = std::sin(r);
  auto p = [&](float sx, float sy, float sz) {
    const Vec3 l(sx * h.x, sy * h.y, sz * h.z);
    return c + Vec3(cs * l.x + sn * l.z, l.y, -sn * l.x + cs * l.z);
  };
  const uint32_t first = uint32_t(s.triangle_count());
  add_quad(s, p(-1, 1, -1), p(-1, 1, 1), p(1, 1, 1), p(1, 1, -1), material);      // top
  add_quad(s, p(-1, -1, -1), p(1, -1, -1), p(1, -1, 1), p(-1, -1, 1), material);  // bottom
  add_quad(s, p(-1, -1, 1), p(1, -1, 1), p(1, 1, 1), p(-1, 1, 1), material);      // +z
  add_quad(s, p(1, -1, -1), p(-1, -1, -1), p(-1, 1, -1), p(1, 1, -1), material);  // -z
  add_quad(s, p(1, -1, 1), p(1, -1, -1), p(1, 1, -1), p(1, 1, 1), material);      // +x
  add_quad(s, p(-1, -1, -1), p(-1, -1, 1), p(-1, 1, 1), p(-1, 1, -1), material);  // -x
  return first;
}

uint32_t add_sphere(Scene& s, Vec3 center, float radius, int rings, int segments, bool inward,
                    uint32_t material) {
  const uint32_t first = uint32_t(s.triangle_count());
  auto point = [&](int i, int j) {
    const float theta = kPi * float(i) / float(rings), phi = 2 * kPi * float(j) / float(segments);
    return Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      // This order is counter-clockwise seen from outside (normal points out); swapping
      // two corners turns the sphere inside out. Triangles at the poles are degenerate.
      Vec3 q[4] = {point(i, j), point(i, j + 1), point(i + 1, j + 1), point(i + 1, j)};
      if (inward) std::swap(q[1], q[3]);
      const uint32_t base = uint32_t(s.positions.size());
      for (Vec3 n : q) {
        s.positions.push_back(center + n * radius);
        s.normals.push_back(inward ? -n : n);
      }
      for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) s.indices.push_back(base + k);
      s.material_ids.push_back(material);
      s.material_ids.push_back(material);
    }
  return first;
}

Scene make_cornell_box() {
  Scene s;
  s.name = "cornell-box";
  Material white{.name = "white", .base_color = {0.725f, 0.71f, 0.68f}};
  Material red{.name = "red", .base_color = {0.63f, 0.065f, 0.05f}};
  Material green{.name = "green", .base_color = {0.14f, 0.45f, 0.091f}};
  Material light{.name = "light", .base_color = {0.78f, 0.78f, 0.78f}, .emission = {17, 12, 4}};
  Material metal{
      .name = "metal", .base_color = {0.95f, 0.93f, 0.88f}, .metallic = 1.0f, .roughness = 0.3f};
  const uint32_t w = add_material(s, white), r = add_material(s, red), g = add_material(s, green),
                 l = add_material(s, light), m = add_material(s, metal);
  add_quad(s, {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, w);    // floor
  add_quad(s, {-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}, w);    // ceiling
  add_quad(s, {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, w);  // back
  add_quad(s, {-1, 0, 1}, {-1, 0, -1}, {-1, 2, -1}, {-1, 2, 1}, r);  // left (red)
  add_quad(s, {1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}, g);      // right (green)
  // Light slightly below the ceiling, facing down.
  add_quad(s, {-0.24f, 1.98f, -0.22f}, {0.23f, 1.98f, -0.22f}, {0.23f, 1.98f, 0.16f},
           {-0.24f, 1.98f, 0.16f}, l);
  add_box(s, {-0.33f, 0.6f, -0.29f}, {0.3f, 0.6f, 0.3f}, 17.0f, w);  // tall block
  add_box(s, {0.34f, 0.3f, 0.38f}, {0.3f, 0.3f, 0.3f}, -17.0f, w);   // short block
  add_sphere(s, {0.34f, 0.85f, 0.38f}, 0.25f, 16, 32, false, m);     // metal ball on it
  // The ball is smooth-shaded from its vertex normals; the quads carry their face normals.
  s.cameras.push_back(Camera{{0, 1, 3.9f}, {0, 1, 0}, {0, 1, 0}, 39.3f});
  return s;
}

Scene make_furnace_sphere(float albedo, float le) {
  Scene s;
  s.name = "white-furnace";
  const uint32_t m = add_material(
      s, Material{.name = "furnace", .base_color = Vec3(albedo), .emission = Vec3(le)});
  add_sphere(s, {0, 0, 0}, 1.0f, 24, 48, true, m);
  s.cameras.push_back(Camera{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60.0f});
  return s;
}

Scene make_lit_plane(float albedo, float env) {
  Scene s;
  s.name = "lit-plane";
  const uint32_t m = add_material(s, Material{.name = "plane", .base_color = Vec3(albedo)});
  const float e = 1000.0f;
  add_quad(s, {-e, 0, -e}, {-e, 0, e}, {e, 0, e}, {e, 0, -e}, m);
  s.environment = Vec3(env);
  s.cameras.push_back(Camera{{0, 1, 0}, {0, 0, 0}, {0, 0, -1}, 60.0f});
  return s;
}

Scene make_lit_sphere(float albedo, int rings, int segments, bool smooth) {
  Scene s;
  s.name = smooth ? "lit-sphere-smooth" : "lit-sphere-flat";
  const uint32_t m = add_material(s, Material{.name = "sphere", .base_color = Vec3(albedo)});
  add_sphere(s, {0, 0, 0}, 1.0f, rings, segments, false, m);
  // The light: a square around l * distance whose normal, cross(t1, t2) = -l, faces the
  // sphere (add_quad's winding); its radiance gives irradiance 1 at distance `dist`.
  const Vec3 l = lit_sphere_light_dir();
  const Vec3 t1 = normalize(cross(l, Vec3(0, 1, 0))), t2 = cross(t1, l);
  const float h = 0.5f * kLitSphereLightSide, dist = kLitSphereLightDistance;
  const float le = dist * dist / (kLitSphereLightSide * kLitSphereLightSide);
  const uint32_t light =
      add_material(s, Material{.name = "light", .base_color = Vec3(0), .emission = Vec3(le)});
  const Vec3 c = l * dist;
  add_quad(s, c - t1 * h - t2 * h, c + t1 * h - t2 * h, c + t1 * h + t2 * h, c - t1 * h + t2 * h,
           light);
  if (!smooth) s.normals.clear();  // flat: every triangle shaded with its face normal
  s.cameras.push_back(Camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.0f});
  return s;
}

}  // namespace multiray
