// Every other mesh format through assimp 5.2 (Debian's libassimp-dev): FBX, COLLADA, 3DS,
// Blender, X, STL, OFF, LightWave, ... (kAssimpExtensions in loaders.h). glTF, OBJ and
// PLY keep their own readers, which check their input more strictly.
//
// assimp parses the file (through SceneFileSystem, so LoadOptions apply to every file it
// opens) and triangulates it; everything after that is checked here as if it came from
// the file: every index against its array, every count against the caps, before the
// scene's arrays are allocated. The node hierarchy is baked into world space like the
// glTF loader does; a mesh used by k nodes counts k times.
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <new>
#include <optional>
#include <vector>

#include "scene/assimp_files.h"
#include "scene/assimp_material.h"
#include "scene/assimp_trial.h"
#include "scene/camera_check.h"
#include "scene/loaders.h"

namespace multiray {
namespace {

// The glTF loader's caps (load_gltf.cpp): about 10 GB of scene data after instancing,
// vertex indices that cannot wrap, and a bounded number of node visits.
constexpr uint64_t kMaxTriangles = uint64_t(1) << 28;
constexpr uint64_t kMaxVertices = 3 * kMaxTriangles;
constexpr uint64_t kMaxNodeInstances = uint64_t(1) << 24;
// Image shape assumed for a camera whose file gives no aspect ratio (assimp's
// mAspect == 0): multiray's default image, 640x360.
constexpr float kAssumedAspect = 16.0f / 9.0f;

Mat4 to_mat4(const aiMatrix4x4& a) {  // both row-major, translation in the last column
  Mat4 r;
  const ai_real* src = &a.a1;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = float(src[4 * i + j]);
  return r;
}

float det3(const Mat4& a) {
  const auto& m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Vec3 vec3(const aiVector3D& v) { return Vec3(float(v.x), float(v.y), float(v.z)); }

// What one instance of a mesh adds to the scene. Meshes without normals are stored one
// vertex per corner with face normals when other meshes have normals.
struct MeshSize {
  uint64_t triangles = 0, shared_vertices = 0;
};

class AssimpReader {
 public:
  AssimpReader(const aiScene& ai, SceneFiles* files)
      : ai_(ai), files_(files), path_(files->scene_path()) {}
  Scene read();

 private:
  [[noreturn]] void fail(const std::string& what) const { detail::fail(path_, what); }
  void check_meshes();
  void count_instances();
  [[noreturn]] void refuse_instances() const;
  void walk(Scene* scene);
  void add_instance(const aiMesh& mesh, const Mat4& world, Scene* scene);
  void add_cameras(Scene* scene);

  const aiScene& ai_;
  SceneFiles* files_;
  const std::string& path_;
  std::vector<MeshSize> sizes_;                    // per mesh
  uint64_t triangles_ = 0, vertices_ = 0;          // after instancing
  bool any_normals_ = false, any_uvs_ = false;     // among meshes some node uses
  std::map<std::string, size_t> camera_of_node_;   // node name -> camera index
  std::vector<std::optional<Mat4>> camera_world_;  // per camera, once its node is met
};

// Checks every mesh's arrays and indices (assimp's own validation step is not relied on)
// and measures it.
void AssimpReader::check_meshes() {
  if (ai_.mNumMeshes > 0 && ai_.mMeshes == nullptr) fail("mesh list missing");
  for (unsigned i = 0; i < ai_.mNumMeshes; ++i) {
    const aiMesh* m = ai_.mMeshes[i];
    const std::string what = "mesh " + std::to_string(i);
    if (m == nullptr || (m->mNumVertices > 0 && m->mVertices == nullptr) ||
        (m->mNumFaces > 0 && m->mFaces == nullptr))
      fail(what + " has missing arrays");
    if (m->mMaterialIndex >= ai_.mNumMaterials)
      fail(what + " uses material " + std::to_string(m->mMaterialIndex) + " of " +
           std::to_string(ai_.mNumMaterials));
    MeshSize s;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines: not surfaces
      if (face.mIndices == nullptr) fail(what + " face " + std::to_string(f) + " has no indices");
      for (int k = 0; k < 3; ++k)
        if (face.mIndices[k] >= m->mNumVertices)
          fail(what + " face " + std::to_string(f) + " uses vertex " +
               std::to_string(face.mIndices[k]) + " of " + std::to_string(m->mNumVertices) +
               " (index out of range)");
      ++s.triangles;
    }
    s.shared_vertices = m->mNumVertices;
    sizes_.push_back(s);
  }
}

// Totals after instancing, computed before anything is allocated; fails beyond the caps.
void AssimpReader::count_instances() {
  uint64_t nodes = 0;
  std::vector<const aiNode*> stack{ai_.mRootNode};
  while (!stack.empty()) {
    const aiNode* n = stack.back();
    stack.pop_back();
    if (n == nullptr) continue;
    if (++nodes > kMaxNodeInstances)
      fail("more than " + std::to_string(kMaxNodeInstances) + " nodes");
    if (n->mNumMeshes > 0 && n->mMeshes == nullptr)
      fail("node '" + std::string(n->mName.C_Str()) + "' has no mesh list");
    for (unsigned i = 0; i < n->mNumMeshes; ++i) {
      if (n->mMeshes[i] >= ai_.mNumMeshes)
        fail("node '" + std::string(n->mName.C_Str()) + "' uses mesh " +
             std::to_string(n->mMeshes[i]) + " of " + std::to_string(ai_.mNumMeshes));
      const aiMesh& m = *ai_.mMeshes[n->mMeshes[i]];
      triangles_ += sizes_[n->mMeshes[i]].triangles;  // checked at once: cannot wrap
      if (triangles_ > kMaxTriangles) refuse_instances();
      any_normals_ |= m.mNormals != nullptr;
      any_uvs_ |= m.mTextureCoords[0] != nullptr && m.mNumUVComponents[0] >= 2;
    }
    if (n->mNumChildren > 0 && n->mChildren == nullptr) fail("node child list missing");
    for (unsigned i = 0; i < n->mNumChildren; ++i) stack.push_back(n->mChildren[i]);
  }
  // Second pass for vertices, now that the storage of normal-less meshes is known.
  stack.assign(1, ai_.mRootNode);
  while (!stack.empty()) {
    const aiNode* n = stack.back();
    stack.pop_back();
    if (n == nullptr) continue;
    for (unsigned i = 0; i < n->mNumMeshes; ++i) {
      const aiMesh& m = *ai_.mMeshes[n->mMeshes[i]];
      const MeshSize& s = sizes_[n->mMeshes[i]];
      vertices_ += (any_normals_ && m.mNormals == nullptr) ? 3 * s.triangles : s.shared_vertices;
    }
    for (unsigned i = 0; i < n->mNumChildren; ++i) stack.push_back(n->mChildren[i]);
  }
  if (vertices_ > kMaxVertices) refuse_instances();
}

void AssimpReader::refuse_instances() const {
  fail("the node hierarchy instances over " + std::to_string(triangles_) + " triangles and " +
       std::to_string(vertices_) + " vertices, more than the limit of " +
       std::to_string(kMaxTriangles) + " triangles and " + std::to_string(kMaxVertices) +
       " vertices (refused before building any instance)");
}

// Depth-first walk with an explicit stack (deep hierarchies must not overflow the call
// stack): adds each node's meshes in world space and notes where its camera is.
void AssimpReader::walk(Scene* scene) {
  struct Frame {
    const aiNode* node;
    Mat4 world;
  };
  std::vector<Frame> stack{{ai_.mRootNode, to_mat4(ai_.mRootNode->mTransformation)}};
  while (!stack.empty()) {
    const Frame f = stack.back();
    stack.pop_back();
    for (unsigned i = 0; i < f.node->mNumMeshes; ++i)
      add_instance(*ai_.mMeshes[f.node->mMeshes[i]], f.world, scene);
    const auto cam = camera_of_node_.find(f.node->mName.C_Str());
    if (cam != camera_of_node_.end() && !camera_world_[cam->second])
      camera_world_[cam->second] = f.world;
    // Children pushed last-first so they are visited in file order.
    for (unsigned i = f.node->mNumChildren; i-- > 0;)
      if (const aiNode* child = f.node->mChildren[i])
        stack.push_back({child, f.world * to_mat4(child->mTransformation)});
  }
}

// Appends one instance of `mesh` transformed by `world`: triangles wound consistently
// under a mirroring transform, uvs with v = 0 at the top (assimp's is at the bottom).
void AssimpReader::add_instance(const aiMesh& mesh, const Mat4& world, Scene* scene) {
  const Mat4 nm = world.normal_matrix();
  const bool flip = det3(world) < 0;
  const bool uvs = mesh.mTextureCoords[0] != nullptr && mesh.mNumUVComponents[0] >= 2;
  const bool per_corner = any_normals_ && mesh.mNormals == nullptr;  // flat normals
  const uint32_t material = mesh.mMaterialIndex;
  auto push_vertex = [&](unsigned v, Vec3 flat_normal) {
    scene->positions.push_back(world.point(vec3(mesh.mVertices[v])));
    if (any_normals_)
      scene->normals.push_back(mesh.mNormals != nullptr
                                   ? detail::shading_normal(nm.vector(vec3(mesh.mNormals[v])))
                                   : flat_normal);
    if (any_uvs_) {
      const aiVector3D* uv = uvs ? &mesh.mTextureCoords[0][v] : nullptr;
      scene->uvs.push_back(uv ? Vec2{float(uv->x), 1.0f - float(uv->y)} : Vec2{});
    }
  };
  const uint32_t base = uint32_t(scene->positions.size());
  if (!per_corner)
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) push_vertex(v, Vec3(0, 0, 1));
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;
    const unsigned c[3] = {face.mIndices[0], face.mIndices[flip ? 2 : 1],
                           face.mIndices[flip ? 1 : 2]};
    if (per_corner) {  // three new vertices with the face normal
      const Vec3 n = detail::flat_normal(world.point(vec3(mesh.mVertices[c[0]])),
                                         world.point(vec3(mesh.mVertices[c[1]])),
                                         world.point(vec3(mesh.mVertices[c[2]])));
      for (int k = 0; k < 3; ++k) {
        scene->indices.push_back(uint32_t(scene->positions.size()));
        push_vertex(c[k], n);
      }
    } else {
      for (int k = 0; k < 3; ++k) scene->indices.push_back(base + c[k]);
    }
    scene->material_ids.push_back(material);
  }
}

