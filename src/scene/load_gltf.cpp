// glTF 2.0 (.gltf / .glb) through tinygltf 2.7 (Debian's compiled library).
//
// tinygltf parses the JSON and loads buffers, but does not check that accessors stay
// inside their buffers, so every accessor is bounds-checked here before it is read.
// Images are not decoded by tinygltf: a custom image callback keeps the encoded bytes
// and always succeeds, so a missing or corrupt image never fails the scene, and only
// the images a material actually uses are decoded (with stb_image) afterwards.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <optional>

#include "scene/gltf_parts.h"
#include "scene/loaders.h"

namespace multiray {
namespace {

namespace tg = tinygltf;
using detail::AccessorView;
using View = AccessorView;
using detail::det3;
using detail::keep_encoded_image;
using detail::local_transform;

// Refuse scenes larger than this after instancing (about 10 GB of scene data) rather
// than running out of memory on a hostile node graph that instances a mesh 2^n times.
constexpr size_t kMaxTriangles = size_t(1) << 28;

// One primitive's triangles in mesh space, read once however often it is instanced.
struct Primitive {
  std::vector<Vec3> positions, normals;  // normals always present (flat if absent)
  std::vector<Vec2> uvs;                 // empty if the primitive has no TEXCOORD_0
  std::vector<uint32_t> indices;
  int material = -1;
};

// Reads one parsed model into a Scene. Use once: read() keeps its walk state in members.
class GltfReader {
 public:
  GltfReader(const std::string& path, const tg::Model& model)
      : path_(path), m_(model), on_path_(model.nodes.size(), 0) {}
  // The scene of the model: every mesh instance of the hierarchy baked into world space,
  // materials (plus a "default" one if some primitive has none), textures and cameras.
  Scene read();

 private:
  [[noreturn]] void fail(const std::string& what) const { detail::fail(path_, what); }
  View view(int accessor, const std::string& what, int want_type,
            std::initializer_list<int> component_types) const;
  const std::vector<Primitive>& mesh(int index);
  Material material(const tg::Material& gm, Scene* scene);
  const std::vector<unsigned char>* image_bytes(int texture_index, int* image) const;
  int texture(int texture_index, Scene* scene);
  Vec3 mean_color(int texture_index) const;

  // The node walk behind read().
  std::vector<int> roots() const;
  void walk(int root, Scene* scene);
  Mat4 enter(int index, const Mat4& parent, Scene* scene);
  void add_camera(const tg::Node& node, const Mat4& world, Scene* scene) const;
  void add_instance(int mesh_index, const Mat4& world, Scene* scene);
  uint32_t material_id(const Primitive& p, Scene* scene);

