// The PLY reader gives the same scene from ascii, binary little-endian and binary
// big-endian encodings of one mesh that also carries properties and elements it must
// skip (as real files do: the bunny has confidence/intensity per vertex).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scene/loaders.h"

namespace multiray {
namespace ply_format_test {

namespace fs = std::filesystem;

// A unit square as one quad plus a triangle on top (5 vertices, 3 triangles).
const float kVerts[5][8] = {
    // x y z   nx ny nz   s t
    {0, 0, 0, 0, 0, 1, 0, 0},
    {1, 0, 0, 0, 0, 1, 1, 0},
    {1, 1, 0, 0, 0, 1, 1, 1},
    {0, 1, 0, 0, 0, 1, 0, 1},
    {0.5f, 2, 0, 0, 0, 1, 0.5f, 1}};

const char* kHeader =
    "element vertex 5\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property uchar confidence\n"  // skipped, between the position and the normal
    "property float nx\nproperty float ny\nproperty float nz\n"
    "property list uchar short junk\n"  // skipped list property
    "property double s\nproperty double t\n"
    "element face 2\n"
    "property uchar flags\n"  // skipped scalar before the list
    "property list uchar uint vertex_indices\n"
    "element edge 1\nproperty int vertex1\nproperty int vertex2\n"  // skipped element
    "end_header\n";

class Writer {
 public:
  explicit Writer(int format) : format_(format) {}
  template <typename T>
  void put(T v) {
    if (format_ == 0) {
      out_ << +v << ' ';
      return;
    }
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (format_ == 2) std::reverse(b, b + sizeof(T));
    out_.write(b, sizeof(T));
  }
  void end_line() {
    if (format_ == 0) out_ << '\n';
  }
  std::string str() const { return out_.str(); }

 private:
  int format_;
  std::ostringstream out_;
};

std::string make_ply(int format) {
  static const char* names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
  Writer w(format);
  for (const auto& v : kVerts) {
    for (int i = 0; i < 3; ++i) w.put<float>(v[i]);
    w.put<uint8_t>(200);
    for (int i = 3; i < 6; ++i) w.put<float>(v[i]);
    w.put<uint8_t>(2), w.put<int16_t>(-7), w.put<int16_t>(300);
    w.put<double>(v[6]), w.put<double>(v[7]);
    w.end_line();
  }
  w.put<uint8_t>(1), w.put<uint8_t>(4);
  for (uint32_t i : {0u, 1u, 2u, 3u}) w.put<uint32_t>(i);
  w.end_line();
  w.put<uint8_t>(0), w.put<uint8_t>(3);
  for (uint32_t i : {3u, 2u, 4u}) w.put<uint32_t>(i);
  w.end_line();
  w.put<int32_t>(0), w.put<int32_t>(1);
  w.end_line();
  return std::string("ply\nformat ") + names[format] + " 1.0\ncomment test\n" + kHeader + w.str();
}

TEST(PlyFormat, AsciiAndBothBinaryByteOrdersAgree) {
  const fs::path dir = fs::temp_directory_path() / ("multiray_ply_" + std::to_string(getpid()));
  fs::create_directories(dir);
  Scene scenes[3];
  for (int f = 0; f < 3; ++f) {
    const std::string p = (dir / ("square" + std::to_string(f) + ".ply")).string();
    std::ofstream(p, std::ios::binary) << make_ply(f);
    scenes[f] = load_ply(p);
  }
  fs::remove_all(dir);
  const Scene& a = scenes[0];
  ASSERT_EQ(a.triangle_count(), 3u);
  EXPECT_EQ(a.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 3, 2, 4}));  // fans
  ASSERT_EQ(a.positions.size(), 5u);
  ASSERT_EQ(a.normals.size(), 5u);
  ASSERT_EQ(a.uvs.size(), 5u);
  EXPECT_FLOAT_EQ(a.positions[4].x, 0.5f);
  EXPECT_FLOAT_EQ(a.positions[4].y, 2.0f);
  EXPECT_FLOAT_EQ(a.normals[2].z, 1.0f);
  EXPECT_FLOAT_EQ(a.uvs[1].x, 1.0f);
  EXPECT_FLOAT_EQ(a.uvs[1].y, 1.0f);  // t = 0 at the bottom becomes v = 1
  for (int f = 1; f < 3; ++f) {
    const Scene& b = scenes[f];
    EXPECT_EQ(b.indices, a.indices) << "format " << f;
    ASSERT_EQ(b.positions.size(), a.positions.size());
    for (size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_EQ(b.positions[i].x, a.positions[i].x) << "format " << f << " vertex " << i;
      EXPECT_EQ(b.positions[i].y, a.positions[i].y) << "format " << f << " vertex " << i;
      EXPECT_EQ(b.normals[i].z, a.normals[i].z) << "format " << f << " vertex " << i;
      EXPECT_EQ(b.uvs[i].x, a.uvs[i].x) << "format " << f << " vertex " << i;
      EXPECT_EQ(b.uvs[i].y, a.uvs[i].y) << "format " << f << " vertex " << i;
    }
  }
}

}  // namespace ply_format_test
}  // namespace multiray
