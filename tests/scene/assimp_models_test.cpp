// The assimp loader against Debian's assimp-testmodels (/usr/share/assimp/models). Every
// expected number was obtained without multiray, as each comment says: most from
// `assimp info FILE` of assimp-utils 5.2.5 (its "Faces" line, whose import triangulates
// too), the rest by counting in the file itself. Tests skip with a message when the
// models are not installed or the build has no assimp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include "scene/loaders.h"

namespace multiray {
namespace assimp_models_test {

std::string model(const std::string& rel) {
  return std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/" + rel;
}

// Skips the test unless assimp is built in and `path` exists.
#define SKIP_UNLESS_READABLE(path)                                                       \
  do {                                                                                   \
    if (!kHaveAssimp) GTEST_SKIP() << "built without assimp (MULTIRAY_WITH_ASSIMP)";     \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "test file missing: " << (path); \
  } while (0)

#ifdef MULTIRAY_HAS_ASSIMP
constexpr bool kHaveAssimp = true;
#else
constexpr bool kHaveAssimp = false;
#endif

// One sample file of every extension load_scene() sends to assimp, with its triangle
// count after instancing: the sum, over every "(mesh i)" in the node hierarchy `assimp
// info` prints, of mesh i's faces in its mesh table (all "triangle"). That is its
// "Faces" total wherever no mesh is used twice; the comments say where it differs.
const std::map<std::string, std::pair<std::string, size_t>> kSamples = {
    {".3ds", {"3DS/fels.3ds", 768}},
    {".3mf", {"3MF/box.3mf", 12}},
    {".ac", {"AC/SphereWithLight.ac", 17664}},
    {".ase", {"ASE/CameraRollAnim.ase", 12}},
    {".b3d", {"B3D/WusonBlitz.b3d", 3732}},
    {".blend", {"BLEND/4Cubes4Mats_248.blend", 48}},
    {".cob", {"COB/dwarf.cob", 1896}},
    {".dae", {"Collada/duck.dae", 4212}},
    // `assimp info -r`: 288 four-corner polygons. (Without -r it calls 48 of the 576
    // triangles lines: its FindDegenerates step; multiray keeps zero-area triangles.)
    {".dxf", {"DXF/PinkEggFromLW.dxf", 576}},
    {".fbx", {"FBX/box.fbx", 12}},
    {".ifc", {"IFC/AC14-FZK-Haus.ifc", 35906}},  // 66 meshes (31,235 faces) used 175 times
    {".lwo", {"LWO/LWO2/MappingModes/earth_cylindrical_x.lwo", 528}},
    {".lxo", {"LWO/LXOB_Modo/CrazyEngine.lxo", 2460}},
    {".md2", {"MD2/faerie.md2", 654}},
    {".ms3d", {"MS3D/Wuson.ms3d", 3732}},
    {".off", {"OFF/Wuson.off", 3732}},
    {".q3o", {"Q3D/E-AT-AT.q3o", 11156}},
    {".q3s", {"Q3D/WusonOrange.q3s", 3732}},
    {".smd", {"SMD/WusonSMD.smd", 3732}},
    {".stl", {"STL/sphereWithHole.stl", 285}},
    {".x", {"X/BCN_Epileptic.X", 5126}},
    {".x3d", {"X3D/ComputerKeyboard.x3d", 100}},  // 40 + 3 instances of a 20-face key
};

TEST(AssimpModels, EveryListedExtensionHasASampleThatLoads) {
  SKIP_UNLESS_READABLE(model(""));
  for (const char* ext : kAssimpExtensions) {
    const auto it = kSamples.find(ext);
    ASSERT_NE(it, kSamples.end()) << ext << " has no sample in this test";
    const std::string p = model(it->second.first);
    if (!std::filesystem::exists(p)) {
      ADD_FAILURE() << "sample missing: " << p;
      continue;
    }
    std::vector<std::string> warnings;
    LoadOptions o;
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    const Scene s = load_scene(p, o);
    EXPECT_EQ(s.triangle_count(), it->second.second) << p;
    EXPECT_EQ(s.material_ids.size(), s.triangle_count()) << p;
  }
  EXPECT_EQ(kSamples.size(), std::size(kAssimpExtensions));  // no untested extension
}

// Bounds as `assimp info` prints them ("Minimum point", "Maximum point"), for files with
// at most one transform level: deeper, it composes the transforms in the wrong order.
void expect_bounds(const Scene& s, Vec3 lo, Vec3 hi, float tol = 1e-4f) {
  const Bounds3 b = s.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.lo[k], lo[k], tol) << "axis " << k;
    EXPECT_NEAR(b.hi[k], hi[k], tol) << "axis " << k;
  }
}

