// Geometry for the Mitsuba 3 reader: Mitsuba's built-in meshes and the merge of every
// shape into one Scene. Private to src/scene (used by load_mitsuba.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace multiray::detail {

// Mitsuba's `rectangle`: the square [-1, 1]^2 in the z = 0 plane, facing +z.
Scene mitsuba_rectangle();
// Mitsuba's `cube`: [-1, 1]^3, faces outwards, flat-shaded.
Scene mitsuba_cube();

// Collects shapes into one scene. Each part keeps its triangles and its shading normals
// (if it has them); uvs are dropped (the reader makes no textures). finish() gives parts
// without normals flat ones when other parts have some, since Scene::normals is all or
// nothing.
class ShapeMerger {
 public:
  // Appends `part` with every position moved by `to_world` (normals by its inverse
  // transpose) and every triangle given `material`. `flip` reverses the winding and the
  // normals (Mitsuba's flip_normals: an area light then emits from the other side).
  void append(const Scene& part, const Mat4& to_world, uint32_t material, bool flip);

  // Moves the merged triangles into `scene` (its materials and cameras are left alone).
  void finish(Scene* scene);

 private:
  struct Part {
    size_t first_index;
    bool has_normals;
  };
  std::vector<Part> parts_;
  std::vector<Vec3> positions_, normals_;  // normals_: NaN where a part has none
  std::vector<uint32_t> indices_, material_ids_;
};

}  // namespace multiray::detail
