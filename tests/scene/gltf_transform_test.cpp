// glTF node transforms, instancing, attribute types and materials, on tiny files written
// by the test with the geometry embedded as a base64 data URI.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene/loaders.h"

namespace multiray {
namespace gltf_transform_test {

namespace fs = std::filesystem;

std::string base64(const std::vector<uint8_t>& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    const uint32_t n = uint32_t(in[i]) << 16 | (i + 1 < in.size() ? in[i + 1] << 8 : 0) |
                       (i + 2 < in.size() ? in[i + 2] : 0);
    out += k[n >> 18 & 63];
    out += k[n >> 12 & 63];
    out += i + 1 < in.size() ? k[n >> 6 & 63] : '=';
    out += i + 2 < in.size() ? k[n & 63] : '=';
  }
  return out;
}

template <typename T>
void append(std::vector<uint8_t>* buf, std::initializer_list<T> values) {
  for (T v : values) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    buf->insert(buf->end(), b, b + sizeof(T));
  }
}

class GltfTransform : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_gltf_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write_temp(const std::string& name, const std::string& text) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }
  fs::path dir_;
};

void expect_vec(Vec3 got, Vec3 want, const char* what) {
  EXPECT_NEAR(got.x, want.x, 1e-5f) << what;
  EXPECT_NEAR(got.y, want.y, 1e-5f) << what;
  EXPECT_NEAR(got.z, want.z, 1e-5f) << what;
}

// One triangle (0,0,0), (1,0,0), (0,1,0) without normals, used by four nodes:
//   node 0: translate (1,2,3) -> child node 1: scale 2      => (1,2,3) (3,2,3) (1,4,3)
//   node 2: matrix translating by (10,0,0)                  => (10,0,0) (11,0,0) (10,1,0)
//   node 3: rotate 90 degrees about +z                      => (0,0,0) (0,1,0) (-1,0,0)
//   node 4: mirror x (scale -1,1,1)                         => (0,0,0) (-1,0,0) (0,1,0)
TEST_F(GltfTransform, NodeTransformsAreBakedPerInstance) {
  std::vector<uint8_t> buf;
  append<float>(&buf, {0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::string gltf = R"({"asset": {"version": "2.0"},
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)" +
                           base64(buf) + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "scene": 0,
    "scenes": [{"nodes": [0, 2, 3, 4]}],
    "nodes": [
      {"translation": [1, 2, 3], "children": [1]},
      {"scale": [2, 2, 2], "mesh": 0},
      {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1], "mesh": 0},
      {"rotation": [0, 0, 0.70710678, 0.70710678], "mesh": 0},
      {"scale": [-1, 1, 1], "mesh": 0}]})";
  const Scene s = load_gltf(write_temp("transform.gltf", gltf));
  ASSERT_EQ(s.triangle_count(), 4u);
  ASSERT_EQ(s.normals.size(), s.positions.size());
  EXPECT_TRUE(s.uvs.empty());
  ASSERT_EQ(s.materials.size(), 1u);  // the default material
  auto corner = [&](size_t t, int k) { return s.positions[s.indices[3 * t + k]]; };
  expect_vec(corner(0, 0), Vec3(1, 2, 3), "scaled child");
  expect_vec(corner(0, 1), Vec3(3, 2, 3), "scaled child");
  expect_vec(corner(0, 2), Vec3(1, 4, 3), "scaled child");
  expect_vec(corner(1, 1), Vec3(11, 0, 0), "matrix node");
  expect_vec(corner(2, 1), Vec3(0, 1, 0), "rotated node");
  expect_vec(corner(2, 2), Vec3(-1, 0, 0), "rotated node");
  // Every triangle's winding agrees with its (flat) shading normal, mirrored one too.
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    const Vec3 g = cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0));
    const Vec3 n = s.normals[s.indices[3 * t]];
    EXPECT_NEAR(length(n), 1.0f, 1e-5f);
    EXPECT_GT(dot(g, n), 0.0f) << "triangle " << t;
  }
}

// Indexed triangle with u8 indices, float normals and normalized u16 uvs; a material
// with texture-less PBR values and the emissive-strength, transmission and IOR
// extensions, plus an unknown one; and a camera under a translated node.
TEST_F(GltfTransform, AttributeTypesMaterialsAndCamera) {
  std::vector<uint8_t> buf;
  append<float>(&buf, {0, 0, 0, 1, 0, 0, 0, 1, 0});    // 0: positions, 36 bytes
  append<float>(&buf, {0, 0, 2, 0, 0, 2, 0, 0, 2});    // 36: normals (unnormalized)
  append<uint16_t>(&buf, {0, 0, 65535, 0, 0, 65535});  // 72: uvs, 12 bytes
  append<uint8_t>(&buf, {2, 1, 0, 0});                 // 84: indices (+1 pad)
  const std::string gltf = R"({"asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_transmission",
                       "KHR_materials_ior", "EXT_made_up"],
    "buffers": [{"byteLength": 88, "uri": "data:application/octet-stream;base64,)" +
                           base64(buf) + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": 72},
                    {"buffer": 0, "byteOffset": 72, "byteLength": 12},
                    {"buffer": 0, "byteOffset": 84, "byteLength": 3}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
      {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC2"},
      {"bufferView": 2, "componentType": 5121, "count": 3, "type": "SCALAR"}],
    "materials": [{"name": "glass",
      "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1], "metallicFactor": 0.25,
                               "roughnessFactor": 0.125},
      "emissiveFactor": [1, 0.5, 0],
      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4},
                     "KHR_materials_transmission": {"transmissionFactor": 0.75},
                     "KHR_materials_ior": {"ior": 1.33},
                     "EXT_made_up": {"whatever": [1, 2]}}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                "indices": 3, "material": 0},
                               {"attributes": {"POSITION": 0}, "mode": 1}]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
    "nodes": [{"mesh": 0}, {"translation": [0, 0, 5], "camera": 0}]})";
  const Scene s = load_gltf(write_temp("types.gltf", gltf));  // no scenes: all roots
  ASSERT_EQ(s.triangle_count(), 1u);                          // the line primitive is skipped
  EXPECT_EQ(s.indices[0], 2u);
  EXPECT_EQ(s.indices[2], 0u);
  ASSERT_EQ(s.uvs.size(), 3u);
  EXPECT_NEAR(s.uvs[1].x, 1.0f, 1e-6f);
  EXPECT_NEAR(s.uvs[2].y, 1.0f, 1e-6f);
  expect_vec(s.normals[0], Vec3(0, 0, 1), "normalized normal");
  ASSERT_EQ(s.materials.size(), 1u);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.name, "glass");
  expect_vec(m.base_color, Vec3(0.5f, 0.25f, 1), "base colour");
  expect_vec(m.emission, Vec3(4, 2, 0), "emission x strength");
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.125f);
  EXPECT_FLOAT_EQ(m.transmission, 0.75f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_EQ(m.base_color_texture, -1);
  ASSERT_EQ(s.cameras.size(), 1u);
  expect_vec(s.cameras[0].eye, Vec3(0, 0, 5), "camera eye");
  expect_vec(s.cameras[0].target, Vec3(0, 0, 4), "camera target");
  EXPECT_NEAR(s.cameras[0].fov_y_deg, 0.5f * 180.0f / kPi, 1e-4f);
}

}  // namespace gltf_transform_test
}  // namespace multiray