  const std::string& path_;
  const tg::Model& m_;
  std::map<int, std::vector<Primitive>> meshes_;
  std::map<int, int> texture_of_image_;
  // Walk state.
  std::vector<char> on_path_;  // per node: 1 while it is on the current path
  size_t triangles_ = 0;       // triangles added so far, instances counted
  bool any_uvs_ = false;       // some instanced primitive has TEXCOORD_0
  std::optional<uint32_t> default_material_;
};

View GltfReader::view(int index, const std::string& what, int want_type,
                      std::initializer_list<int> component_types) const {
  return detail::checked_accessor(m_, index, what, want_type, component_types, path_);
}

const std::vector<Primitive>& GltfReader::mesh(int index) {
  if (auto it = meshes_.find(index); it != meshes_.end()) return it->second;
  if (size_t(index) >= m_.meshes.size())
    fail("node refers to missing mesh " + std::to_string(index));
  std::vector<Primitive>& out = meshes_[index];
  const tg::Mesh& gm = m_.meshes[size_t(index)];
  for (size_t p = 0; p < gm.primitives.size(); ++p) {
    const tg::Primitive& gp = gm.primitives[p];
    if (gp.mode != TINYGLTF_MODE_TRIANGLES) continue;  // points, lines, strips: skipped
    const std::string what = "mesh '" + gm.name + "' primitive " + std::to_string(p);
    auto attr = [&](const char* name) {
      auto it = gp.attributes.find(name);
      return it == gp.attributes.end() ? -1 : it->second;
    };
    if (attr("POSITION") < 0) fail(what + ": no POSITION attribute");
    const View pos = view(attr("POSITION"), what + " POSITION", TINYGLTF_TYPE_VEC3,
                          {TINYGLTF_COMPONENT_TYPE_FLOAT});
    Primitive prim;
    prim.material = gp.material;
    if (gp.material >= int(m_.materials.size()))
      fail(what + ": refers to missing material " + std::to_string(gp.material));
    std::vector<uint32_t> idx;
    if (gp.indices >= 0) {
      const View iv =
          view(gp.indices, what + " indices", TINYGLTF_TYPE_SCALAR,
               {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
      idx.resize(iv.count - iv.count % 3);
      for (size_t i = 0; i < idx.size(); ++i)
        if ((idx[i] = iv.index(i)) >= pos.count)
          fail(what + ": index " + std::to_string(idx[i]) + " is out of range (" +
               std::to_string(pos.count) + " vertices)");
    } else {
      if (pos.count > UINT32_MAX) fail(what + ": too many vertices");
      idx.resize(pos.count - pos.count % 3);
      for (size_t i = 0; i < idx.size(); ++i) idx[i] = uint32_t(i);
    }
    View nrm, uv;
    const bool has_n = attr("NORMAL") >= 0, has_uv = attr("TEXCOORD_0") >= 0;
    if (has_n)
      nrm = view(attr("NORMAL"), what + " NORMAL", TINYGLTF_TYPE_VEC3,
                 {TINYGLTF_COMPONENT_TYPE_FLOAT});
    if (has_uv)
      uv = view(attr("TEXCOORD_0"), what + " TEXCOORD_0", TINYGLTF_TYPE_VEC2,
                {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
    if ((has_n && nrm.count != pos.count) || (has_uv && uv.count != pos.count))
      fail(what + ": attribute counts differ from the POSITION count");
    auto p3 = [](const View& v, size_t i) { return Vec3(v.get(i, 0), v.get(i, 1), v.get(i, 2)); };
    if (has_n) {  // indexed as in the file
      prim.indices = std::move(idx);
      for (size_t i = 0; i < pos.count; ++i) prim.positions.push_back(p3(pos, i));
      for (size_t i = 0; i < pos.count; ++i) prim.normals.push_back(normalize(p3(nrm, i)));
      for (size_t i = 0; has_uv && i < pos.count; ++i)
        prim.uvs.push_back(Vec2{uv.get(i, 0), uv.get(i, 1)});
    } else {  // the spec asks for flat normals: one vertex per corner
      for (size_t t = 0; t < idx.size(); t += 3) {
        const Vec3 a = p3(pos, idx[t]), b = p3(pos, idx[t + 1]), c = p3(pos, idx[t + 2]);
        const Vec3 n = normalize(cross(b - a, c - a));
        for (int k = 0; k < 3; ++k) {
          prim.indices.push_back(uint32_t(prim.positions.size()));
          prim.positions.push_back(p3(pos, idx[t + k]));
          prim.normals.push_back(n);
          if (has_uv) prim.uvs.push_back(Vec2{uv.get(idx[t + k], 0), uv.get(idx[t + k], 1)});
        }
      }
    }
    out.push_back(std::move(prim));
  }
  return out;
}

// Encoded bytes of the image behind texture `texture_index` (its index in *image), or
// null when the texture or image does not exist.
const std::vector<unsigned char>* GltfReader::image_bytes(int texture_index, int* image) const {
  if (texture_index < 0 || size_t(texture_index) >= m_.textures.size()) return nullptr;
  *image = m_.textures[size_t(texture_index)].source;
  if (*image < 0 || size_t(*image) >= m_.images.size()) return nullptr;
  return &m_.images[size_t(*image)].image;
}

// Index into scene->textures of the decoded texture, or -1 if it cannot be decoded.
int GltfReader::texture(int texture_index, Scene* scene) {
  int image = -1;
  const std::vector<unsigned char>* bytes = image_bytes(texture_index, &image);
  if (bytes == nullptr) return -1;
  if (auto it = texture_of_image_.find(image); it != texture_of_image_.end()) return it->second;
  Texture tex;
  int result = -1;
  if (detail::decode_texture(bytes->data(), bytes->size(), &tex)) {
    result = int(scene->textures.size());
    scene->textures.push_back(std::move(tex));
  }
  return texture_of_image_[image] = result;
}

// Mean linear colour of a texture; zero if it cannot be decoded.
Vec3 GltfReader::mean_color(int texture_index) const {
  int image = -1;
  const std::vector<unsigned char>* bytes = image_bytes(texture_index, &image);
  Texture tex;
  if (bytes == nullptr || !detail::decode_texture(bytes->data(), bytes->size(), &tex))
    return Vec3(0.0f);
  double sum[3] = {0, 0, 0};
  for (int y = 0; y < tex.height; ++y)
    for (int x = 0; x < tex.width; ++x) {
      const Vec3 c = tex.texel(x, y);
      for (int k = 0; k < 3; ++k) sum[k] += c[k];
    }
  const double n = double(tex.srgb8.size());
  return Vec3(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
}

// Number `key` of extension `ext` in `exts`, or `fallback`.
double ext_number(const tg::ExtensionMap& exts, const char* ext, const char* key,
                  double fallback) {
  auto it = exts.find(ext);
  if (it == exts.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
  const tg::Value& v = it->second.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// Contract: base colour factor (and texture, if set and on TEXCOORD_0), emissive factor
// x KHR_materials_emissive_strength, metallic, roughness, KHR_materials_transmission,
// KHR_materials_ior. The material model has no emission texture, so an emissive
// texture is folded in as its mean colour (zero if it cannot be decoded), which keeps
// the emitted power instead of lighting the whole surface at full factor.
Material GltfReader::material(const tg::Material& gm, Scene* scene) {
  Material out;
  out.name = gm.name;
  const tg::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() >= 3)
    out.base_color = Vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                          float(pbr.baseColorFactor[2]));
  if (pbr.baseColorTexture.index >= 0 && pbr.baseColorTexture.texCoord == 0)
    out.base_color_texture = texture(pbr.baseColorTexture.index, scene);
  out.metallic = std::clamp(float(pbr.metallicFactor), 0.0f, 1.0f);
  out.roughness = std::clamp(float(pbr.roughnessFactor), 0.0f, 1.0f);
  if (gm.emissiveFactor.size() >= 3) {
    const float s = float(
        ext_number(gm.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0));
    out.emission = Vec3(float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]),
                        float(gm.emissiveFactor[2])) *
                   s;
  }
  if (gm.emissiveTexture.index >= 0 && max_component(out.emission) > 0)
    out.emission *= mean_color(gm.emissiveTexture.index);
  out.transmission = std::clamp(
      float(ext_number(gm.extensions, "KHR_materials_transmission", "transmissionFactor", 0)),
      0.0f, 1.0f);
  out.ior = float(ext_number(gm.extensions, "KHR_materials_ior", "ior", 1.5));
  if (!(out.ior >= 1.0f)) out.ior = 1.5f;  // also catches NaN
  if (!is_finite(out.base_color) || !is_finite(out.emission))
    fail("material '" + gm.name + "' has a non-finite colour");
  return out;
}

// Roots of the node walk: the default scene's nodes, else scene 0's, else (a file
// without scenes) every node that is nobody's child.
std::vector<int> GltfReader::roots() const {
  if (!m_.scenes.empty()) {
    const int s =
        m_.defaultScene >= 0 && size_t(m_.defaultScene) < m_.scenes.size() ? m_.defaultScene : 0;
    return m_.scenes[size_t(s)].nodes;
  }
  std::vector<char> is_child(m_.nodes.size(), 0);
  for (const tg::Node& n : m_.nodes)
    for (int c : n.children)
      if (c >= 0 && size_t(c) < is_child.size()) is_child[size_t(c)] = 1;
  std::vector<int> roots;
  for (size_t i = 0; i < m_.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(int(i));
  return roots;
}

// Depth-first walk of the hierarchy under `root`, with an explicit stack. A node already
// on the current path means the hierarchy has a cycle (invalid glTF), which would
// otherwise never end; enter() fails on it.
void GltfReader::walk(int root, Scene* scene) {
  struct Frame {
    int node;
    Mat4 world;
    size_t next_child = 0;
  };
  std::vector<Frame> stack;
  stack.push_back({root, enter(root, Mat4(), scene)});
  while (!stack.empty()) {
    Frame& f = stack.back();
    const std::vector<int>& children = m_.nodes[size_t(f.node)].children;
    if (f.next_child < children.size()) {
      const int child = children[f.next_child++];
      const Mat4 world = f.world;  // `f` dangles once the stack grows
      stack.push_back({child, enter(child, world, scene)});
    } else {
      on_path_[size_t(f.node)] = 0;
      stack.pop_back();
    }
  }
}

// Enters node `index`, whose parent has world transform `parent`: fails if the node does
// not exist or is already on the current path, marks it on the path (walk() unmarks it
// when leaving), adds its camera and its mesh instance to *scene, and returns its world
// transform.
Mat4 GltfReader::enter(int index, const Mat4& parent, Scene* scene) {
  if (index < 0 || size_t(index) >= m_.nodes.size())
    fail("node " + std::to_string(index) + " does not exist");
  if (on_path_[size_t(index)])
    fail("node hierarchy has a cycle through node " + std::to_string(index));
  on_path_[size_t(index)] = 1;
  const tg::Node& node = m_.nodes[size_t(index)];
  const Mat4 world = parent * local_transform(node);
  add_camera(node, world, scene);
  if (node.mesh >= 0) add_instance(node.mesh, world, scene);
  return world;
}

// Appends the node's camera to scene->cameras if it is a perspective camera that yields
// a finite eye and a field of view in (0, 180) degrees; other cameras are ignored.
void GltfReader::add_camera(const tg::Node& node, const Mat4& world, Scene* scene) const {
  if (node.camera < 0 || size_t(node.camera) >= m_.cameras.size() ||
      m_.cameras[size_t(node.camera)].type != "perspective")
    return;
  Camera cam;
  cam.eye = world.point(Vec3(0, 0, 0));
  cam.target = cam.eye + normalize(world.vector(Vec3(0, 0, -1)));
  cam.up = normalize(world.vector(Vec3(0, 1, 0)));
  cam.fov_y_deg = float(m_.cameras[size_t(node.camera)].perspective.yfov * 180.0 / kPi);
  if (is_finite(cam.eye) && cam.fov_y_deg > 0 && cam.fov_y_deg < 180)
    scene->cameras.push_back(cam);
}

// Appends mesh `mesh_index` transformed by `world` to *scene: vertices in world space,
// triangles wound consistently even under a mirroring transform, one material id per
// triangle. Fails when the scene would exceed kMaxTriangles.
void GltfReader::add_instance(int mesh_index, const Mat4& world, Scene* scene) {
  const Mat4 nm = world.normal_matrix();
  const bool flip = det3(world) < 0;  // mirroring: keep the winding consistent
  for (const Primitive& p : mesh(mesh_index)) {
    triangles_ += p.indices.size() / 3;
    if (triangles_ > kMaxTriangles)
      fail("more than " + std::to_string(kMaxTriangles) + " triangles after instancing");
    const uint32_t mat = material_id(p, scene);
    const uint32_t base = uint32_t(scene->positions.size());
    for (size_t i = 0; i < p.positions.size(); ++i) {
      scene->positions.push_back(world.point(p.positions[i]));
      scene->normals.push_back(normalize(nm.vector(p.normals[i])));
      scene->uvs.push_back(p.uvs.empty() ? Vec2{} : p.uvs[i]);
    }
    any_uvs_ |= !p.uvs.empty();
    for (size_t t = 0; t < p.indices.size(); t += 3) {
      scene->indices.push_back(base + p.indices[t]);
      scene->indices.push_back(base + p.indices[t + (flip ? 2 : 1)]);
      scene->indices.push_back(base + p.indices[t + (flip ? 1 : 2)]);
      scene->material_ids.push_back(mat);
    }
  }
}

// Index into scene->materials for primitive `p`: its own material, or for primitives
// without one a "default" material appended on first use.
uint32_t GltfReader::material_id(const Primitive& p, Scene* scene) {
  if (p.material >= 0) return uint32_t(p.material);
  if (!default_material_) {
    default_material_ = uint32_t(scene->materials.size());
    scene->materials.emplace_back().name = "default";
  }
  return *default_material_;
}

Scene GltfReader::read() {
  Scene scene;
  scene.name = detail::file_name(path_);
  for (const tg::Material& gm : m_.materials) scene.materials.push_back(material(gm, &scene));
  for (int root : roots()) walk(root, &scene);
  // Every vertex got a uv (zero where its primitive has none); keep them only if any is real.
  if (!any_uvs_) scene.uvs.clear();
  return scene;
}

}  // namespace

Scene load_gltf(const std::string& path) {
  const std::string bytes = detail::read_file(path);  // clear messages for missing/empty
  tg::Model model;
  tg::TinyGLTF ctx;
  ctx.SetImageLoader(&keep_encoded_image, &model);
  std::string err, warn;
  const std::string base_dir = [&] {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
  }();
  if (bytes.size() > UINT32_MAX) detail::fail(path, "file too large for tinygltf");
  bool ok = false;
  try {
    if (bytes.compare(0, 4, "glTF") == 0)  // binary container, whatever the extension
      ok = ctx.LoadBinaryFromMemory(&model, &err, &warn,
                                    reinterpret_cast<const unsigned char*>(bytes.data()),
                                    unsigned(bytes.size()), base_dir);
    else
      ok = ctx.LoadASCIIFromString(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                   base_dir);
  } catch (const std::exception& e) {
    detail::fail(path, std::string("malformed glTF: ") + e.what());
  }
  if (!ok)
    detail::fail(path, "malformed glTF: " + (err.empty() ? std::string("parse error") : err));
  Scene scene = GltfReader(path, model).read();
  detail::validate_loaded(scene, path);
  return scene;
}

}  // namespace multiray
