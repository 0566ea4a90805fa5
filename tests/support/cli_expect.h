// Checks shared by the command-line tests (gmock): a scratch file, and the project's rule
// for bad input — one line on stderr starting "multiray: error: ", exit code 2.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/run_cli.h"

namespace multiray::testing {

// Writes `content` to a file `name` and returns its path. The folder is this test
// process's own: ctest runs test processes in parallel, and two writing one /tmp/ball.raw
// while a third read it made a render fail now and then.
inline std::string temp_file(const std::string& name, const std::string& content) {
  const std::string dir = ::testing::TempDir() + "/multiray-test-" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

// One error line, exit code 2, and the message mentions `word`.
inline void expect_input_error(const CliResult& r, const std::string& args,
                               const std::string& word) {
  EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
  EXPECT_THAT(r.out, ::testing::HasSubstr(word)) << args;
  EXPECT_THAT(r.out, ::testing::StartsWith("multiray: error: ")) << args;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << args << "\n" << r.out;
}

}  // namespace multiray::testing
