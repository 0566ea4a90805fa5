// Loaders against real files made by others. Triangle counts are the ones documented in
// ../shared/data/README.md (n-gons count as n-2 triangles; glTF instances once per use).
// Tests skip with a message when a file is absent so a fresh clone still passes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/loaders.h"

namespace multiray {
namespace real_models_test {

std::string assimp_model(const std::string& rel) {
  return std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/" + rel;
}
std::string shared_file(const std::string& rel) {
  return std::string(MULTIRAY_SHARED_DATA_DIR) + "/" + rel;
}

#define SKIP_IF_MISSING(path)                                                          \
  do {                                                                                 \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "test file missing: " << path; \
  } while (0)

size_t textured_materials(const Scene& s) {
  return size_t(std::count_if(s.materials.begin(), s.materials.end(),
                              [](const Material& m) { return m.base_color_texture >= 0; }));
}

TEST(RealModels, CylinderEngineGlbCountsEveryInstance) {
  const std::string p = assimp_model("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 121496u);  // 75,730 unique triangles
  EXPECT_EQ(s.normals.size(), s.positions.size());
}

// Loads `path`, collecting its warnings.
Scene load_warned(const std::string& path, std::vector<std::string>* warnings) {
  LoadOptions o;
  o.warn = [warnings](const std::string& line) { warnings->push_back(line); };
  return load_scene(path, o);
}

size_t count_containing(const std::vector<std::string>& lines, const std::string& word) {
  return size_t(std::count_if(lines.begin(), lines.end(), [&](const std::string& l) {
    return l.find(word) != std::string::npos;
  }));
}

TEST(RealModels, ClearCoatTestWarnsAboutItsExtension) {
  const std::string p = assimp_model("glTF2/ClearCoat-glTF/ClearCoatTest.gltf");
  SKIP_IF_MISSING(p);
  std::vector<std::string> warnings;
  const Scene s = load_warned(p, &warnings);
  EXPECT_EQ(s.triangle_count(), 37116u);
  EXPECT_EQ(count_containing(warnings, "extension KHR_materials_clearcoat"), 1u);
  // Its labels and base plates are textured: those textures are read per texel now.
  EXPECT_GE(textured_materials(s), 1u);
}

TEST(RealModels, WusonObjAndPlyAgree) {
  const std::string obj = assimp_model("OBJ/WusonOBJ.obj"), ply = assimp_model("PLY/Wuson.ply");
  SKIP_IF_MISSING(obj);
  SKIP_IF_MISSING(ply);
  const Scene a = load_scene(obj), b = load_scene(ply);
  EXPECT_EQ(a.triangle_count(), 3732u);
  EXPECT_EQ(b.triangle_count(), 3732u);
  ASSERT_EQ(a.materials.size(), 1u);  // no .mtl: one default material
  EXPECT_EQ(b.normals.size(), b.positions.size());
  EXPECT_EQ(b.uvs.size(), b.positions.size());
  const Bounds3 ba = a.bounds(), bb = b.bounds();
  const float tol = 1e-4f * max_component(ba.extent());
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(ba.lo[k], bb.lo[k], tol) << "axis " << k;
    EXPECT_NEAR(ba.hi[k], bb.hi[k], tol) << "axis " << k;
  }
}

TEST(RealModels, Regr01ObjManyGroupsAndMaterials) {
  const std::string p = assimp_model("OBJ/regr01.obj");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 2710u);
  EXPECT_GE(s.materials.size(), 11u);
}

TEST(RealModels, GltfPerspectiveCameraFromNode) {
  const std::string p = assimp_model("glTF2/cameras/Cameras.gltf");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  ASSERT_EQ(s.cameras.size(), 1u);  // the orthographic camera is skipped
  const Camera& c = s.cameras[0];
  EXPECT_NEAR(c.eye.x, 0.5f, 1e-6f);
  EXPECT_NEAR(c.eye.z, 3.0f, 1e-6f);
  EXPECT_NEAR(c.target.z, 2.0f, 1e-5f);  // looks down -z
  EXPECT_NEAR(c.up.y, 1.0f, 1e-6f);
  EXPECT_NEAR(c.fov_y_deg, 0.7f * 180.0f / kPi, 1e-3f);
}

TEST(RealModels, StanfordBunnyPly) {
  const std::string p = shared_file("meshes/stanford_bunny/bunny.ply");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 69451u);
  EXPECT_EQ(s.positions.size(), 35947u);
  EXPECT_TRUE(s.normals.empty());
}

