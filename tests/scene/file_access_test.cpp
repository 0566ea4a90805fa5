// Files a scene names are read only if they are regular files inside the model's folder
// and within the byte limit (LoadOptions); everything else is refused before it is
// opened: a refused buffer or scene file is an InputError, a refused image, texture or
// material library a warning. FIFOs would block an open() forever, so every load here
// runs under a 10 s guard.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene/load_guard.h"
#include "scene/loaders.h"

namespace multiray {
namespace file_access_test {

namespace fs = std::filesystem;
using test::expect_input_error;
using test::Outcome;
using test::within_10s;

// One triangle (0,0,0) (1,0,0) (0,1,0) as 36 bytes of little-endian floats.
std::string triangle_bytes() {
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return std::string(reinterpret_cast<const char*>(v), sizeof v);
}

// A glTF whose one triangle is in buffer `buffer_uri` and whose material uses the image
// at `image_uri` (no image if empty).
std::string gltf(const std::string& buffer_uri, const std::string& image_uri = "") {
  std::string s = R"({"asset": {"version": "2.0"},
    "buffers": [{"byteLength": 36, "uri": ")" +
                  buffer_uri + R"("}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
    "nodes": [{"mesh": 0}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1])";
  if (!image_uri.empty())
    s += R"(, "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}],
    "images": [{"uri": ")" +
         image_uri + R"("}]})";
  else
    s += "}}]}";
  return s;
}

// A 1x1 binary PPM (stb_image decodes it).
const char* kPpm = "P6\n1 1\n255\n\x10\x20\x30";

class FileAccess : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_files_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_ / "model");
    fs::create_directories(dir_ / "outside");
    options_.warn = [this](const std::string& line) { warnings_.push_back(line); };
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `contents` to `name` under the test folder and returns its path.
  std::string write(const std::string& name, const std::string& contents) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << contents;
    return p;
  }
  std::string fifo(const std::string& name) {
    const std::string p = (dir_ / name).string();
    EXPECT_EQ(mkfifo(p.c_str(), 0600), 0) << std::strerror(errno);
    return p;
  }
  Outcome load(const std::string& path) {
    return within_10s([&] { scene_ = load_scene(path, options_); });
  }
  // The one warning there must be, checked for `words`.
  void expect_warning(std::initializer_list<std::string> words) {
    ASSERT_EQ(warnings_.size(), 1u);
    EXPECT_EQ(warnings_[0].find('\n'), std::string::npos);
    for (const std::string& w : words)
      EXPECT_NE(warnings_[0].find(w), std::string::npos)
          << "'" << w << "' not in " << warnings_[0];
  }

  fs::path dir_;
  LoadOptions options_;
  std::vector<std::string> warnings_;
  Scene scene_;
};

TEST_F(FileAccess, SceneFileThatIsAFifoIsRefused) {
  for (const char* name : {"model/a.gltf", "model/a.glb", "model/a.obj", "model/a.ply"})
    expect_input_error(load(fifo(name)), {"a.", "not a regular file"});
}

TEST_F(FileAccess, GltfBufferFifoIsAnError) {
  fifo("model/geo.bin");
  expect_input_error(load(write("model/a.gltf", gltf("geo.bin"))),
                     {"a.gltf: buffer refused", "geo.bin", "not a regular file"});
}

TEST_F(FileAccess, GltfImageFifoIsAWarningAndTheFactorStays) {
  write("model/geo.bin", triangle_bytes());
  fifo("model/tex.ppm");
  const Outcome o = load(write("model/a.gltf", gltf("geo.bin", "tex.ppm")));
  ASSERT_TRUE(o.returned) << o.message;
  expect_warning({"a.gltf: image 'tex.ppm' was refused", "not a regular file", "its factor"});
  ASSERT_EQ(scene_.materials.size(), 1u);
  EXPECT_EQ(scene_.materials[0].base_color_texture, -1);
  EXPECT_FLOAT_EQ(scene_.materials[0].base_color.y, 0.25f);
}

