// Atomic writes (core/file_io.h): the whole new file or the old one, and never a
// temporary file left behind, whichever step fails.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/file_io.h"

namespace multiray {
namespace file_io_test {

namespace fs = std::filesystem;

class FileIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("multiray_file_io_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // Names in the folder that are temporary files of an atomic write.
  std::vector<std::string> leftovers() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().find(".part-") != std::string::npos)
        out.push_back(e.path().filename().string());
    return out;
  }

  fs::path dir_;
};

TEST_F(FileIo, WritesTheWholeFileAndReplacesTheOldOne) {
  const std::string p = path("out.txt");
  write_file_atomically(p, std::string("old contents"));
  EXPECT_EQ(read(p), "old contents");
  std::string big(3 << 20, '\0');  // several MB, binary, so that writes may come in parts
  for (size_t i = 0; i < big.size(); ++i) big[i] = char((i * 7919) >> 3);
  write_file_atomically(p, big);
  EXPECT_EQ(read(p), big);
  write_file_atomically(p, std::string());  // empty is a file too
  EXPECT_TRUE(fs::exists(p));
  EXPECT_EQ(fs::file_size(p), 0u);
  EXPECT_TRUE(leftovers().empty());
}

TEST_F(FileIo, AFailedRenameKeepsTheTargetAndLeavesNoTemporaryFile) {
  // The target is a folder with a file in it: the temporary file is written, but renaming
  // it over the folder fails.
  const std::string p = path("taken");
  fs::create_directories(p);
  std::ofstream(p + "/inside.txt") << "keep me";
  try {
    write_file_atomically(p, std::string("new contents"));
    ADD_FAILURE() << "renaming a file over a folder succeeded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("renaming"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(p));
  EXPECT_EQ(read(p + "/inside.txt"), "keep me");
  EXPECT_EQ(leftovers(), std::vector<std::string>{});
}

TEST_F(FileIo, AMissingFolderIsAnInputError) {
  EXPECT_THROW(write_file_atomically(path("no/such/folder/out.txt"), std::string("x")),
               InputError);
  EXPECT_TRUE(leftovers().empty());
}

TEST_F(FileIo, ReplaceRenamesTheWritersFileOrRemovesItWhenTheWriterFails) {
  const std::string p = path("image.exr");
  write_file_atomically(p, std::string("old image"));
  std::string seen;
  replace_file_atomically(p, [&](const std::string& temp) {
    seen = temp;
    EXPECT_NE(temp, p);
    EXPECT_EQ(fs::path(temp).parent_path(), fs::path(p).parent_path());  // same folder
    std::ofstream(temp, std::ios::binary) << "new image";
  });
  EXPECT_EQ(read(p), "new image");
  EXPECT_FALSE(fs::exists(seen));

  EXPECT_THROW(replace_file_atomically(p,
                                       [](const std::string& temp) {
                                         std::ofstream(temp, std::ios::binary) << "half";
                                         throw std::runtime_error("encoder failed");
                                       }),
               std::runtime_error);
  EXPECT_EQ(read(p), "new image");  // the old file stays whole
  EXPECT_TRUE(leftovers().empty());

  // A writer that writes nothing: reopening the temporary file fails, as an InputError.
  EXPECT_THROW(replace_file_atomically(p, [](const std::string&) {}), InputError);
  EXPECT_EQ(read(p), "new image");
  EXPECT_TRUE(leftovers().empty());
}

}  // namespace file_io_test
}  // namespace multiray
