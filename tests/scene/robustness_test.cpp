// Damaged and deliberately invalid files: every load either succeeds (a validated
// scene) or throws InputError with one line. Uses assimp's invalid test models and
// truncated / byte-flipped copies of real files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "core/error.h"
#include "scene/loaders.h"

namespace multiray {
namespace robustness_test {

namespace fs = std::filesystem;

// 1 if `path` loads, 0 if it is rejected properly; a test failure otherwise.
int load_or_reject(const std::string& path) {
  try {
    load_scene(path);
    return 1;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return 0;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": not an InputError: " << e.what();
    return 0;
  }
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(Robustness, AssimpInvalidModels) {
  const fs::path root = MULTIRAY_ASSIMP_MODELS_DIR;
  if (!fs::exists(root)) GTEST_SKIP() << "assimp test models missing: " << root;
  const char* files[] = {"invalid/empty.obj",
                         "invalid/malformed.obj",
                         "invalid/malformed2.obj",
                         "invalid/empty.ply",
                         "glTF2/IndexOutOfRange/IndexOutOfRange.gltf",
                         "glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf",
                         "glTF2/RecursiveNodes/RecursiveNodes.gltf",
                         "glTF2/MissingBin/BoxTextured.gltf",
                         "glTF2/IncorrectVertexArrays/Cube.gltf",
                         "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
                         "glTF2/TestNoRootNode/NoScene.gltf",
                         "glTF2/TestNoRootNode/SceneWithoutNodes.gltf",
                         "glTF2/wrongTypes/badArray.gltf",
                         "glTF2/wrongTypes/badExtension.gltf",
                         "glTF2/wrongTypes/badNumber.gltf",
                         "glTF2/wrongTypes/badObject.gltf",
                         "glTF2/wrongTypes/badString.gltf",
                         "glTF2/wrongTypes/badUint.gltf",
                         "PLY/issue623.ply",
                         "PLY/pond.0.ply",  // list on vertices; truncated body
                         "OBJ/number_formats.obj",
                         "OBJ/box_longline.obj"};
  for (const char* f : files)
    if (fs::exists(root / f)) load_or_reject((root / f).string());
  // These must be rejected: out-of-range indices, a node cycle, a missing buffer, and
  // a 936-corner face (tinyobjloader stores corner counts in a byte).
  for (const char* f :
       {"glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf",
        "glTF2/RecursiveNodes/RecursiveNodes.gltf", "glTF2/MissingBin/BoxTextured.gltf",
        "invalid/empty.ply", "OBJ/box_longline.obj"})
    if (fs::exists(root / f)) {
      EXPECT_EQ(load_or_reject((root / f).string()), 0) << f;
    }
}

class Damaged : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("multiray_damaged_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Loads copies of `src` cut at `cuts` evenly spaced lengths and with `flips` random
  // byte changes (fixed seed).
  void sweep(const std::string& src, int cuts, int flips) {
    if (!fs::exists(src)) GTEST_SKIP() << "test file missing: " << src;
    const std::string data = slurp(src);
    const std::string name = (dir_ / fs::path(src).filename()).string();
    for (int i = 0; i < cuts; ++i) {
      std::ofstream(name, std::ios::binary) << data.substr(0, data.size() * i / cuts);
      load_or_reject(name);
    }
    std::mt19937 rng(1234);
    for (int i = 0; i < flips; ++i) {
      std::string bad = data;
      for (int k = 0; k < 4; ++k) bad[rng() % bad.size()] = char(rng());
      std::ofstream(name, std::ios::binary) << bad;
      load_or_reject(name);
    }
  }
  fs::path dir_;
};

TEST_F(Damaged, BinaryPly) {
  sweep(std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/PLY/cube_binary.ply", 40, 200);
}
TEST_F(Damaged, AsciiPly) {
  sweep(std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/PLY/cube_uv.ply", 40, 200);
}
TEST_F(Damaged, Obj) { sweep(std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/OBJ/box.obj", 40, 200); }
TEST_F(Damaged, GltfEmbedded) {
  sweep(std::string(MULTIRAY_ASSIMP_MODELS_DIR) +
            "/glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf",
        40, 200);
}
TEST_F(Damaged, Glb) {
  sweep(std::string(MULTIRAY_ASSIMP_MODELS_DIR) + "/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
        40, 200);
}

}  // namespace robustness_test
}  // namespace multiray
