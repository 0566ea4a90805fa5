// OBJ specifics on small files written by the test: n-gon splitting, per-corner
// attributes, MTL values, and file names whose letter case differs from the disk.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene/loaders.h"

namespace multiray {
namespace obj_test {

namespace fs = std::filesystem;

class Obj : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_obj_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream((dir_ / name).string(), std::ios::binary) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

TEST_F(Obj, PolygonsAttributesAndMaterials) {
  // 2x1 binary PPM: one white and one mid-grey texel (sRGB 128 = 0.2158 linear).
  write("tex.ppm", std::string("P6\n2 1\n255\n") + "\xff\xff\xff\x80\x80\x80");
  write("mat.mtl",
        "newmtl lamp\nKd 0.1 0.2 0.3\nKe 17 12 4\n"
        "newmtl wood\nKd 0.5 0.5 0.5\nmap_Kd TEX.PPM\n"         // case differs from disk
        "newmtl ghost\nKd 0.9 0.9 0.9\nmap_Kd missing.png\n");  // no such file
  const std::string obj = write("poly.obj",
                                "mtllib MAT.MTL\n"  // case differs from disk
                                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\n"
                                "vt 0 0\nvt 1 0\nvt 1 1\n"
                                "vn 0 0 2\n"
                                "usemtl lamp\nf 1/1/1 2/2/1 3/3/1 4/1/1\n"  // quad: 2 triangles
                                "usemtl wood\nf 1 2 3 4 5\n"                // pentagon: 3
                                "usemtl ghost\nf 1 2 3\n"
                                "usemtl nosuch\nf 1 3 4\n");  // unknown: default material
  const Scene s = load_obj(obj);
  ASSERT_EQ(s.triangle_count(), 7u);
  ASSERT_EQ(s.positions.size(), 21u);  // de-indexed: three vertices per triangle
  ASSERT_EQ(s.normals.size(), 21u);
  ASSERT_EQ(s.uvs.size(), 21u);
  // Quad corner 0 is (0,0,0) with vt (0,0) -> v flipped to 1, and the given normal,
  // normalized.
  EXPECT_EQ(s.positions[0].x, 0.0f);
  EXPECT_FLOAT_EQ(s.uvs[0].y, 1.0f);
  EXPECT_FLOAT_EQ(s.normals[0].z, 1.0f);
  // Pentagon corners have no normal: they get the flat one, here +z as well.
  EXPECT_FLOAT_EQ(s.normals[6].z, 1.0f);

  ASSERT_EQ(s.materials.size(), 4u);  // lamp, wood, ghost, default
  EXPECT_EQ(s.materials[0].emission.x, 17.0f);
  EXPECT_EQ(s.materials[0].emission.z, 4.0f);
  EXPECT_FLOAT_EQ(s.materials[0].base_color.y, 0.2f);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.materials[1].base_color_texture, 0);
  EXPECT_EQ(s.materials[2].base_color_texture, -1);  // missing texture is ignored
  EXPECT_EQ(s.materials[3].name, "default");
  const Texture& t = s.textures[0];
  ASSERT_EQ(t.width, 2);
  EXPECT_FLOAT_EQ(t.texel(0, 0).x, 1.0f);
  EXPECT_NEAR(t.texel(1, 0).y, 0.2158f, 1e-4f);
  const uint32_t expected_ids[7] = {0, 0, 1, 1, 1, 2, 3};
  for (int i = 0; i < 7; ++i) EXPECT_EQ(s.material_ids[i], expected_ids[i]) << i;
}

TEST_F(Obj, MissingMtlFileMeansDefaultMaterial) {
  // Issue 31: the missing library was dropped without a word; now one warning per name.
  LoadOptions options;
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& line) { warnings.push_back(line); };
  const Scene s = load_obj(write("nomtl.obj",
                                 "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                 "usemtl red\nf 1 2 3\nmtllib gone.mtl\n"),
                           options);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_TRUE(s.normals.empty());
  EXPECT_TRUE(s.uvs.empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("nomtl.obj: material library 'gone.mtl' not found"),
            std::string::npos)
      << warnings[0];
}

TEST_F(Obj, LoadSceneDispatchIgnoresExtensionCase) {
  EXPECT_EQ(load_scene(write("upper.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).name,
            "upper.OBJ");
}

}  // namespace obj_test
}  // namespace multiray
