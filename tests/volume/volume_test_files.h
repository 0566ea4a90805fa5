// Small volume files written in a per-test temporary folder, and the shared real volumes
// (skipped with a message when ../shared/data is absent).
#pragma once

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace multiray::test {

namespace fs = std::filesystem;

// A real volume in ../shared/data/volumes.
inline std::string shared_volume(const std::string& name) {
  return std::string(MULTIRAY_SHARED_DATA_DIR) + "/volumes/" + name;
}

#define SKIP_IF_MISSING(path)                                                          \
  do {                                                                                 \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "test file missing: " << path; \
  } while (0)

// A fresh folder per test, removed afterwards; `dir_/vol` holds the files, `dir_/outside`
// is a sibling for files that must be refused.
class VolumeFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_volume_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "vol");
    fs::create_directories(dir_ / "outside");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `bytes` to `name` (relative to the test folder) and returns its path.
  std::string write(const std::string& name, const std::string& bytes) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  std::string fifo(const std::string& name) {
    const std::string p = (dir_ / name).string();
    EXPECT_EQ(mkfifo(p.c_str(), 0600), 0) << std::strerror(errno);
    return p;
  }

  fs::path dir_;
};

// Bytes of the 16-bit values `v`, big- or little-endian.
template <class T>
std::string bytes16(std::initializer_list<T> v, bool big_endian) {
  std::string s;
  for (T x : v) {
    const auto u = static_cast<uint16_t>(x);
    const char lo = char(u & 0xff), hi = char(u >> 8);
    s += big_endian ? std::string{hi, lo} : std::string{lo, hi};
  }
  return s;
}

// A NRRD header (NRRD0004) with the given type line, sizes and extra lines.
inline std::string nrrd_header(const std::string& type, const std::string& sizes,
                               const std::string& extra = "") {
  return "NRRD0004\ntype: " + type + "\ndimension: 3\nsizes: " + sizes + "\nencoding: raw\n" +
         extra;
}

}  // namespace multiray::test
