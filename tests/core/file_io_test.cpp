// Atomic writes (core/file_io.h): the whole new file or the old one, and never a
// temporary file left behind, whichever step fails.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
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
  // A folder appears at the target while the temporary file is written (after the check
  // that refuses a folder up front), so renaming the file over it fails.
  const std::string p = path("taken");
  try {
    replace_file_atomically(p, [&](const std::string& temp) {
      fs::create_directories(p);
      std::ofstream(p + "/inside.txt") << "keep me";
      std::ofstream(temp, std::ios::binary) << "new contents";
    });
    ADD_FAILURE() << "renaming a file over a folder succeeded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("renaming"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(p));
  EXPECT_EQ(read(p + "/inside.txt"), "keep me");
  EXPECT_EQ(leftovers(), std::vector<std::string>{});
}

// Outputs are renamed into place, so a FIFO, a device or a folder at an output's name
// would be replaced by a regular file (as root, /dev/null itself): refused, untouched.
TEST_F(FileIo, OnlyRegularFilesOrNewNamesAreOutputs) {
  const std::string fifo = path("pipe");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
  const std::string folder = path("folder");
  fs::create_directories(folder);
  // A private null device (root only), never the system's /dev/null: were the check ever
  // broken, the write below would replace it.
  const std::string device = path("null");
  std::vector<std::string> specials{fifo, folder};
  if (mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) specials.push_back(device);
  for (const std::string& p : specials) {
    try {
      write_file_atomically(p, std::string("x"));
      ADD_FAILURE() << p << " was written";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("regular file"), std::string::npos) << e.what();
    }
    EXPECT_THROW(replace_file_atomically(p, [](const std::string&) {}), InputError) << p;
    EXPECT_THROW(check_output_file(p, "--trace"), InputError) << p;
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  if (specials.size() > 2) {
    EXPECT_TRUE(fs::is_character_file(device));
  }
  EXPECT_TRUE(leftovers().empty());
  // A new name, a regular file and a link to a regular file are outputs.
  EXPECT_NO_THROW(check_output_file(path("new.json"), "--json"));
  write_file_atomically(path("file.json"), std::string("old"));
  fs::create_symlink(path("file.json"), path("link.json"));
  EXPECT_NO_THROW(write_file_atomically(path("link.json"), std::string("new")));
  EXPECT_EQ(read(path("file.json")), "old");  // the link was replaced, not its target
  EXPECT_EQ(read(path("link.json")), "new");
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
