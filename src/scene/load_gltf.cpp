// glTF 2.0 (.gltf / .glb) through tinygltf 2.7 (Debian's compiled library).
//
// tinygltf parses the JSON and loads buffers, but does not check that accessors stay
// inside their buffers, so every accessor is bounds-checked here before it is read.
// Images are not decoded by tinygltf: a custom image callback keeps the encoded bytes
// and always succeeds, so a missing or corrupt image never fails the scene, and only
// the images a material actually uses are decoded (with stb_image) afterwards.
// tinygltf reads buffer and image files through our file callbacks, which go through
// SceneFiles: it never opens a FIFO, a file outside the model's folder or past the byte
// limit. The node graph is measured before any instance is built (check_instancing).
#include <sys/stat.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>

#include "core/scene_files.h"
#include "scene/camera_check.h"
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
// Vertices after instancing: three per triangle at most for sane meshes, and below 2^32
// so that uint32_t indices cannot wrap.
constexpr size_t kMaxVertices = 3 * kMaxTriangles;
// Node visits of the walk (each one a matrix product, maybe a camera): a graph of empty
// nodes nested 10 deep with 10 children each would otherwise take 10^10 steps.
constexpr size_t kMaxNodeInstances = size_t(1) << 24;

// A file SceneFiles refused to read for tinygltf, and why.
struct RefusedFile {
  std::string path, why;
};

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
  // `refused`: the files SceneFiles refused while tinygltf loaded the model (only images
  // can be, in a model that loaded); each is reported once, with its reason.
  GltfReader(const std::string& path, const tg::Model& model, const LoadOptions& options,
             const std::vector<RefusedFile>& refused)
      : path_(path),
        m_(model),
        options_(options),
        refused_(refused),
        on_path_(model.nodes.size(), 0) {}
  // The scene of the model: every mesh instance of the hierarchy baked into world space,
  // materials (plus a "default" one if some primitive has none), textures and cameras.
  // Fails before building anything when check_instancing() does.
  Scene read();

 private:
  [[noreturn]] void fail(const std::string& what) const { detail::fail(path_, what); }
  View view(int accessor, const std::string& what, int want_type,
            std::initializer_list<int> component_types) const;
  const std::vector<Primitive>& mesh(int index);
  Material material(const tg::Material& gm, Scene* scene);
  struct TextureRef {
    int index = -1, tex_coord = 0;
  };
  const std::vector<unsigned char>* image_bytes(int texture_index, int* image) const;
  int texture(const TextureRef& info, TexelCoding coding, const std::string& material,
              Scene* scene);
  void warn_unsupported_extensions() const;
  std::string why_unread(const std::string& uri);

  // The node walk behind read().
  std::vector<int> roots() const;
  void check_instancing(const std::vector<int>& roots);
  void walk(int root, Scene* scene);
  Mat4 enter(int index, const Mat4& parent, Scene* scene);
  void add_camera(const tg::Node& node, const Mat4& world, Scene* scene);
  void add_instance(int mesh_index, const Mat4& world, Scene* scene);
  uint32_t material_id(const Primitive& p, Scene* scene);

  const std::string& path_;
  const tg::Model& m_;
  const LoadOptions& options_;
  const std::vector<RefusedFile>& refused_;
  std::vector<char> refusal_told_;  // per refused_ entry
  std::map<int, std::vector<Primitive>> meshes_;
  std::map<std::pair<int, int>, int> texture_of_image_;  // (image, coding) -> texture
  std::set<int> warned_images_;
  // Walk state.
  std::vector<char> on_path_;   // per node: 1 while it is on the current path
  size_t triangles_ = 0;        // triangles added so far, instances counted
  bool any_uvs_ = false;        // some instanced primitive has TEXCOORD_0
  size_t dropped_cameras_ = 0;  // cameras camera_problem() refused
  std::string camera_problem_;  // the first one's problem
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
      for (size_t i = 0; i < pos.count; ++i)
        prim.normals.push_back(detail::shading_normal(p3(nrm, i)));  // NaN if unusable
      for (size_t i = 0; has_uv && i < pos.count; ++i)
        prim.uvs.push_back(Vec2{uv.get(i, 0), uv.get(i, 1)});
    } else {  // the spec asks for flat normals: one vertex per corner
      for (size_t t = 0; t < idx.size(); t += 3) {
        const Vec3 a = p3(pos, idx[t]), b = p3(pos, idx[t + 1]), c = p3(pos, idx[t + 2]);
        const Vec3 n = detail::flat_normal(a, b, c);
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

// Index into scene->textures of texture `info` decoded as `coding`, or -1 when it
// cannot be used; then one warning per image (missing file, not an image, a texture
// coordinate set other than 0) says what the material does instead.
int GltfReader::texture(const TextureRef& info, TexelCoding coding, const std::string& material,
                        Scene* scene) {
  if (info.index < 0) return -1;
  int image = -1;
  const std::vector<unsigned char>* bytes = image_bytes(info.index, &image);
  auto warn_once = [&](const std::string& why) {
    if (warned_images_.insert(image).second)
      detail::warn(options_, path_,
                   why + "; material '" + material + "' (and any other using it) renders with " +
                       "its factor alone");
  };
  if (bytes == nullptr) {
    warn_once("texture " + std::to_string(info.index) + " refers to a missing image");
    return -1;
  }
  const std::string name = m_.images[size_t(image)].uri.empty()
                               ? "image " + std::to_string(image)
                               : "image '" + m_.images[size_t(image)].uri + "'";
  if (info.tex_coord != 0) {
    warn_once(name + " is mapped by TEXCOORD_" + std::to_string(info.tex_coord) +
              " (only TEXCOORD_0 is supported)");
    return -1;
  }
  const auto key = std::make_pair(image, int(coding));
  if (auto it = texture_of_image_.find(key); it != texture_of_image_.end()) return it->second;
  Texture tex;
  int result = -1;
  if (bytes->empty()) {
    warn_once(name + " " + why_unread(m_.images[size_t(image)].uri));
  } else if (detail::decode_texture(bytes->data(), bytes->size(), &tex, options_,
                                    path_ + ": " + name, coding)) {
    result = int(scene->textures.size());
    scene->textures.push_back(std::move(tex));
  } else {
    warn_once(name + " is not a decodable image (or over " +
              std::to_string(detail::kMaxTexturePixels) + " pixels)");
  }
  return texture_of_image_[key] = result;
}

// Why the image file `uri` has no bytes: SceneFiles' reason if it refused the file, else
// that it was not found.
std::string GltfReader::why_unread(const std::string& uri) {
  refusal_told_.resize(refused_.size(), 0);
  for (size_t i = 0; i < refused_.size(); ++i) {
    const std::string& p = refused_[i].path;
    if (uri.empty() || p.size() < uri.size() || p.compare(p.size() - uri.size(), uri.size(), uri))
      continue;
    refusal_told_[i] = 1;
    return "was refused: " + refused_[i].why;
  }
  return "was not found or could not be read";
}

// Number `key` of extension `ext` in `exts`, or `fallback`.
double ext_number(const tg::ExtensionMap& exts, const char* ext, const char* key,
                  double fallback) {
  auto it = exts.find(ext);
  if (it == exts.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
  const tg::Value& v = it->second.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// Contract: base colour factor and texture (with its alpha: alphaMode, alphaCutoff),
// emissive factor x KHR_materials_emissive_strength and emissive texture, metallic and
// roughness factors and their texture, normal texture and scale, KHR_materials_transmission,
// KHR_materials_ior. Occlusion textures are not read (see Material). Out-of-range factors
// are clamped to glTF's ranges.
Material GltfReader::material(const tg::Material& gm, Scene* scene) {
  Material out;
  out.name = gm.name;
  const tg::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() >= 3)
    out.base_color = Vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                          float(pbr.baseColorFactor[2]));
  if (pbr.baseColorFactor.size() >= 4)
    out.opacity = std::clamp(float(pbr.baseColorFactor[3]), 0.0f, 1.0f);  // NaN stays NaN
  out.base_color_texture = texture({pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord},
                                   TexelCoding::srgb, gm.name, scene);
  out.metallic = std::clamp(float(pbr.metallicFactor), 0.0f, 1.0f);
  out.roughness = std::clamp(float(pbr.roughnessFactor), 0.0f, 1.0f);
  out.metallic_roughness_texture =
      texture({pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord},
              TexelCoding::linear, gm.name, scene);
  out.normal_texture = texture({gm.normalTexture.index, gm.normalTexture.texCoord},
                               TexelCoding::signed_unit, gm.name, scene);
  out.normal_scale = float(gm.normalTexture.scale);
  if (gm.emissiveFactor.size() >= 3) {
    const float s = float(
        ext_number(gm.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0));
    out.emission = Vec3(float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]),
                        float(gm.emissiveFactor[2])) *
                   s;
  }
  if (max_component(out.emission) > 0)
    out.emission_texture = texture({gm.emissiveTexture.index, gm.emissiveTexture.texCoord},
                                   TexelCoding::srgb, gm.name, scene);
  if (gm.alphaMode == "MASK") out.alpha_mode = AlphaMode::mask;
  if (gm.alphaMode == "BLEND") out.alpha_mode = AlphaMode::blend;
  out.alpha_cutoff = float(gm.alphaCutoff);
  out.transmission = std::clamp(
      float(ext_number(gm.extensions, "KHR_materials_transmission", "transmissionFactor", 0)),
      0.0f, 1.0f);
  out.ior = float(ext_number(gm.extensions, "KHR_materials_ior", "ior", 1.5));
  if (!(out.ior >= 1.0f)) out.ior = 1.5f;  // also catches NaN
  if (!is_finite(out.base_color) || !is_finite(out.emission))
    fail("material '" + gm.name + "' has a non-finite colour");
  if (!std::isfinite(out.normal_scale) || !(out.opacity >= 0) || !std::isfinite(out.alpha_cutoff))
    fail("material '" + gm.name + "' has a non-finite normal scale, alpha or alpha cutoff");
  return out;
}

