// Raw volumes: the command-line spec grammar and files read back exactly.
#include <gtest/gtest.h>

#include <string>

#include "scene/load_guard.h"
#include "volume/load_volume.h"
#include "volume/volume_test_files.h"

namespace multiray {
namespace raw_test {

using test::bytes16;
using test::expect_input_error;
using test::within_10s;

TEST(RawSpec, ParsesGridTypeByteOrderAndSpacing) {
  RawVolumeSpec s = parse_raw_spec("256x256x108:int16");
  EXPECT_EQ(s.nx, 256);
  EXPECT_EQ(s.ny, 256);
  EXPECT_EQ(s.nz, 108);
  EXPECT_EQ(s.type, VoxelType::i16);
  EXPECT_FALSE(s.big_endian);
  EXPECT_EQ(s.spacing.x, 1);
  s = parse_raw_spec("4x5x6:uint16:be:spacing=0.96,0.96,1.5");
  EXPECT_EQ(s.type, VoxelType::u16);
  EXPECT_TRUE(s.big_endian);
  EXPECT_EQ(s.spacing.x, 0.96f);
  EXPECT_EQ(s.spacing.z, 1.5f);
  s = parse_raw_spec("1x1x1:int8:spacing=2,2,2:le");
  EXPECT_EQ(s.type, VoxelType::i8);
  EXPECT_FALSE(s.big_endian);
  EXPECT_EQ(parse_raw_spec("1x1x1:uint8").type, VoxelType::u8);
}

TEST(RawSpec, BadSpecsAreOneLineNamingTheProblem) {
  auto bad = [](const std::string& text, std::initializer_list<std::string> words) {
    expect_input_error(within_10s([text] { parse_raw_spec(text); }), words);
  };
  bad("0x1x1:uint8", {"'0x1x1:uint8'", "axis 0 has 0 samples"});
  bad("0x1x1", {"axis 0 has 0 samples"});
  bad("10x10", {"NXxNYxNZ"});
  bad("10x10x10:float", {"unknown voxel type 'float'"});
  bad("-5x2x2:uint8", {"NXxNYxNZ", "whole numbers"});
  bad("3x3x3:uint8:spacing=0,1,1", {"spacing", "axis 0"});
  bad("3x3x3:uint8:spacing=1,1", {"three numbers"});
  bad("3x3x3:uint8:spacing=1,1,nan", {"spacing"});
  bad("3x3x3:uint8:spacing=1,1,1e300", {"spacing"});
  bad("3x3x3:uint8:be:le", {"byte order is given twice"});
  bad("3x3x3:uint8:fast", {"unknown option 'fast'"});
  bad("3x3x3", {"voxel type is missing"});
  bad("99999999999999999999x1x1:uint8", {"NXxNYxNZ"});
  bad("16385x1x1:uint8", {"16385 samples"});
  bad("16384x16384x16:uint8", {"more than the limit"});
}

class RawRead : public test::VolumeFiles {};

TEST_F(RawRead, EveryTypeAndByteOrder) {
  RawVolumeSpec s = parse_raw_spec("2x2x1:int16:be:spacing=1,2,3");
  Volume v = load_raw_volume(write("vol/be.raw", bytes16<int16_t>({-1024, 1, 2986, -2}, true)), s);
  EXPECT_EQ(v.values, (std::vector<float>{-1024, 1, 2986, -2}));
  EXPECT_EQ(v.min_value, -1024);
  EXPECT_EQ(v.max_value, 2986);
  EXPECT_EQ(v.spacing.y, 2);
  EXPECT_EQ(v.name, "be.raw");
  s = parse_raw_spec("2x2x1:uint16:le");
  v = load_raw_volume(write("vol/le.raw", bytes16<uint16_t>({65535, 0, 258, 1}, false)), s);
  EXPECT_EQ(v.values, (std::vector<float>{65535, 0, 258, 1}));
  s = parse_raw_spec("3x1x1:int8");
  v = load_raw_volume(write("vol/i8.raw", std::string("\xff\x80\x7f", 3)), s);
  EXPECT_EQ(v.values, (std::vector<float>{-1, -128, 127}));
  s = parse_raw_spec("3x1x1:uint8");
  v = load_raw_volume(write("vol/u8.raw", std::string("\xff\x80\x7f", 3)), s);
  EXPECT_EQ(v.values, (std::vector<float>{255, 128, 127}));
}

TEST_F(RawRead, SizeMustMatchExactly) {
  const RawVolumeSpec s = parse_raw_spec("10x10x10:uint8");
  const std::string shorter = write("vol/s.raw", std::string(999, '\0'));
  const std::string longer = write("vol/l.raw", std::string(1001, '\0'));
  expect_input_error(within_10s([&] { load_raw_volume(shorter, s); }), {"s.raw", "1 byte short"});
  expect_input_error(within_10s([&] { load_raw_volume(longer, s); }),
                     {"l.raw", "1 byte too long"});
}

TEST_F(RawRead, FifoAndMemoryLimitAreRefused) {
  const RawVolumeSpec s = parse_raw_spec("10x10x10:uint8");
  const std::string f = fifo("vol/f.raw");
  expect_input_error(within_10s([&] { load_raw_volume(f, s); }), {"f.raw", "not a regular file"});
  const std::string p = write("vol/p.raw", std::string(1000, '\0'));
  VolumeLoadOptions o;
  o.max_bytes = 4000;  // 1000 bytes + 4000 of floats
  expect_input_error(within_10s([&] { load_raw_volume(p, s, o); }),
                     {"more than the limit of 4000"});
  RawVolumeSpec bad = s;
  bad.nx = -5;  // specs built in code are checked too
  expect_input_error(within_10s([&] { load_raw_volume(p, bad); }), {"-5x10x10", "negative"});
}

TEST(RawSpec, TheFileNameIsCheckedWhereItDescribesTheData) {
  // Issue 31: 2x2x2 float32 and 4x4x2 uint8 are the same 32 bytes; only a name can tell.
  const RawVolumeSpec bytes = parse_raw_spec("4x4x2:uint8");
  bool described = false;
  const std::string m = raw_name_mismatch("/d/x_2x2x2_float32.raw", bytes, &described);
  EXPECT_TRUE(described);
  EXPECT_NE(m.find("its name says 2x2x2 float32, but --raw reads it as 4x4x2 uint8"),
            std::string::npos)
      << m;
  EXPECT_EQ(raw_name_mismatch("/d/bonsai_4x4x2_uint8.raw", bytes, &described), "");
  EXPECT_TRUE(described);
  EXPECT_NE(raw_name_mismatch("ct_int16.raw", bytes, &described).find("says int16"),
            std::string::npos);
  EXPECT_EQ(raw_name_mismatch("scan_4x4x2_1x2xA.raw", bytes, &described), "");  // not a grid
  // The shared volumes' spelling: a byte order after the type.
  EXPECT_EQ(raw_name_mismatch("ct_4x4x2_uint8le.raw", bytes, &described), "");
  EXPECT_NE(raw_name_mismatch("cranium_ct_4x4x2_int16le.raw", bytes, &described).find("int16"),
            std::string::npos);
  EXPECT_EQ(raw_name_mismatch("/d/plain.raw", bytes, &described), "");
  EXPECT_FALSE(described);
}

}  // namespace raw_test
}  // namespace multiray