TEST(AssimpModels, Fels3dsCountAndBounds) {
  const std::string p = model("3DS/fels.3ds");
  SKIP_UNLESS_READABLE(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 768u);  // assimp info: 1 mesh, 768 faces
  expect_bounds(s, Vec3(-2.221913f, -2.564741f, -0.121266f),
                Vec3(1.282885f, 2.116860f, 3.084285f));
}

TEST(AssimpModels, SphereWithHoleStl) {
  const std::string p = model("STL/sphereWithHole.stl");
  SKIP_UNLESS_READABLE(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 285u);  // ASCII STL: grep -c "facet normal" gives 285
  expect_bounds(s, Vec3(0.0f), Vec3(3.0f));
  EXPECT_EQ(s.normals.size(), s.positions.size());  // STL facet normals
}

// The same Wuson model as OFF, Milkshape and SMD agrees with the dedicated PLY reader.
TEST(AssimpModels, WusonAgreesWithThePlyReader) {
  const std::string ply = model("PLY/Wuson.ply");
  SKIP_UNLESS_READABLE(ply);
  const Scene ref = load_scene(ply);
  ASSERT_EQ(ref.triangle_count(), 3732u);
  // OFF header "3205 3732 0", and every face line starts with 3.
  const Scene off = load_scene(model("OFF/Wuson.off"));
  EXPECT_EQ(off.triangle_count(), 3732u);
  EXPECT_EQ(off.positions.size(), 3205u);  // shared vertices, no normals in the file
  const Bounds3 a = ref.bounds(), b = off.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.lo[k], b.lo[k], 1e-5f) << "axis " << k;
    EXPECT_NEAR(a.hi[k], b.hi[k], 1e-5f) << "axis " << k;
  }
}

TEST(AssimpModels, DuckDaeHasNormalsUvsTextureAndCamera) {
  const std::string p = model("Collada/duck.dae");
  SKIP_UNLESS_READABLE(p);
  const Scene s = load_scene(p);
  // <polylist count="2144"> with a <vcount> list whose sum of (n - 2) is 4212.
  EXPECT_EQ(s.triangle_count(), 4212u);
  EXPECT_EQ(s.normals.size(), s.positions.size());
  EXPECT_EQ(s.uvs.size(), s.positions.size());
  ASSERT_EQ(s.textures.size(), 1u);  // duckCM.tga
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].base_color_texture, 0);
  // <asset><unit meter="0.01"> scales the file's centimetres (assimp info bounds).
  expect_bounds(s, Vec3(-0.692985f, 0.099294f, -0.613282f), Vec3(0.961799f, 1.639700f, 0.539252f));
  // camera1: <translate>400.113 463.264 -431.078</translate> (x 0.01), yfov 37.8492.
  ASSERT_EQ(s.cameras.size(), 1u);
  const Camera& c = s.cameras[0];
  EXPECT_NEAR(c.eye.x, 4.00113f, 1e-4f);
  EXPECT_NEAR(c.eye.y, 4.63264f, 1e-4f);
  EXPECT_NEAR(c.eye.z, -4.31078f, 1e-4f);
  EXPECT_NEAR(c.fov_y_deg, 37.8492f, 1e-2f);
  // Rotated -223.2 degrees about y and -38.4 about x: it looks at the duck (the origin).
  const Vec3 view = normalize(c.target - c.eye), to_duck = normalize(Vec3(0.0f) - c.eye);
  EXPECT_GT(dot(view, to_duck), 0.95f);
}

