// What every loader refuses or repairs after reading: coordinates beyond 1e18 (refused),
// unusable shading normals (replaced by face normals, with a warning), non-finite uvs
// (refused), glTF node graphs that would instance too much (refused before any
// instance is built), and images charged against the run's memory before they are
// decoded.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "scene/load_guard.h"
#include "scene/loaders.h"
#include "support/png_bytes.h"

namespace multiray {
namespace scene_limits_test {

namespace fs = std::filesystem;
using test::expect_input_error;
using test::Outcome;
using test::within_10s;

const char* kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\n";
const char* kPlyFaces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    const auto byte = [&](size_t j) { return j < in.size() ? uint32_t(uint8_t(in[j])) : 0u; };
    const uint32_t n = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
    out += k[n >> 18 & 63];
    out += k[n >> 12 & 63];
    out += i + 1 < in.size() ? k[n >> 6 & 63] : '=';
    out += i + 2 < in.size() ? k[n & 63] : '=';
  }
  return out;
}

std::string floats(std::initializer_list<float> v) {
  std::string s(v.size() * 4, '\0');
  std::memcpy(s.data(), std::data(v), s.size());
  return s;
}

// glTF with one triangle (positions, optional normals or uvs in the same embedded
// buffer), meshes on nodes `nodes_json` and scene roots `roots`.
std::string gltf(const std::string& nodes_json, const std::string& roots = "[0]",
                 const std::string& normals = "", const std::string& uvs = "") {
  const std::string positions = floats({0, 0, 0, 0, 0, 1, 1, 0, 0});
  const std::string data = positions + normals + uvs;
  std::string attrs = R"("POSITION": 0)";
  std::string accessors =
      R"({"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"})";
  if (!normals.empty()) {
    attrs += R"(, "NORMAL": 1)";
    accessors +=
        R"(, {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"})";
  }
  if (!uvs.empty()) {
    attrs += R"(, "TEXCOORD_0": 1)";
    accessors +=
        R"(, {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC2"})";
  }
  return R"({"asset": {"version": "2.0"},
    "buffers": [{"byteLength": )" +
         std::to_string(data.size()) + R"(, "uri": "data:application/octet-stream;base64,)" +
         base64(data) + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": )" +
         std::to_string(data.size()) + R"(}],
    "accessors": [)" +
         accessors + R"(],
    "meshes": [{"primitives": [{"attributes": {)" +
         attrs + R"(}}]}],
    "scenes": [{"nodes": )" +
         roots + R"(}],
    "nodes": )" +
         nodes_json + "}";
}

// `levels` levels of nodes, each instancing the node below `fanout` times; the bottom
// node has mesh 0 if `with_mesh`. Node 0 is the root.
std::string nested_nodes(int levels, int fanout, bool with_mesh) {
  std::string nodes = "[";
  for (int l = 0; l < levels; ++l) {
    std::string children;
    for (int c = 0; c < fanout; ++c) {
      if (c > 0) children += ',';
      children += std::to_string(l + 1);
    }
    nodes += R"({"children": [)" + children + "]},";
  }
  return nodes + (with_mesh ? R"({"mesh": 0}])" : "{}]");
}

void expect_vec(Vec3 got, Vec3 want) {
  EXPECT_FLOAT_EQ(got.x, want.x);
  EXPECT_FLOAT_EQ(got.y, want.y);
  EXPECT_FLOAT_EQ(got.z, want.z);
}

class SceneLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_limits_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    options_.warn = [this](const std::string& line) { warnings_.push_back(line); };
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& contents) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << contents;
    return p;
  }
  Outcome load(const std::string& path) {
    return within_10s([&] { scene_ = load_scene(path, options_); });
  }

  fs::path dir_;
  LoadOptions options_;
  std::vector<std::string> warnings_;
  Scene scene_;
};

TEST_F(SceneLimits, CoordinatesBeyond1e18AreRefusedByEveryLoader) {
  expect_input_error(load(write("big.obj", "v 0 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n")),
                     {"big.obj", "vertex", "beyond 1e18"});
  expect_input_error(load(write("big.ply", std::string(kPlyHeader) + kPlyFaces +
                                               "0 0 0\n1 0 0\n0 -2e18 0\n3 0 1 2\n")),
                     {"big.ply", "vertex 2", "beyond 1e18"});
  // A glTF node scale pushes a unit triangle out to 1e30.
  expect_input_error(load(write("big.gltf", gltf(R"([{"mesh": 0, "scale": [1e30, 1, 1]}])"))),
                     {"big.gltf", "beyond 1e18"});
  // 1e18 itself is fine.
  ASSERT_TRUE(load(write("edge.obj", "v 0 0 0\nv 1e18 0 0\nv 0 1 0\nf 1 2 3\n")).returned);
}

