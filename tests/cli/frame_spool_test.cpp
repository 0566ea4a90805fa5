// stats.json's frame records kept on disk (app/frame_spool.h): the document written is the
// one dump_json would give (and a newline) for the same records held in memory, byte for byte,
// whatever the strings hold; and nothing is left in the folder.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/frame_spool.h"
#include "study/stats_json.h"

namespace multiray::app {
namespace {

namespace fs = std::filesystem;

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/spool_" + std::to_string(getpid()) + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(FrameSpool, WritesWhatDumpJsonWouldForTheSameDocument) {
  for (const int frames : {0, 1, 3, 200}) {
    const std::string dir = fresh_dir(std::to_string(frames));
    nlohmann::json head{{"scene", "tri_\xE9.obj"},  // not UTF-8: escaped the same way
                        {"frames_requested", frames},
                        {"settings", {{"frames", frames}, {"note", "\"frames\": \"x\"\n"}}}};
    nlohmann::json whole = head;
    whole["frames"] = nlohmann::json::array();
    {
      FrameSpool spool(dir);
      for (int f = 0; f < frames; ++f) {
        nlohmann::json rec{{"frame", f},
                           {"devices", {{{"name", "cpu"}, {"ms", f * 0.5}}, {{"name", "gpu"}}}},
                           {"empty", nlohmann::json::array()},
                           {"text", "line\nbreak \xFF"}};
        spool.add(rec);
        whole["frames"].push_back(rec);
      }
      EXPECT_EQ(spool.size(), size_t(frames));
      spool.write(dir + "/stats.json", head);
    }
    EXPECT_EQ(read(dir + "/stats.json"), study::dump_json(whole, 1) + "\n") << frames << " frames";
    // Only stats.json: the records' file had no name, and the atomic write left no part.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += 1, (void)e;
    EXPECT_EQ(files, 1u);
  }
}

}  // namespace
}  // namespace multiray::app
