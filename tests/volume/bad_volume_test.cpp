// Hostile and broken volume files: each is refused with one InputError line naming the
// problem, before anything large is allocated and without opening FIFOs. Loads run under
// the 10 s guard of tests/scene/load_guard.h, so a blocked open fails instead of hanging.
#include <gtest/gtest.h>
#include <zlib.h>

#include <string>

#include "scene/load_guard.h"
#include "volume/load_volume.h"
#include "volume/volume_test_files.h"

namespace multiray {
namespace bad_volume_test {

using test::expect_input_error;
using test::nrrd_header;
using test::within_10s;

class BadVolume : public test::VolumeFiles {
 protected:
  // Loads the NRRD file `name` (relative to the test folder) under the guard.
  test::Outcome load(const std::string& name, VolumeLoadOptions o = {}) {
    const std::string p = (dir_ / name).string();
    return within_10s([p, o] { load_volume(p, o); });
  }
};

TEST_F(BadVolume, DataFileShortOrLongByOneByte) {
  write("vol/short.raw", std::string(999, '\0'));
  write("vol/long.raw", std::string(1001, '\0'));
  write("vol/s.nhdr", nrrd_header("uint8", "10 10 10", "data file: short.raw\n"));
  write("vol/l.nhdr", nrrd_header("uint8", "10 10 10", "data file: long.raw\n"));
  expect_input_error(load("vol/s.nhdr"), {"s.nhdr", "short.raw", "1 byte short", "1000"});
  expect_input_error(load("vol/l.nhdr"), {"l.nhdr", "long.raw", "1 byte too long", "1001"});
  // Attached data too.
  write("vol/a.nrrd", nrrd_header("uint8", "2 2 2") + "\n" + std::string(7, '\0'));
  expect_input_error(load("vol/a.nrrd"), {"a.nrrd", "1 byte short"});
}

TEST_F(BadVolume, GzipDataThatDecodesShort) {
  const std::string data(999, '\x01');
  const std::string gz = (dir_ / "vol/g.gz").string();
  gzFile f = gzopen(gz.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, data.data(), unsigned(data.size())), int(data.size()));
  gzclose(f);
  std::string h = nrrd_header("uint8", "10 10 10", "data file: g.gz\n");
  h.replace(h.find("encoding: raw"), 13, "encoding: gzip");
  write("vol/g.nhdr", h);
  expect_input_error(load("vol/g.nhdr"), {"g.nhdr", "data file 'g.gz'", "1000", "999"});
}

// `data` as one gzip member (zlib's deflate at `level` with a gzip wrapper), in memory.
std::string gzip_bytes(const std::string& data, int level = 9) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, level, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, uLong(data.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = uInt(data.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// 1000 bytes that compress to a few hundred: every corruption shows in the stream.
std::string varied_bytes() {
  std::string s;
  for (int i = 0; i < 1000; ++i) s.push_back(char((i * 37 + i / 7) % 251));
  return s;
}

TEST_F(BadVolume, CorruptGzipDataAreRefused) {
  // Issue 31: 8 bytes overwritten rendered with exit 0. Teem stops reading once it has the
  // voxels, so a corruption that decodes into valid but wrong (or more) bytes was never
  // noticed: zlib's CRC and length check at the end of the stream was not reached.
  std::string smooth;
  for (int z = 0; z < 32; ++z)
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) smooth.push_back(char((x * x + y * 3 + z) / 7 % 256));
  std::string gz = gzip_bytes(smooth, 6);                   // 1573 bytes
  for (size_t i = 837; i < 845; ++i) gz[i] = char(~gz[i]);  // one of the places Teem missed
  write("vol/s.gz", gz);
  std::string n = nrrd_header("uint8", "32 32 32", "data file: s.gz\n");
  n.replace(n.find("encoding: raw"), 13, "encoding: gzip");
  write("vol/s.nhdr", n);
  expect_input_error(load("vol/s.nhdr"), {"s.nhdr", "data file 's.gz'", "gzip data are corrupt"});
  // Small streams, corrupted at the end (the CRC and length), in the middle, cut short,
  // or followed by other bytes.
  std::string h = nrrd_header("uint8", "10 10 10", "data file: g.gz\n");
  h.replace(h.find("encoding: raw"), 13, "encoding: gzip");
  write("vol/g.nhdr", h);
  const std::string good = gzip_bytes(varied_bytes());
  write("vol/g.gz", good);
  EXPECT_TRUE(load("vol/g.nhdr").returned);
  std::string bad = good;
  for (size_t i = bad.size() - 8; i < bad.size(); ++i) bad[i] = char(~bad[i]);  // CRC, length
  write("vol/g.gz", bad);
  expect_input_error(load("vol/g.nhdr"),
                     {"g.nhdr", "data file 'g.gz'", "corrupt", "incorrect data check"});
  bad = good;
  for (size_t i = 40; i < 48; ++i) bad[i] = '\x55';  // inside the deflate data
  write("vol/g.gz", bad);
  expect_input_error(load("vol/g.nhdr"), {"g.nhdr", "data file 'g.gz'", "gzip"});
  write("vol/g.gz", good.substr(0, good.size() - 5));
  expect_input_error(load("vol/g.nhdr"), {"g.nhdr", "data file 'g.gz'", "truncated"});
  write("vol/g.gz", good + "trailing");
  expect_input_error(load("vol/g.nhdr"),
                     {"g.nhdr", "data file 'g.gz'", "8 bytes after the end of its gzip data"});
  // Two gzip members (cat a.gz b.gz) are one stream of data.
  const std::string v = varied_bytes();
  write("vol/g.gz", gzip_bytes(v.substr(0, 300)) + gzip_bytes(v.substr(300)));
  EXPECT_TRUE(load("vol/g.nhdr").returned);
}

TEST_F(BadVolume, GzipDataThatDecodeLongAreRefusedAsRawDataAre) {
  // Issue 31: raw data one byte too long were refused, gzip data were not.
  std::string h = nrrd_header("uint8", "10 10 10", "data file: g.gz\n");
  h.replace(h.find("encoding: raw"), 13, "encoding: gzip");
  write("vol/g.nhdr", h);
  write("vol/g.gz", gzip_bytes(std::string(1001, '\x01')));
  expect_input_error(load("vol/g.nhdr"), {"g.nhdr", "data file 'g.gz'", "too long", "1000"});
  // A byte skip counts decoded bytes: 1 skipped + 1000 voxels is exactly right.
  write("vol/s.nhdr", h + "byte skip: 1\n");
  write("vol/g.gz", gzip_bytes(std::string(1001, '\x01')));
  EXPECT_TRUE(load("vol/s.nhdr").returned);
  // Byte skip -1: the voxels are the last bytes; a little before them is fine.
  write("vol/m.nhdr", h + "byte skip: -1\n");
  EXPECT_TRUE(load("vol/m.nhdr").returned);
}

TEST_F(BadVolume, TinyGzipClaimingHugeGridIsRefusedBeforeAllocating) {
  // Issue 31: a 100-byte gzip volume claiming 2^31 voxels had Teem allocate 2.1 GB first.
  std::string h = nrrd_header("uint8", "2048 1024 1024");
  h.replace(h.find("encoding: raw"), 13, "encoding: gzip");
  write("vol/big.nrrd", h + "\n" + gzip_bytes(std::string(4000, '\0')));
  expect_input_error(load("vol/big.nrrd"),
                     {"big.nrrd", "too short for 2048x1024x1024 uint8", "decode to at most"});
}

TEST_F(BadVolume, AbsurdDimensionsAreRefusedBeforeAllocating) {
  write("vol/d.raw", "x");
  write("vol/h.nhdr", nrrd_header("uint8", "100000 100000 100000", "data file: d.raw\n"));
  expect_input_error(load("vol/h.nhdr"), {"h.nhdr", "axis 0 has 100000 samples", "16384"});
  // Each axis within the limit, the product not.
  write("vol/p.nhdr", nrrd_header("uint8", "16384 16384 16384", "data file: d.raw\n"));
  expect_input_error(load("vol/p.nhdr"), {"p.nhdr", "voxels, more than the limit"});
}

TEST_F(BadVolume, NotThreeDimensions) {
  write("vol/2d.nrrd", "NRRD0004\ntype: uint8\ndimension: 2\nsizes: 2 2\nencoding: raw\n\nabcd");
  expect_input_error(load("vol/2d.nrrd"), {"2d.nrrd", "2 dimensions", "exactly 3"});
  write("vol/4d.nrrd", "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 1 1 1 2\nencoding: raw\n\nab");
  expect_input_error(load("vol/4d.nrrd"), {"4 dimensions"});
}

TEST_F(BadVolume, UnsupportedTypesAndEncodings) {
  for (const char* type : {"float", "double", "int32", "uint64"}) {
    write("vol/t.nrrd",
          nrrd_header(type, "1 1 1", "endian: little\n") + "\n" + std::string(8, '\0'));
    expect_input_error(load("vol/t.nrrd"), {"t.nrrd", "voxel type", "not supported"});
  }
  write("vol/b.nrrd",
        "NRRD0004\ntype: block\nblock size: 4\ndimension: 3\nsizes: 1 1 1\n"
        "encoding: raw\n\nabcd");
  expect_input_error(load("vol/b.nrrd"), {"b.nrrd", "block"});
  write("vol/e.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1 1 2\nencoding: ascii\n\n1 2");
  expect_input_error(load("vol/e.nrrd"), {"encoding 'ascii' is not supported"});
  write("vol/x.nrrd", "P6\n1 1\n255\nabc");
  expect_input_error(load("vol/x.nrrd"), {"x.nrrd", "not a NRRD file"});
}

TEST_F(BadVolume, BadSpacings) {
  write("vol/d.raw", std::string(8, '\0'));
  const char* bad[] = {"spacings: 0 1 1\n",     "spacings: -1 1 1\n",
                       "spacings: nan 1 1\n",   "spacings: 1e-300 1 1\n",
                       "spacings: 1 1 1e300\n", "spacings: 0.001 1 10\n"};  // ratio 10000
  for (const char* line : bad) {
    write("vol/h.nhdr", nrrd_header("uint8", "2 2 2", line) + "data file: d.raw\n");
    const test::Outcome o = load("vol/h.nhdr");
    expect_input_error(o, {"h.nhdr"});
    EXPECT_NE(o.message.find("spacing"), std::string::npos) << o.message;
  }
  write("vol/r.nhdr", nrrd_header("uint8", "2 2 2",
                                  "space dimension: 3\n"
                                  "space directions: (1,1,0) (0,1,0) (0,0,1)\n") +
                          "data file: d.raw\n");
  expect_input_error(load("vol/r.nhdr"), {"not axis-aligned"});
}

TEST_F(BadVolume, FifoDirectoryAndDeviceAreNeverRead) {
  fifo("vol/fifo.raw");
  write("vol/f.nhdr", nrrd_header("uint8", "2 2 2", "data file: fifo.raw\n"));
  expect_input_error(load("vol/f.nhdr"), {"f.nhdr", "fifo.raw", "not a regular file"});
  std::filesystem::create_directories(dir_ / "vol/dir.raw");
  write("vol/d.nhdr", nrrd_header("uint8", "2 2 2", "data file: dir.raw\n"));
  expect_input_error(load("vol/d.nhdr"), {"dir.raw", "not a regular file"});
  write("vol/z.nhdr", nrrd_header("uint8", "2 2 2", "data file: /dev/zero\n"));
  VolumeLoadOptions anywhere;
  anywhere.allow_outside = true;
  expect_input_error(load("vol/z.nhdr", anywhere), {"/dev/zero", "not a regular file"});
  // The header itself.
  fifo("vol/h.nhdr");
  expect_input_error(load("vol/h.nhdr"), {"h.nhdr", "not a regular file"});
  // Spellings Teem would also take as "data file" are checked the same way.
  write("vol/u.nhdr", nrrd_header("uint8", "2 2 2", "DATA FILE: fifo.raw\n"));
  expect_input_error(load("vol/u.nhdr"), {"fifo.raw", "not a regular file"});
}

TEST_F(BadVolume, DataFileOutsideTheFolder) {
  write("outside/d.raw", std::string(8, '\0'));
  write("vol/o.nhdr", nrrd_header("uint8", "2 2 2", "data file: ../outside/d.raw\n"));
  expect_input_error(load("vol/o.nhdr"), {"o.nhdr", "outside", "folder"});
  write("vol/p.nhdr", nrrd_header("uint8", "2 2 2", "data file: /etc/passwd\n"));
  expect_input_error(load("vol/p.nhdr"), {"/etc/passwd", "outside"});
}

TEST_F(BadVolume, SeveralDataFilesAreRefused) {
  write("vol/l.nhdr", nrrd_header("uint8", "2 2 2", "data file: LIST\na.raw\nb.raw\n"));
  expect_input_error(load("vol/l.nhdr"), {"lists of data files"});
  write("vol/n.nhdr", nrrd_header("uint8", "2 2 2", "data file: s%03d.raw 1 2 1 2\n"));
  expect_input_error(load("vol/n.nhdr"), {"numbered series"});
  write("vol/t.nhdr", nrrd_header("uint8", "2 2 2", "data file: a.raw\ndata file: b.raw\n"));
  expect_input_error(load("vol/t.nhdr"), {"more than one 'data file:'"});
}

TEST_F(BadVolume, MaxBytesIsCheckedBeforeReading) {
  write("vol/d.raw", std::string(64 * 64 * 64, '\0'));
  write("vol/h.nhdr", nrrd_header("uint8", "64 64 64", "data file: d.raw\n"));
  VolumeLoadOptions o;
  o.max_bytes = 1 << 20;  // the load takes about 1.3 MB
  expect_input_error(load("vol/h.nhdr", o), {"h.nhdr", "64x64x64 uint8", "more than the limit"});
  o.max_bytes = 2 << 20;
  EXPECT_TRUE(load("vol/h.nhdr", o).returned);
}

TEST_F(BadVolume, TeemErrorsAreOneLine) {
  write("vol/t.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2\nencoding: raw\n\nabcd");
  expect_input_error(load("vol/t.nrrd"), {"t.nrrd", "NRRD header: "});
  write("vol/n.nhdr", nrrd_header("uint8", "2 2 2"));  // no data file, no data
  expect_input_error(load("vol/n.nhdr"), {"no 'data file:' line"});
}

}  // namespace bad_volume_test
}  // namespace multiray
