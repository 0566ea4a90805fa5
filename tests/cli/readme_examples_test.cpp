// The README's examples, run as written and in order (issue 32: "every README example runs
// as written"). The commands are read from the sh blocks of README.md's "Using it" section,
// run from a folder laid out like a fresh clone after `make run` (build/, examples/, and
// ../shared beside it when it exists here), and each must exit 0 and write what it names:
// -o's file or folder, --json, --report, and every "-> FILE" a render prints. A command
// that needs what this machine lacks (../shared/data, Debian's assimp models, an OpenCL
// device, mpirun) is skipped with a message; the view example runs until Ctrl-C, so it
// gets a SIGINT after a few seconds and must then have served its page's address.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_cli.h"

namespace readme_examples_test {

namespace fs = std::filesystem;
using multiray::testing::run_cli;

// The commands of the sh blocks between "## Using it" and the next "## " heading, with
// continuation lines joined.
std::vector<std::string> readme_commands(const std::string& readme) {
  std::ifstream in(readme);
  std::vector<std::string> commands;
  std::string line, pending;
  bool section = false, block = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) section = line == "## Using it";
    if (!section) continue;
    if (line.rfind("```", 0) == 0) {
      block = !block && line == "```sh";
      continue;
    }
    if (!block) continue;
    if (!line.empty() && line.back() == '\\') {
      pending += line.substr(0, line.size() - 1);
      continue;
    }
    line = pending + line;
    pending.clear();
    if (line.find_first_not_of(' ') != std::string::npos && line[0] != '#')
      commands.push_back(line);
  }
  return commands;
}

std::vector<std::string> words(const std::string& command) {
  std::istringstream in(command.substr(0, command.find(" #")));
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

// What `command` says it writes, relative to the clone: -o's file (the first frame of a
// #### pattern) or folder (its stats.json), --json, --report.
std::vector<std::string> named_outputs(const std::string& command) {
  const std::vector<std::string> w = words(command);
  std::vector<std::string> out;
  for (size_t i = 0; i + 1 < w.size(); ++i) {
    const std::string& v = w[i + 1];
    if (w[i] == "-o" || w[i] == "--out") {
      const bool image = std::regex_search(v, std::regex("\\.(png|exr)$"));
      out.push_back(image ? std::regex_replace(v, std::regex("#"), "0") : v + "/stats.json");
    } else if (w[i] == "--json" || w[i] == "--report") {
      out.push_back(v);
    }
  }
  return out;
}

// Why this machine cannot run `command` as written, or "" when it can.
std::string missing_for(const std::string& command, const std::string& clone) {
  if (command.find("../shared/data") != std::string::npos &&
      !fs::exists(clone + "/../shared/data"))
    return "../shared/data is absent";
  if (command.find("/usr/share/assimp") != std::string::npos &&
      !fs::exists("/usr/share/assimp/models"))
    return "Debian's assimp-testmodels are not installed";
  if (command.rfind("mpirun", 0) == 0 && run_cli("sh", "-c 'command -v mpirun'").code != 0)
    return "mpirun is not installed";
  if (command.find("opencl") != std::string::npos &&
      run_cli(MULTIRAY_BIN, "devices").out.find("opencl:0") == std::string::npos)
    return "no OpenCL device";
  return "";
}

TEST(Readme, EveryExampleRunsAsWrittenAndWritesWhatItSays) {
  const std::vector<std::string> commands =
      readme_commands(std::string(MULTIRAY_SOURCE_DIR) + "/README.md");
  ASSERT_GE(commands.size(), 10u) << "the README's examples were not found";
  // A fresh clone after `make run`: build/ and examples/ in it, ../shared beside it.
  // A folder of its own: a fixed /tmp/readme_examples was shared by every worktree's run,
  // and one run's remove_all deleted another's clone mid-command (issue 51).
  std::string pattern = (fs::temp_directory_path() / "readme_examples.XXXXXX").string();
  ASSERT_NE(mkdtemp(pattern.data()), nullptr) << pattern;
  const std::string root = pattern;
  const std::string clone = root + "/multiray";
  fs::create_directories(clone);
  fs::create_directory_symlink(MULTIRAY_BUILD_DIR, clone + "/build");
  fs::create_directory_symlink(std::string(MULTIRAY_SOURCE_DIR) + "/examples",
                               clone + "/examples");
  const fs::path data(MULTIRAY_SHARED_DATA_DIR);  // ../shared/data of the real clone
  if (fs::exists(data))
    fs::create_directory_symlink(fs::absolute(data).parent_path(), root + "/shared");

  // Twice in a row: a command must not be refused because its own earlier run's outputs
  // are there (issue 51).
  for (int pass = 0; pass < 2; ++pass) {
    std::string exports;  // `export` lines hold for the commands after them
    for (const std::string& command : commands) {
      if (command.rfind("export ", 0) == 0) {
        exports += command.substr(0, command.find(" #")) + "\n";
        continue;
      }
      const std::string why = missing_for(command, clone);
      if (!why.empty()) {
        std::printf("skipped (%s): %s\n", why.c_str(), command.c_str());
        continue;
      }
      const bool until_interrupted = command.find("until Ctrl-C") != std::string::npos;
      // The command as written, in a script, after the exports before it.
      const std::string script = root + "/example.sh";
      std::ofstream(script) << exports << "\n"
                            << (until_interrupted ? "timeout --preserve-status -s INT 4 " : "")
                            << command << "\n";
      const auto start = std::chrono::steady_clock::now();
      const auto r = run_cli("sh", script, "cd '" + clone + "' &&", 600);
      std::printf("pass %d: %s\n  exit %d after %.1f s\n", pass + 1, command.c_str(), r.code,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      if (until_interrupted) {
        if (r.out.find("cannot listen on") != std::string::npos) {  // the port is someone else's
          std::printf("skipped (its port is in use here): %s\n", command.c_str());
          continue;
        }
        EXPECT_TRUE(r.code == 0 || r.code == 130) << command << "\n" << r.out;
        EXPECT_NE(r.out.find("http://127.0.0.1:8080/"), std::string::npos) << r.out;
        continue;
      }
      EXPECT_EQ(r.code, 0) << command << "\n" << r.out;
      for (const std::string& f : named_outputs(command))
        EXPECT_TRUE(fs::exists(clone + "/" + f)) << command << "\n  did not write " << f;
      const std::regex arrow("-> (\\S+)");
      for (std::sregex_iterator it(r.out.begin(), r.out.end(), arrow), end; it != end; ++it)
        EXPECT_TRUE(fs::exists(clone + "/" + (*it)[1].str())) << command << "\n  no " << (*it)[1];
    }
  }
  if (::testing::Test::HasFailure())
    std::printf("outputs kept in %s\n", root.c_str());
  else
    fs::remove_all(root);
}

}  // namespace readme_examples_test
