// golden_record: records the reference distributions of the golden image cases
// (tests/golden/README.md). For each case it renders K seeds through the command line,
// keeps each pixel's mean and variance, then renders H other seeds and checks them against
// what it recorded: the statistics' mean and standard deviation over those seeds (their
// null distributions) set the limits the test applies (tests/support/golden.h).
//
//   golden_record [--renders K] [--check H] [CASE ...]     (default: every case)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "golden/cases.h"
#include "golden/golden_run.h"
#include "support/golden.h"

namespace mt = multiray::testing;

namespace {

constexpr uint64_t kFirstSeed = 1000;    // recorded seeds: kFirstSeed, kFirstSeed + 1, ...
constexpr uint64_t kFirstCheck = 90000;  // checked seeds, never recorded

// Renders seeds [first, first + n) of `c`, two processes at a time, in seed order.
std::vector<mt::CaseRender> render_seeds(const mt::GoldenCase& c, uint64_t first, int n,
                                         const std::string& scratch) {
  std::vector<mt::CaseRender> out(static_cast<size_t>(n));
  auto work = [&](int lane) {
    for (int i = lane; i < n; i += 2) {
      out[size_t(i)] = mt::render_golden_case(MULTIRAY_BIN, c, MULTIRAY_SHARED_DATA_DIR,
                                              fmt::format("--seed {}", first + i),
                                              fmt::format("{}/{}_{}", scratch, c.name, lane));
      if (out[size_t(i)].cli.code != 0) {
        std::fprintf(stderr, "golden_record: %s seed %llu failed:\n%s\n", c.name.c_str(),
                     (unsigned long long)(first + i), out[size_t(i)].cli.out.c_str());
        std::exit(1);
      }
    }
  };
  std::thread a(work, 0), b(work, 1);
  a.join(), b.join();
  return out;
}

void record(const mt::GoldenCase& c, int renders, int checks) {
  const std::string dir = std::string(MULTIRAY_SOURCE_DIR) + "/tests/golden/" + c.name;
  const std::string scratch = std::filesystem::temp_directory_path().string() + "/golden_record";
  std::filesystem::create_directories(dir);
  std::map<std::string, mt::GoldenAccumulator> acc;
  for (const auto& r : render_seeds(c, kFirstSeed, renders, scratch))
    for (const auto& [stem, img] : r.images) acc[stem].add(img);
  std::map<std::string, mt::GoldenReference> refs;
  for (const auto& [stem, a] : acc) {
    refs[stem] = a.reference();
    mt::write_golden(dir + "/" + stem, refs[stem]);
  }
  // The null distributions: seeds never recorded, each image's statistics.
  std::map<std::string, std::vector<mt::GoldenVerdict>> verdicts;
  for (const auto& r : render_seeds(c, kFirstCheck, checks, scratch))
    for (const auto& [stem, img] : r.images)
      verdicts[stem].push_back(mt::compare_to_golden(img, refs.at(stem)));
  nlohmann::json null = nlohmann::json::object();
  for (const auto& [stem, vs] : verdicts)
    for (const auto& [name, d] : mt::null_of(vs)) null[stem][name] = {d.mean, d.sd};
  nlohmann::json doc = {{"case", c.name},
                        {"scene", c.scene},
                        {"args", c.args},
                        {"renders", renders},
                        {"first_seed", kFirstSeed},
                        {"images", acc.size()},
                        {"null_seeds", checks},
                        {"null_first_seed", kFirstCheck},
                        {"null", null}};
  std::ofstream(dir + "/reference.json") << doc.dump(2) << "\n";
  std::printf("%s: %zu images from %d renders, null distributions from %d other seeds\n",
              c.name.c_str(), acc.size(), renders, checks);
}

}  // namespace

int main(int argc, char** argv) {
  int renders = 256, checks = 64;
  std::vector<std::string> names;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--renders" || a == "--check") && i + 1 < argc)
      (a == "--renders" ? renders : checks) = std::atoi(argv[++i]);
    else
      names.push_back(a);
  }
  if (renders < 16 || checks < 1) {
    std::fprintf(stderr, "golden_record: --renders must be >= 16 and --check >= 1\n");
    return 2;
  }
  for (const std::string& n : names)
    if (!mt::find_golden_case(n)) {
      std::fprintf(stderr, "golden_record: no case '%s' (tests/golden/cases.h)\n", n.c_str());
      return 2;
    }
  for (const auto& c : mt::golden_cases())
    if (names.empty() || std::find(names.begin(), names.end(), c.name) != names.end()) {
      if (!c.scene.empty() &&
          !std::filesystem::exists(std::string(MULTIRAY_SHARED_DATA_DIR) + "/" + c.scene)) {
        std::fprintf(stderr, "golden_record: %s needs %s/%s\n", c.name.c_str(),
                     MULTIRAY_SHARED_DATA_DIR, c.scene.c_str());
        return 1;
      }
      record(c, renders, checks);
    }
  return 0;
}