// Cameras in file order, each at the world transform of the node with its name (the
// root's if no node has it). mHorizontalFOV is the full horizontal angle: so says
// assimp 5.2's camera.h, and so store its COLLADA and FBX importers (older headers said
// half; assimp issues #2256, #5691). Orthographic cameras are skipped; unusable ones
// (camera_problem) give one warning.
void AssimpReader::add_cameras(Scene* scene) {
  size_t dropped = 0;
  std::string first_problem;
  for (unsigned i = 0; i < ai_.mNumCameras; ++i) {
    const aiCamera* c = ai_.mCameras[i];
    if (c == nullptr || c->mOrthographicWidth > 0) continue;
    const Mat4 world = camera_world_[i].value_or(to_mat4(ai_.mRootNode->mTransformation));
    Camera cam;
    cam.eye = world.point(vec3(c->mPosition));
    const Vec3 dir = world.vector(vec3(c->mLookAt));
    // The target one unit ahead, or further where float cannot resolve that from the eye.
    const float reach = std::max(
        1.0f, 1e-3f * std::max({std::abs(cam.eye.x), std::abs(cam.eye.y), std::abs(cam.eye.z)}));
    cam.target = cam.eye + normalize(dir) * reach;
    cam.up = normalize(world.vector(vec3(c->mUp)));
    const double aspect = c->mAspect > 0 ? double(c->mAspect) : double(kAssumedAspect);
    cam.fov_y_deg = detail::to_float(
        2.0 * std::atan(std::tan(0.5 * double(c->mHorizontalFOV)) / aspect) * 180.0 / kPi);
    const std::string problem = camera_problem(cam);
    if (problem.empty())
      scene->cameras.push_back(cam);
    else if (dropped++ == 0)
      first_problem = problem;
  }
  if (dropped > 0)
    detail::warn(files_->options(), path_,
                 std::to_string(dropped) + " camera(s) not used: " + first_problem);
}

