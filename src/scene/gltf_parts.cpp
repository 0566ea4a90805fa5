#include "scene/gltf_parts.h"

#include <algorithm>
#include <cmath>

#include "scene/loaders.h"

namespace multiray::detail {

namespace tg = tinygltf;

// tinygltf image callback: keeps the encoded bytes (as_is) for later decoding. Images
// in a bufferView whose range lies outside its buffer are dropped, because tinygltf
// hands us a pointer into the buffer without checking the range. Always succeeds.
bool keep_encoded_image(tg::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void* user) {
  const tg::Model* model = static_cast<const tg::Model*>(user);
  image->as_is = true;
  image->image.clear();
  if (image->bufferView >= 0) {
    const tg::BufferView& bv = model->bufferViews[size_t(image->bufferView)];
    const size_t have = model->buffers[size_t(bv.buffer)].data.size();
    if (bv.byteOffset > have || bv.byteLength > have - bv.byteOffset) return true;
  }
  if (bytes != nullptr && size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

AccessorView checked_accessor(const tg::Model& model, int index, const std::string& what,
                              int want_type, std::initializer_list<int> component_types,
                              const std::string& path) {
  auto fail = [&](const std::string& why) { detail::fail(path, why); };
  if (index < 0 || size_t(index) >= model.accessors.size())
    fail(what + ": accessor " + std::to_string(index) + " does not exist");
  const tg::Accessor& a = model.accessors[size_t(index)];
  const std::string name = what + " (accessor " + std::to_string(index) + ")";
  if (a.sparse.isSparse) fail(name + ": sparse accessors are not supported");
  if (a.type != want_type || std::find(component_types.begin(), component_types.end(),
                                       a.componentType) == component_types.end())
    fail(name + ": unsupported element type or component type");
  if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size())
    fail(name + ": has no valid bufferView");
  const tg::BufferView& bv = model.bufferViews[size_t(a.bufferView)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
    fail(name + ": bufferView refers to a missing buffer");
  const std::vector<unsigned char>& data = model.buffers[size_t(bv.buffer)].data;
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
    fail(name + ": bufferView " + std::to_string(a.bufferView) +
         " extends past the end of its buffer");
  AccessorView v;
  v.type = a.componentType;
  v.ncomp = tg::GetNumComponentsInType(uint32_t(a.type));
  v.normalized = a.normalized;
  v.count = a.count;
  const size_t elem = size_t(tg::GetComponentSizeInBytes(uint32_t(a.componentType))) * v.ncomp;
  v.stride = bv.byteStride ? bv.byteStride : elem;
  if (v.stride < elem) fail(name + ": byteStride is smaller than an element");
  if (a.count > 0 && (a.byteOffset > bv.byteLength || elem > bv.byteLength - a.byteOffset ||
                      a.count - 1 > (bv.byteLength - a.byteOffset - elem) / v.stride))
    fail(name + ": " + std::to_string(a.count) + " elements extend past the end of bufferView " +
         std::to_string(a.bufferView));
  v.base = data.data() + bv.byteOffset + a.byteOffset;
  return v;
}

Mat4 local_transform(const tg::Node& n) {
  Mat4 m;
  if (n.matrix.size() == 16) {  // column-major in glTF
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m.m[r][c] = to_float(n.matrix[size_t(c) * 4 + r]);
    return m;
  }
  Mat4 t, r, s;
  if (n.translation.size() == 3)
    for (int i = 0; i < 3; ++i) t.m[i][3] = to_float(n.translation[i]);
  if (n.rotation.size() == 4) {
    double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    const double len = std::sqrt(x * x + y * y + z * z + w * w);
    if (len > 0) x /= len, y /= len, z /= len, w /= len;
    const double q[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = float(q[i][j]);
  }
  if (n.scale.size() == 3)
    for (int i = 0; i < 3; ++i) s.m[i][i] = to_float(n.scale[i]);
  return t * r * s;
}

float det3(const Mat4& a) {
  const auto& m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

}  // namespace multiray::detail