TEST(AssimpModels, BoxFbx) {
  const std::string p = model("FBX/box.fbx");
  SKIP_UNLESS_READABLE(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 12u);  // assimp info: 12 faces, 1 mesh, 5 nodes deep
  // The mesh sits under translation, rotation and scaling nodes (FBX geometric
  // transforms). Bounds of `assimp export box.fbx box.obj -ptv` (assimp's own
  // PreTransformVertices step), measured over its `v` lines.
  expect_bounds(s, Vec3(-0.2260957f, -0.1618642f, -0.0646463f),
                Vec3(0.2844616f, 0.2443484f, 0.4646601f));
}

// FBX says its up axis (GlobalSettings UpAxis/UpAxisSign, which assimp passes on as
// scene metadata): the samples are all Y-up; the same ASCII file with UpAxis 2 is Z-up.
// (No Z-up FBX ships with assimp-testmodels; COLLADA's Z_UP files arrive turned Y-up.)
TEST(AssimpModels, FbxUpAxisComesFromTheFile) {
  const std::string p = model("FBX/cubes_nonames.fbx");
  SKIP_UNLESS_READABLE(p);
  const Scene y_up = load_scene(p);
  EXPECT_EQ(y_up.file_up.y, 1.0f);
  EXPECT_FALSE(y_up.file_up_from.empty());
  std::ifstream in(p, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string field = "\"UpAxis\", \"int\", \"Integer\", \"\",";
  const size_t at = text.find(field + "1");
  ASSERT_NE(at, std::string::npos) << "an ASCII FBX with UpAxis 1";
  text[at + field.size()] = '2';
  const std::string z_path = ::testing::TempDir() + "/cubes_z_up.fbx";
  std::ofstream(z_path, std::ios::binary) << text;
  const Scene z_up = load_scene(z_path);
  EXPECT_EQ(z_up.file_up.z, 1.0f);
  EXPECT_EQ(z_up.file_up.x + z_up.file_up.y, 0.0f);
  // COLLADA: assimp applies <up_axis>Z_UP</up_axis> itself; nothing is declared to us.
  const std::string dae = model("Collada/cube_tristrips.dae");
  if (std::filesystem::exists(dae)) {
    EXPECT_EQ(dot(load_scene(dae).file_up, Vec3(1, 1, 1)), 0.0f);
  }
}

// TEST.PNG is named in upper case in the file; the folder has test.png.
TEST(AssimpModels, TextureNameCaseIsResolved) {
  const std::string p = model("3DS/cube_with_diffuse_texture.3DS");
  SKIP_UNLESS_READABLE(p);
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warn = [&](const std::string& w) { warnings.push_back(w); };
  const Scene s = load_scene(p, o);
  EXPECT_EQ(s.triangle_count(), 12u);  // assimp info: 12 faces
  EXPECT_EQ(s.textures.size(), 1u);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
}

// Materials without PBR keys: roughness from the Phong exponent, (2 / (n + 2))^(1/4), and
// opacity below 1 as alpha blending. `assimp export FILE out.obj` writes the exponent and
// the opacity into out.mtl as Ns and d: fels.3ds "Ns 40", "d 1"; phong_cube.fbx "Ns 10",
// "d 0.5" (its roughness is not checked: assimp's FBX reader also gives it a roughness
// factor, which takes precedence).
TEST(AssimpModels, PhongMaterials) {
  const std::string fels = model("3DS/fels.3ds"), cube = model("FBX/phong_cube.fbx");
  SKIP_UNLESS_READABLE(fels);
  SKIP_UNLESS_READABLE(cube);
  const Scene a = load_scene(fels);
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_NEAR(a.materials[0].roughness, std::pow(2.0f / 42.0f, 0.25f), 1e-5f);
  EXPECT_EQ(a.materials[0].metallic, 0.0f);
  EXPECT_EQ(a.materials[0].alpha_mode, AlphaMode::opaque);
  const Scene b = load_scene(cube);
  ASSERT_EQ(b.materials.size(), 1u);
  EXPECT_EQ(b.materials[0].name, "phong1");
  EXPECT_EQ(b.materials[0].alpha_mode, AlphaMode::blend);
  EXPECT_NEAR(b.materials[0].opacity, 0.5f, 1e-6f);
}

}  // namespace assimp_models_test
}  // namespace multiray