Scene AssimpReader::read() {
  if (ai_.mRootNode == nullptr) fail("the file has no node hierarchy");
  if (ai_.mNumMaterials > 0 && ai_.mMaterials == nullptr) fail("material list missing");
  if (ai_.mNumCameras > 0 && ai_.mCameras == nullptr) fail("camera list missing");
  check_meshes();
  count_instances();
  Scene scene;
  scene.name = detail::file_name(path_);
  scene.positions.reserve(size_t(vertices_));
  if (any_normals_) scene.normals.reserve(size_t(vertices_));
  if (any_uvs_) scene.uvs.reserve(size_t(vertices_));
  scene.indices.reserve(size_t(3 * triangles_));
  scene.material_ids.reserve(size_t(triangles_));
  detail::AssimpMaterials materials(ai_, files_, &scene);
  for (unsigned i = 0; i < ai_.mNumMaterials; ++i) {
    if (ai_.mMaterials[i] == nullptr) fail("material " + std::to_string(i) + " missing");
    scene.materials.push_back(materials.convert(*ai_.mMaterials[i]));
  }
  camera_world_.assign(ai_.mNumCameras, std::nullopt);
  for (unsigned i = 0; i < ai_.mNumCameras; ++i)
    if (ai_.mCameras[i] != nullptr) camera_of_node_.emplace(ai_.mCameras[i]->mName.C_Str(), i);
  walk(&scene);
  add_cameras(&scene);
  detail::validate_loaded(&scene, path_, files_->options());
  return scene;
}

}  // namespace