TEST(RealModels, DamagedHelmetWithBaseColorTexture) {
  const std::string p = shared_file("meshes/damaged_helmet/DamagedHelmet.gltf");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 15452u);
  // Albedo, emissive, metallic-roughness and normal maps; the occlusion map is not read.
  ASSERT_EQ(s.textures.size(), 4u);
  EXPECT_EQ(s.textures[0].width, 2048);
  EXPECT_EQ(textured_materials(s), 1u);
  EXPECT_EQ(s.uvs.size(), s.positions.size());
  const Material& m = s.materials[0];
  auto coding = [&](int t) { return s.textures[size_t(t)].coding; };
  ASSERT_GE(m.emission_texture, 0);
  ASSERT_GE(m.metallic_roughness_texture, 0);
  ASSERT_GE(m.normal_texture, 0);
  EXPECT_EQ(coding(m.base_color_texture), TexelCoding::srgb);
  EXPECT_EQ(coding(m.emission_texture), TexelCoding::srgb);
  EXPECT_EQ(coding(m.metallic_roughness_texture), TexelCoding::linear);
  EXPECT_EQ(coding(m.normal_texture), TexelCoding::signed_unit);
  // The factor stays (1, 1, 1); the mostly-black map says where the helmet glows.
  EXPECT_EQ(m.emission.x, 1.0f);
}

// The data folder has the geometry but none of the 15 PNGs the original file names: one
// warning per missing image, none for the copy without texture references.
TEST(RealModels, FlightHelmetLoadsWithoutItsTexturesAndSaysSo) {
  for (const char* name : {"FlightHelmet.gltf", "FlightHelmet_notextures.gltf"}) {
    const std::string p = shared_file(std::string("meshes/flight_helmet/") + name);
    SKIP_IF_MISSING(p);
    std::vector<std::string> warnings;
    const Scene s = load_warned(p, &warnings);
    EXPECT_EQ(s.triangle_count(), 94722u) << name;
    EXPECT_TRUE(s.textures.empty()) << name;
    const bool original = std::string(name) == "FlightHelmet.gltf";
    EXPECT_EQ(count_containing(warnings, "was not found"), original ? 15u : 0u) << name;
  }
}

TEST(RealModels, DabrovicSponzaResolvesTextureNameCase) {
  const std::string p = shared_file("meshes/dabrovic_sponza/sponza.obj");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 66450u);
  EXPECT_GE(s.textures.size(), 10u);
  EXPECT_GE(textured_materials(s), 10u);
  EXPECT_EQ(s.uvs.size(), s.positions.size());
}

TEST(RealModels, CornellBoxHasItsAreaLight) {
  const std::string p = shared_file("cornell_box/mcguire/CornellBox-Original.obj");
  SKIP_IF_MISSING(p);
  const Scene s = load_scene(p);
  EXPECT_EQ(s.triangle_count(), 36u);
  const auto light = std::find_if(s.materials.begin(), s.materials.end(), [](const Material& m) {
    return m.emission.x == 17.0f && m.emission.y == 12.0f && m.emission.z == 4.0f;
  });
  ASSERT_NE(light, s.materials.end());
  const uint32_t id = uint32_t(light - s.materials.begin());
  EXPECT_EQ(std::count(s.material_ids.begin(), s.material_ids.end(), id), 2);  // one quad
}

}  // namespace real_models_test
}  // namespace multiray