TEST_F(SceneLimits, UnusableNormalsAreReplacedByFaceNormals) {
  // The triangle (0,0,0) (0,0,1) (1,0,0) faces +y. Normals: NaN, zero, and a huge one
  // whose direction is fine (its float length overflows).
  const std::string ply = std::string(kPlyHeader) +
                          "property float nx\nproperty float ny\nproperty float nz\n" + kPlyFaces +
                          "0 0 0 nan nan nan\n0 0 1 0 0 0\n1 0 0 3e38 0 0\n3 0 1 2\n";
  ASSERT_TRUE(load(write("n.ply", ply)).returned);
  ASSERT_EQ(scene_.normals.size(), 3u);
  expect_vec(scene_.normals[0], Vec3(0, 1, 0));
  expect_vec(scene_.normals[1], Vec3(0, 1, 0));
  expect_vec(scene_.normals[2], Vec3(1, 0, 0));
  ASSERT_EQ(warnings_.size(), 1u);
  EXPECT_NE(warnings_[0].find("n.ply: 2 shading normal(s)"), std::string::npos) << warnings_[0];

  warnings_.clear();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::string gl = gltf(R"([{"mesh": 0}])", "[0]", floats({nan, 0, 0, 0, 0, 0, 0, 0, 5}));
  ASSERT_TRUE(load(write("n.gltf", gl)).returned);
  expect_vec(scene_.normals[0], Vec3(0, 1, 0));
  expect_vec(scene_.normals[1], Vec3(0, 1, 0));
  expect_vec(scene_.normals[2], Vec3(0, 0, 1));
  ASSERT_EQ(warnings_.size(), 1u);

  warnings_.clear();
  ASSERT_TRUE(load(write("n.obj",
                         "v 0 0 0\nv 0 0 1\nv 1 0 0\nvn 3e38 3e38 0\nvn 0 0 0\n"
                         "f 1//1 2//2 3//2\n"))
                  .returned);
  EXPECT_NEAR(scene_.normals[0].x, 0.70710678f, 1e-6f);
  expect_vec(scene_.normals[1], Vec3(0, 1, 0));
  EXPECT_TRUE(warnings_.empty());  // OBJ corners without a normal get the flat one anyway
}

TEST_F(SceneLimits, NonFiniteUvsAreRefused) {
  const float inf = std::numeric_limits<float>::infinity();
  expect_input_error(
      load(write("uv.gltf", gltf(R"([{"mesh": 0}])", "[0]", "", floats({0, 0, inf, 0, 0, 1})))),
      {"uv.gltf", "uv 1", "NaN or infinite"});
}

TEST_F(SceneLimits, NestedInstancesAreRefusedBeforeBuilding) {
  // 10 levels of 10 instances each: 10^10 triangles from a file of about 1 KB.
  const std::string file = write("nested.gltf", gltf(nested_nodes(10, 10, true)));
  EXPECT_LT(fs::file_size(file), 2000u);
  expect_input_error(load(file), {"nested.gltf", "instances 10000000000 triangles",
                                  "limit of 268435456", "before building"});
  // 64 levels of 2: the count saturates instead of wrapping to 0.
  expect_input_error(load(write("deep.gltf", gltf(nested_nodes(64, 2, true)))),
                     {"instances over 1.8e19 triangles"});
  // Without any mesh the walk alone would take 10^10 steps.
  expect_input_error(load(write("empty.gltf", gltf(nested_nodes(10, 10, false)))),
                     {"empty.gltf", "instances 11111111111 nodes, more than the limit"});
}

TEST_F(SceneLimits, SharedSubtreesWithinTheLimitsLoad) {
  // 3 levels of 2 instances: 8 copies of the triangle, and a cycle is still an error.
  ASSERT_TRUE(load(write("dag.gltf", gltf(nested_nodes(3, 2, true)))).returned);
  EXPECT_EQ(scene_.triangle_count(), 8u);
  expect_input_error(
      load(write("cycle.gltf", gltf(R"([{"children": [1]}, {"mesh": 0, "children": [0]}])"))),
      {"cycle"});
}

TEST_F(SceneLimits, ImagesAreChargedFromTheirHeadersBeforeDecoding) {
  // Issue 31: a 16 KB PNG of 16000 x 16000 pixels decoded to 2 GB under --max-memory 1G.
  write("big.png", test::png_claiming(16000, 16000));
  write("small.png", test::png_bytes(4, 3));
  write("m.mtl",
        "newmtl a\nmap_Kd small.png\nnewmtl b\nmap_Kd small2.png\n"
        "newmtl c\nmap_Kd big.png\n");
  write("small2.png", test::png_bytes(2, 2));
  const std::string obj = write("t.obj",
                                "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\nusemtl c\nf 1 2 3\n");
  std::vector<std::string> charged;
  uint64_t kept = 0;
  options_.reserve_image = [&](const std::string& what, uint64_t keep, uint64_t transient) {
    charged.push_back(what);
    EXPECT_GE(transient, keep);  // stb's copy at least, while decoding
    if (kept + keep + transient > (uint64_t(1) << 30))
      throw InputError(what + ": over the test's 1 GiB");
    kept += keep;
  };
  expect_input_error(load(obj), {"t.obj: texture 'big.png' (16000 x 16000 pixels)", "1 GiB"});
  ASSERT_EQ(charged.size(), 3u);
  EXPECT_NE(charged[0].find("t.obj: texture 'small.png' (4 x 3 pixels)"), std::string::npos)
      << charged[0];
  EXPECT_EQ(kept, 4u * (12 + 4));  // the two small textures, 4 bytes a texel
  // Without the big texture, the same accounting lets the scene load.
  write("m.mtl", "newmtl a\nmap_Kd small.png\nnewmtl b\nmap_Kd small2.png\n");
  kept = 0;
  EXPECT_TRUE(load(obj).returned);
  EXPECT_EQ(scene_.textures.size(), 2u);
}

TEST_F(SceneLimits, EnvironmentMapsAreChargedFromTheirHeaders) {
  // A Radiance header claiming 16000 x 16000 (3 GB of float pixels to stb_image).
  const std::string hdr =
      write("sky.hdr",
            "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16000 +X 16000\n" + std::string(64, '\x01'));
  std::string what;
  uint64_t keep = 0;
  options_.reserve_image = [&](const std::string& w, uint64_t k, uint64_t) {
    what = w, keep = k;
    throw InputError(w + ": too big for the test");
  };
  expect_input_error(within_10s([&] { load_environment_map(hdr, options_); }),
                     {"sky.hdr: environment map (16000 x 16000 pixels)"});
  EXPECT_EQ(keep, uint64_t(16000) * 16000 * 12);
}

}  // namespace scene_limits_test
}  // namespace multiray
