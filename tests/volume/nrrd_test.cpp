// NRRD files written here, read back exactly: every voxel type, both byte orders,
// attached and detached data, spacings and space directions, gzip.
#include <gtest/gtest.h>
#include <zlib.h>

#include <string>
#include <vector>

#include "volume/load_volume.h"
#include "volume/volume_test_files.h"

namespace multiray {
namespace nrrd_test {

using test::bytes16;
using test::nrrd_header;

class NrrdRead : public test::VolumeFiles {};

void expect_values(const Volume& v, const std::vector<float>& want) {
  ASSERT_EQ(v.values.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(v.values[i], want[i]) << "voxel " << i;
}

TEST_F(NrrdRead, DetachedUint8) {
  write("vol/a.raw", std::string("\x00\x01\x7f\x80\xfe\xff", 6));
  const Volume v =
      load_volume(write("vol/a.nhdr", nrrd_header("uchar", "3 2 1") + "data file: a.raw\n"));
  EXPECT_EQ(v.name, "a.nhdr");
  EXPECT_EQ(v.nx, 3);
  EXPECT_EQ(v.ny, 2);
  EXPECT_EQ(v.nz, 1);
  EXPECT_EQ(v.type, VoxelType::u8);
  expect_values(v, {0, 1, 127, 128, 254, 255});
  EXPECT_EQ(v.min_value, 0);
  EXPECT_EQ(v.max_value, 255);
  EXPECT_EQ(v.spacing.x, 1);  // no spacing given
  EXPECT_EQ(v.at(2, 1, 0), 255);
}

TEST_F(NrrdRead, AttachedInt8) {
  const Volume v = load_volume(write("vol/a.nrrd", nrrd_header("signed char", "2 1 2") + "\n" +
                                                       std::string("\x80\xff\x00\x7f", 4)));
  EXPECT_EQ(v.type, VoxelType::i8);
  expect_values(v, {-128, -1, 0, 127});
  EXPECT_EQ(v.min_value, -128);
  EXPECT_EQ(v.max_value, 127);
}

TEST_F(NrrdRead, Int16BothByteOrders) {
  for (bool big : {false, true}) {
    const std::string data = bytes16<int16_t>({-1024, -1, 0, 2986, 32767, -32768}, big);
    const std::string endian = big ? "big" : "little";
    const Volume v = load_volume(
        write("vol/" + endian + ".nrrd",
              nrrd_header("short", "1 2 3", "endian: " + endian + "\n") + "\n" + data));
    EXPECT_EQ(v.type, VoxelType::i16);
    expect_values(v, {-1024, -1, 0, 2986, 32767, -32768});
    EXPECT_EQ(v.min_value, -32768);
    EXPECT_EQ(v.max_value, 32767);
  }
}

TEST_F(NrrdRead, Uint16DetachedBigEndian) {
  write("vol/d.raw", bytes16<uint16_t>({0, 1, 256, 65535}, true));
  const Volume v = load_volume(
      write("vol/d.nhdr", nrrd_header("uint16", "2 2 1", "endian: big\ndata file: ./d.raw\n")));
  EXPECT_EQ(v.type, VoxelType::u16);
  expect_values(v, {0, 1, 256, 65535});
}

TEST_F(NrrdRead, SpacingsAndSpaceDirections) {
  write("vol/d.raw", std::string(8, '\x05'));
  Volume v = load_volume(
      write("vol/s.nhdr", nrrd_header("uint8", "2 2 2", "spacings: 0.9570312 0.9570312 1.5\n") +
                              "data file: d.raw\n"));
  EXPECT_FLOAT_EQ(v.spacing.x, 0.9570312f);
  EXPECT_FLOAT_EQ(v.spacing.y, 0.9570312f);
  EXPECT_FLOAT_EQ(v.spacing.z, 1.5f);
  EXPECT_FLOAT_EQ(v.voxel_length(), 0.9570312f);
  // LPS-style directions with a negative axis: the lengths are the spacing.
  v = load_volume(
      write("vol/dir.nhdr", nrrd_header("uint8", "2 2 2",
                                        "space: left-posterior-superior\n"
                                        "space directions: (0.5,0,0) (0,-2,0) (0,0,3)\n") +
                                "data file: d.raw\n"));
  EXPECT_EQ(v.spacing.x, 0.5f);
  EXPECT_EQ(v.spacing.y, 2.0f);
  EXPECT_EQ(v.spacing.z, 3.0f);
  const Bounds3 b = v.bounds();
  EXPECT_EQ(b.lo.x, -0.5f);
  EXPECT_EQ(b.hi.y, 2.0f);
  EXPECT_EQ(b.hi.z, 3.0f);
}

// Where the patient's front and head are: from `space` and the signs of `space
// directions` where the header has them, else the assumed convention (LAS: +y anterior,
// +z superior; volume.h says why).
TEST_F(NrrdRead, OrientationFromSpaceOrAssumed) {
  write("vol/o.raw", std::string(8, '\x05'));
  const auto read = [&](const std::string& fields) {
    return load_volume(
        write("vol/o.nhdr", nrrd_header("uint8", "2 2 2", fields) + "data file: o.raw\n"));
  };
  const auto same = [](Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
  Volume v = read("spacings: 1 1 1\n");
  EXPECT_FALSE(v.orientation.from_file);
  EXPECT_TRUE(same(v.orientation.anterior, Vec3(0, 1, 0)));
  EXPECT_TRUE(same(v.orientation.superior, Vec3(0, 0, 1)));
  v = read("space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n");
  EXPECT_TRUE(v.orientation.from_file);
  EXPECT_TRUE(same(v.orientation.anterior, Vec3(0, -1, 0))) << "LPS: +y is posterior";
  EXPECT_TRUE(same(v.orientation.superior, Vec3(0, 0, 1)));
  // Rows stored towards anterior and slices from the head down, in LPS.
  v = read("space: LPS\nspace directions: (1,0,0) (0,-1,0) (0,0,-2)\n");
  EXPECT_TRUE(same(v.orientation.anterior, Vec3(0, 1, 0)));
  EXPECT_TRUE(same(v.orientation.superior, Vec3(0, 0, -1)));
  v = read("space: right-anterior-superior\nspace directions: (-1,0,0) (0,1,0) (0,0,1)\n");
  EXPECT_TRUE(same(v.orientation.anterior, Vec3(0, 1, 0)));
  v = read("space: scanner-xyz\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n");
  EXPECT_TRUE(same(v.orientation.anterior, Vec3(0, -1, 0))) << "scanner-xyz is LPS";
  // A space without anatomy: the assumed convention.
  v = read("space: 3D-right-handed\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n");
  EXPECT_FALSE(v.orientation.from_file);
  EXPECT_TRUE(same(v.orientation.anterior, Vec3(0, 1, 0)));
}

TEST_F(NrrdRead, LineAndByteSkips) {
  write("vol/d.raw", "# text header\nXY" + std::string("\x01\x02", 2));
  const Volume v = load_volume(
      write("vol/k.nhdr",
            nrrd_header("uint8", "2 1 1", "line skip: 1\nbyte skip: 2\ndata file: d.raw\n")));
  expect_values(v, {1, 2});
  // Byte skip -1: the data are the file's last bytes.
  write("vol/e.raw", "junk" + std::string("\x03\x04", 2));
  const Volume e = load_volume(
      write("vol/e.nhdr", nrrd_header("uint8", "1 1 2", "byte skip: -1\ndata file: e.raw\n")));
  expect_values(e, {3, 4});
}

TEST_F(NrrdRead, GzipDetached) {
  const std::string data = bytes16<int16_t>({-5, 7, 300, -300}, false);
  const std::string gz = (dir_ / "vol/g.raw.gz").string();
  gzFile f = gzopen(gz.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, data.data(), unsigned(data.size())), int(data.size()));
  gzclose(f);
  std::string h = nrrd_header("int16", "2 2 1", "endian: little\ndata file: g.raw.gz\n");
  h.replace(h.find("encoding: raw"), 13, "encoding: gzip");
  const Volume v = load_volume(write("vol/g.nhdr", h));
  expect_values(v, {-5, 7, 300, -300});
}

TEST_F(NrrdRead, OutsideDataFileReadWhenAllowed) {
  write("outside/d.raw", std::string(4, '\x09'));
  const std::string h =
      write("vol/o.nhdr", nrrd_header("uint8", "2 2 1", "data file: ../outside/d.raw\n"));
  VolumeLoadOptions o;
  o.allow_outside = true;
  EXPECT_EQ(load_volume(h, o).values[3], 9);
}

}  // namespace nrrd_test
}  // namespace multiray