// One warning per extension the file uses that the reader ignores, so that a scene that
// looks wrong says why (e.g. KHR_materials_clearcoat, KHR_texture_transform). Required
// ones are named as such: the file's author said it cannot be shown correctly without.
void GltfReader::warn_unsupported_extensions() const {
  static const std::set<std::string> kSupported = {
      "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior"};
  for (const std::string& ext : m_.extensionsUsed) {
    if (kSupported.count(ext)) continue;
    const bool required = std::find(m_.extensionsRequired.begin(), m_.extensionsRequired.end(),
                                    ext) != m_.extensionsRequired.end();
    detail::warn(options_, path_,
                 "uses " + std::string(required ? "required " : "") + "extension " + ext +
                     ", which multiray does not support; rendered without it");
  }
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

namespace {

// Triangles, vertices and node visits a subtree adds when walked once. Sums saturate at
// UINT64_MAX instead of wrapping.
struct Cost {
  uint64_t triangles = 0, vertices = 0, nodes = 0;
  Cost& operator+=(const Cost& o) {
    auto add = [](uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; };
    triangles = add(triangles, o.triangles);
    vertices = add(vertices, o.vertices);
    nodes = add(nodes, o.nodes);
    return *this;
  }
};

std::string count_text(uint64_t n) { return n == UINT64_MAX ? "over 1.8e19" : std::to_string(n); }

}  // namespace

// What walking `roots` would build, computed per node once (memoised over the node
// graph, a DAG when valid) in time linear in nodes + child links, so a 1 KB file whose
// nodes instance their children 10 times, 10 levels deep, is refused at once instead of
// after gigabytes. A child listed k times counts k times: that is the instance
// multiplication. Fails like walk() on missing nodes and cycles (a node met again while
// it is still on the depth-first path), and when the totals exceed the caps.
void GltfReader::check_instancing(const std::vector<int>& roots) {
  enum : char { kNew, kOnPath, kDone };
  std::vector<char> state(m_.nodes.size(), kNew);
  std::vector<Cost> cost(m_.nodes.size());
  auto reach = [&](int index) {  // true if `index` still needs to be visited
    if (index < 0 || size_t(index) >= m_.nodes.size())
      fail("node " + std::to_string(index) + " does not exist");
    if (state[size_t(index)] == kOnPath)
      fail("node hierarchy has a cycle through node " + std::to_string(index));
    if (state[size_t(index)] == kDone) return false;
    state[size_t(index)] = kOnPath;
    return true;
  };
  struct Frame {
    int node;
    size_t next_child = 0;
  };
  Cost total;
  for (int root : roots) {
    std::vector<Frame> stack;
    if (reach(root)) stack.push_back({root});
    while (!stack.empty()) {
      Frame& f = stack.back();
      const tg::Node& node = m_.nodes[size_t(f.node)];
      if (f.next_child < node.children.size()) {
        const int child = node.children[f.next_child++];
        if (reach(child)) stack.push_back({child});
        continue;
      }
      Cost c;
      c.nodes = 1;
      if (node.mesh >= 0)
        for (const Primitive& p : mesh(node.mesh)) {
          c.triangles += p.indices.size() / 3;
          c.vertices += p.positions.size();
        }
      for (int child : node.children) c += cost[size_t(child)];
      cost[size_t(f.node)] = c;
      state[size_t(f.node)] = kDone;
      stack.pop_back();
    }
    total += cost[size_t(root)];
  }
  auto refuse = [&](uint64_t n, const char* what, size_t limit) {
    fail("the node hierarchy instances " + count_text(n) + " " + what +
         ", more than the limit of " + std::to_string(limit) +
         " (refused before building any instance)");
  };
  if (total.triangles > kMaxTriangles) refuse(total.triangles, "triangles", kMaxTriangles);
  if (total.vertices > kMaxVertices) refuse(total.vertices, "vertices", kMaxVertices);
  if (total.nodes > kMaxNodeInstances) refuse(total.nodes, "nodes", kMaxNodeInstances);
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

// Appends the node's camera to scene->cameras if it is a perspective camera that
// camera_problem() accepts; other perspective cameras are counted for one warning, and
// orthographic ones are ignored.
void GltfReader::add_camera(const tg::Node& node, const Mat4& world, Scene* scene) {
  if (node.camera < 0 || size_t(node.camera) >= m_.cameras.size() ||
      m_.cameras[size_t(node.camera)].type != "perspective")
    return;
  Camera cam;
  cam.eye = world.point(Vec3(0, 0, 0));
  // The target one unit ahead, or further where float cannot resolve that from the eye
  // (an eye at 1e8 plus a unit vector rounds back to the eye).
  const float reach = std::max(
      1.0f, 1e-3f * std::max({std::abs(cam.eye.x), std::abs(cam.eye.y), std::abs(cam.eye.z)}));
  cam.target = cam.eye + normalize(world.vector(Vec3(0, 0, -1))) * reach;
  cam.up = normalize(world.vector(Vec3(0, 1, 0)));
  cam.fov_y_deg = detail::to_float(m_.cameras[size_t(node.camera)].perspective.yfov * 180.0 / kPi);
  const std::string problem = camera_problem(cam);
  if (problem.empty()) {
    scene->cameras.push_back(cam);
  } else if (dropped_cameras_++ == 0) {
    camera_problem_ = problem;
  }
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
      scene->normals.push_back(detail::shading_normal(nm.vector(p.normals[i])));
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
  warn_unsupported_extensions();
  for (const tg::Material& gm : m_.materials) scene.materials.push_back(material(gm, &scene));
  const std::vector<int> starts = roots();
  check_instancing(starts);
  for (int root : starts) walk(root, &scene);
  if (dropped_cameras_ > 0)
    detail::warn(options_, path_,
                 std::to_string(dropped_cameras_) + " camera(s) not used: " + camera_problem_);
  // Refused images no material uses (every refusal of a loaded model was an image).
  refusal_told_.resize(refused_.size(), 0);
  for (size_t i = 0; i < refused_.size(); ++i)
    if (!refusal_told_[i]) detail::warn(options_, path_, "image refused: " + refused_[i].why);
  // Every vertex got a uv (zero where its primitive has none); keep them only if any is real.
  if (!any_uvs_) scene.uvs.clear();
  return scene;
}

}  // namespace

namespace {

// tinygltf's file callbacks, so that every buffer and image file goes through SceneFiles.
// FileExists only stat()s (tinygltf's own opens the file, and opening a FIFO blocks);
// a refused read leaves its reason in `refused` and in tinygltf's message.
struct FileAccess {
  SceneFiles* files;
  std::vector<RefusedFile> refused;  // in order
};

bool file_exists(const std::string& path, void*) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

std::string expand_file_path(const std::string& path, void*) { return path; }

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
  auto* access = static_cast<FileAccess*>(user);
  std::string why;
  if (access->files->read(path, out, &why)) return true;
  access->refused.push_back({path, why});
  if (err != nullptr) *err += why;
  return false;
}

}  // namespace

Scene load_gltf(const std::string& path, const LoadOptions& options) {
  SceneFiles files(path, options);
  const std::string bytes = files.read_scene_file();  // clear messages for missing/empty
  tg::Model model;
  tg::TinyGLTF ctx;
  ctx.SetImageLoader(&keep_encoded_image, &model);
  FileAccess access{&files, {}};
  ctx.SetFsCallbacks(
      tg::FsCallbacks{&file_exists, &expand_file_path, &read_whole_file, nullptr, &access});
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
  if (!ok) {
    // Only buffers are required; a refused one is named in tinygltf's error.
    for (const RefusedFile& r : access.refused)
      if (err.find(r.why) != std::string::npos) detail::fail(path, "buffer refused: " + r.why);
    detail::fail(path, "malformed glTF: " + (err.empty() ? std::string("parse error") : err));
  }
  Scene scene = GltfReader(path, model, options, access.refused).read();
  detail::validate_loaded(&scene, path, options);
  return scene;
}

}  // namespace multiray
