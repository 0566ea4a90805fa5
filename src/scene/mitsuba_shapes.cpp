#include "scene/mitsuba_shapes.h"

#include <cmath>
#include <limits>

#include "scene/loaders.h"

namespace multiray::detail {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Appends the quad a, b, c, d (counter-clockwise seen from the side it faces) as two
// triangles with the flat normal `n` at each of its own four vertices.
void add_quad(Scene* s, Vec3 a, Vec3 b, Vec3 c, Vec3 d, Vec3 n) {
  const uint32_t base = uint32_t(s->positions.size());
  for (Vec3 p : {a, b, c, d}) s->positions.push_back(p), s->normals.push_back(n);
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) s->indices.push_back(base + i);
  s->material_ids.push_back(0), s->material_ids.push_back(0);
}

}  // namespace

Scene mitsuba_rectangle() {
  Scene s;
  add_quad(&s, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1});
  return s;
}

Scene mitsuba_cube() {
  Scene s;
  // For each axis and sign, the face's normal n and two in-plane axes u, v with u x v = n.
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {-1.0f, 1.0f}) {
      Vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = sign;
      u[(axis + 1) % 3] = 1;
      v[(axis + 2) % 3] = sign;
      add_quad(&s, n - u - v, n + u - v, n + u + v, n - u + v, n);
    }
  return s;
}

void ShapeMerger::append(const Scene& part, const Mat4& to_world, uint32_t material, bool flip) {
  const uint32_t base = uint32_t(positions_.size());
  const Mat4 nm = to_world.normal_matrix();
  const bool has_normals = part.normals.size() == part.positions.size();
  parts_.push_back({indices_.size(), has_normals});
  for (size_t i = 0; i < part.positions.size(); ++i) {
    positions_.push_back(to_world.point(part.positions[i]));
    Vec3 n(kNaN);
    if (has_normals) n = shading_normal(nm.vector(part.normals[i]) * (flip ? -1.0f : 1.0f));
    normals_.push_back(n);
  }
  for (size_t t = 0; t + 2 < part.indices.size(); t += 3) {
    const uint32_t a = part.indices[t], b = part.indices[t + 1], c = part.indices[t + 2];
    for (uint32_t i : {a, flip ? c : b, flip ? b : c}) indices_.push_back(base + i);
    material_ids_.push_back(material);
  }
}

void ShapeMerger::finish(Scene* scene) {
  bool any = false, all = true;
  for (const Part& p : parts_) any |= p.has_normals, all &= p.has_normals;
  if (!any) normals_.clear();
  if (any && !all) {
    // Rebuild: parts with normals keep their shared vertices; the others get three
    // vertices of their own per triangle, with its flat normal.
    std::vector<Vec3> positions, normals;
    std::vector<uint32_t> indices;
    std::vector<int64_t> remap(positions_.size(), -1);
    size_t part = 0;
    for (size_t t = 0; t < indices_.size(); t += 3) {
      while (part + 1 < parts_.size() && parts_[part + 1].first_index <= t) ++part;
      const uint32_t* tri = &indices_[t];
      const Vec3 flat = flat_normal(positions_[tri[0]], positions_[tri[1]], positions_[tri[2]]);
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = tri[k];
        if (parts_[part].has_normals && remap[v] >= 0) {
          indices.push_back(uint32_t(remap[v]));
          continue;
        }
        if (parts_[part].has_normals) remap[v] = int64_t(positions.size());
        indices.push_back(uint32_t(positions.size()));
        positions.push_back(positions_[v]);
        normals.push_back(parts_[part].has_normals ? normals_[v] : flat);
      }
    }
    positions_ = std::move(positions), normals_ = std::move(normals),
    indices_ = std::move(indices);
  }
  scene->positions = std::move(positions_);
  scene->normals = std::move(normals_);
  scene->uvs.clear();
  scene->indices = std::move(indices_);
  scene->material_ids = std::move(material_ids_);
}

}  // namespace multiray::detail