namespace {
// One assimp read of the scene file `text` (its named files through `files`). The importer
// owns the scene it returns (nullptr: assimp refused the file, GetErrorString() says why).
const aiScene* read_with_assimp(Assimp::Importer& importer, const std::string& path,
                                const std::string& text, SceneFiles& files,
                                detail::SceneFileSystem** io_out) {
  auto* io =
      new detail::SceneFileSystem(&files, std::vector<unsigned char>(text.begin(), text.end()));
  importer.SetIOHandler(io);  // the importer owns and deletes it
  if (io_out) *io_out = io;
  // Drop point and line primitives (not surfaces), and do not invent bone meshes for
  // files that hold only a skeleton.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
  return importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType);
}

// The read in a child process limited to options.parser_memory_limit (scene/assimp_trial.h);
// throws InputError when it did not fit or crashed.
void trial_read_with_assimp(const std::string& path, const std::string& text, SceneFiles& files,
                            const LoadOptions& options) {
  int signal = 0;
  const detail::TrialResult r = detail::trial_read(
      options.parser_memory_limit,
      [&] {
        Assimp::Importer importer;
        // assimp turns exceptions (bad_alloc too) into a null scene and an error string.
        if (!read_with_assimp(importer, path, text, files, nullptr) &&
            std::string(importer.GetErrorString()).find("bad_alloc") != std::string::npos)
          throw std::bad_alloc();
      },
      &signal);
  if (r == detail::TrialResult::too_large) {
    char gb[32];
    std::snprintf(gb, sizeof gb, "%.1f", double(options.parser_memory_limit) / 1e9);
    detail::fail(path, std::string("assimp needs more than the ") + gb +
                           " GB this run has left to read it (--max-memory); the file claims "
                           "more than it holds, or the limit is too low");
  }
  if (r == detail::TrialResult::crashed)
    detail::fail(path, "assimp crashed reading it (signal " + std::to_string(signal) +
                           ", in a trial read in a separate process)");
}
}  // namespace

namespace {
// The up axis FBX files declare (assimp passes GlobalSettings on as scene metadata and
// leaves the geometry as it is), into scene->file_up. COLLADA's <up_axis> needs nothing:
// assimp rotates the root node into Y-up itself.
void read_up_axis(const aiScene& ai, Scene* scene) {
  int32_t axis = 0, sign = 1;
  if (ai.mMetaData == nullptr || !ai.mMetaData->Get("UpAxis", axis)) return;
  ai.mMetaData->Get("UpAxisSign", sign);  // absent: +1
  if (fbx_up_axis(axis, sign, scene->file_up)) scene->file_up_from = "the file's UpAxis";
}
}  // namespace

Scene load_assimp(const std::string& path, const LoadOptions& options) {
  SceneFiles files(path, options);
  const std::string text = files.read_scene_file();
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".off") detail::check_off_counts(path, text);  // counts assimp would trust
  if (options.parser_memory_limit > 0) trial_read_with_assimp(path, text, files, options);
  Assimp::Importer importer;
  detail::SceneFileSystem* io = nullptr;
  const aiScene* ai = nullptr;
  try {
    ai = read_with_assimp(importer, path, text, files, &io);
  } catch (const std::exception& e) {  // assimp catches its own; this is for bad_alloc & co.
    detail::fail(path, std::string("assimp failed: ") + e.what());
  }
  if (ai == nullptr) {
    std::string why = importer.GetErrorString();
    if (!io->first_refusal().empty()) why += " (" + io->first_refusal() + ")";
    detail::fail(path, "assimp cannot read it: " + why);
  }
  Scene scene = AssimpReader(*ai, &files).read();
  read_up_axis(*ai, &scene);
  return scene;
}

}  // namespace multiray