TEST_F(FileAccess, GltfFilesOutsideTheFolderNeedAllowOutside) {
  write("outside/geo.bin", triangle_bytes());
  write("outside/tex.ppm", kPpm);
  const std::string file = write("model/a.gltf", gltf("../outside/geo.bin"));
  expect_input_error(load(file),
                     {"buffer refused", "outside/geo.bin", "outside the scene's folder"});
  // Through a symlink inside the folder: the same, since symlinks are resolved.
  fs::create_symlink(dir_ / "outside/geo.bin", dir_ / "model/link.bin");
  expect_input_error(load(write("model/b.gltf", gltf("link.bin"))),
                     {"link.bin", "outside the scene's folder"});
  // Deep '..' chains to system files: refused, the scene loads with the factor.
  write("model/geo.bin", triangle_bytes());
  ASSERT_TRUE(
      load(write("model/c.gltf", gltf("geo.bin", "../../../../../../../../etc/passwd"))).returned);
  expect_warning({"was refused", "etc/passwd", "outside the scene's folder"});

  warnings_.clear();
  options_.allow_outside = true;
  ASSERT_TRUE(load(file).returned);
  EXPECT_EQ(scene_.triangle_count(), 1u);
  ASSERT_TRUE(load(write("model/d.gltf", gltf("geo.bin", "../outside/tex.ppm"))).returned);
  EXPECT_TRUE(warnings_.empty());
  EXPECT_EQ(scene_.materials[0].base_color_texture, 0);
  // Never a FIFO, allowed outside or not.
  fifo("outside/geo2.bin");
  expect_input_error(load(write("model/e.gltf", gltf("../outside/geo2.bin"))),
                     {"not a regular file"});
}

TEST_F(FileAccess, ByteLimitCountsTheSceneFileAndWhatItNames) {
  write("model/geo.bin", triangle_bytes());
  const std::string file = write("model/a.gltf", gltf("geo.bin"));
  const uint64_t scene_bytes = fs::file_size(file);
  options_.max_total_bytes = scene_bytes + 36;
  ASSERT_TRUE(load(file).returned);
  options_.max_total_bytes = scene_bytes + 35;
  expect_input_error(load(file), {"buffer refused", "geo.bin", "is 36 bytes", "limit"});
  options_.max_total_bytes = scene_bytes - 1;
  expect_input_error(load(file), {"a.gltf: file is", "limit"});
}

TEST_F(FileAccess, ObjMaterialLibraryAndTextureRefusalsAreWarnings) {
  const std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
  fifo("model/m.mtl");
  ASSERT_TRUE(load(write("model/a.obj", obj)).returned);
  expect_warning({"a.obj: material library refused", "m.mtl", "not a regular file"});
  EXPECT_EQ(scene_.materials.back().name, "default");

  warnings_.clear();
  fs::remove(dir_ / "model/m.mtl");
  write("model/m.mtl", "newmtl red\nKd 1 0 0\nmap_Kd t.ppm\n");
  fifo("model/t.ppm");
  ASSERT_TRUE(load(write("model/b.obj", obj)).returned);
  expect_warning({"b.obj: texture refused", "t.ppm", "not a regular file"});
  ASSERT_EQ(scene_.materials[0].name, "red");
  EXPECT_EQ(scene_.materials[0].base_color_texture, -1);
  EXPECT_FLOAT_EQ(scene_.materials[0].base_color.x, 1.0f);

  warnings_.clear();
  write("outside/o.mtl", "newmtl red\nKd 0 1 0\n");
  const std::string outside =
      write("model/c.obj", "mtllib ../outside/o.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ASSERT_TRUE(load(outside).returned);
  expect_warning({"material library refused", "o.mtl", "outside the scene's folder"});
  options_.allow_outside = true;
  ASSERT_TRUE(load(outside).returned);
  ASSERT_EQ(scene_.materials[0].name, "red");
  EXPECT_FLOAT_EQ(scene_.materials[0].base_color.y, 1.0f);
}

}  // namespace file_access_test
}  // namespace multiray
