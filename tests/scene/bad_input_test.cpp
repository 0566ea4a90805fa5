// Bad scene files must raise InputError with one line naming the file and the problem:
// never a crash, hang, abort or a different exception type.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "scene/loaders.h"

namespace multiray {
namespace bad_input_test {

namespace fs = std::filesystem;

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_bad_input_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& contents) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << contents;
    return p;
  }

  // Loads `path` and checks the error: InputError, one line, naming the file and
  // containing `word`.
  static void expect_error(const std::string& path, const std::string& word) {
    try {
      load_scene(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(fs::path(path).filename().string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(word), std::string::npos) << "expected '" << word << "' in: " << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "wrong exception type for " << path << ": " << e.what();
    }
  }

  fs::path dir_;
};

const char* kPlyHeader3 =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

// Binary little-endian PLY of one triangle; cut it to `keep` bytes of body.
std::string binary_triangle(size_t keep) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string body(reinterpret_cast<const char*>(v), sizeof v);
  body += char(3);
  const int32_t idx[3] = {0, 1, 2};
  body.append(reinterpret_cast<const char*>(idx), sizeof idx);
  return s + body.substr(0, keep);
}

TEST_F(BadInput, MissingFile) { expect_error((dir_ / "nothere.obj").string(), "not found"); }

TEST_F(BadInput, EmptyFiles) {
  for (const char* name : {"empty.obj", "empty.ply", "empty.gltf", "empty.glb"})
    expect_error(write(name, ""), "empty");
}

TEST_F(BadInput, UnknownExtension) { expect_error(write("model.xyz", "v 0 0 0\n"), "extension"); }

TEST_F(BadInput, DirectoryInsteadOfFile) {
  fs::create_directories(dir_ / "folder.obj");
  expect_error((dir_ / "folder.obj").string(), "regular file");
}

TEST_F(BadInput, PlyBinaryCutShort) {
  // The intact file loads; every shorter body is reported as truncated.
  EXPECT_EQ(load_scene(write("ok.ply", binary_triangle(49))).triangle_count(), 1u);
  for (size_t keep : {0, 10, 36, 37, 45, 48})
    expect_error(write("cut" + std::to_string(keep) + ".ply", binary_triangle(keep)), "truncated");
}

TEST_F(BadInput, PlyHeaderLiesAboutCounts) {
  std::string ply = kPlyHeader3;
  ply.replace(ply.find("vertex 3"), 8, "vertex 1000000");
  expect_error(write("liar.ply", ply + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "promises");
  // An absurd count is refused from the file size, before anything is allocated.
  ply.replace(ply.find("vertex 1000000"), 14, "vertex 1000000000000");
  expect_error(write("absurd.ply", ply + "0 0 0\n"), "promises");
  expect_error(write("nofaces.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n0 1 0\n"),
               "truncated");
}

TEST_F(BadInput, PlyNonNumericToken) {
  expect_error(write("abc.ply", std::string(kPlyHeader3) + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n"),
               "'abc' is not a number");
}

TEST_F(BadInput, PlyMalformedHeader) {
  expect_error(write("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"), "end_header");
  expect_error(write("notply.ply", "solid cube\n"), "not a PLY");
  expect_error(write("badtype.ply",
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n"
                     "end_header\n0\n"),
               "property");
}

TEST_F(BadInput, FaceIndexOutOfRange) {
  expect_error(write("range.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
               "out of range");
  expect_error(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "out of range");
  expect_error(write("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9\n"), "out of range");
  expect_error(write("normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//4\n"),
               "out of range");
}

TEST_F(BadInput, NanVertex) {
  expect_error(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "line 2");
  expect_error(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "finite");
  expect_error(write("abc.obj", "v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n"), "'abc'");
  expect_error(write("short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"), "too few");
  expect_error(write("nan.ply", std::string(kPlyHeader3) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"),
               "NaN");
}

TEST_F(BadInput, AllTrianglesDegenerate) {
  expect_error(write("flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\nf 1 1 2\n"), "zero area");
  expect_error(write("flat.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n"),
               "zero area");
}

TEST_F(BadInput, NoTriangles) {
  expect_error(write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no triangles");
  expect_error(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "malformed");
}

TEST_F(BadInput, GltfBrokenJson) {
  expect_error(write("broken.gltf", R"({"asset": {"version": "2.0"}, "meshes": [ {)"),
               "malformed glTF");
  expect_error(write("notgltf.gltf", "hello"), "malformed glTF");
  expect_error(write("noversion.gltf", R"({"meshes": []})"), "malformed glTF");
}

// One triangle in a data URI; `count` elements of POSITION are claimed.
std::string gltf_triangle(int count, const std::string& extra_node = "") {
  return R"({"asset": {"version": "2.0"},
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)"
         R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
         std::to_string(count) + R"(, "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0)" +
         extra_node + R"(}]})";
}

TEST_F(BadInput, GltfAccessorPastBufferEnd) {
  EXPECT_EQ(load_scene(write("ok.gltf", gltf_triangle(3))).triangle_count(), 1u);
  expect_error(write("past.gltf", gltf_triangle(12)), "past the end");
}

TEST_F(BadInput, GltfNodeCycle) {
  expect_error(write("cycle.gltf", gltf_triangle(3, R"(, "children": [0])")), "cycle");
}

TEST_F(BadInput, GlbCutShort) {
  const std::string glb = std::string("glTF") + std::string("\x02\0\0\0\x40\0\0\0", 8) + "{";
  expect_error(write("cut.glb", glb), "malformed glTF");
}

}  // namespace bad_input_test
}  // namespace multiray
