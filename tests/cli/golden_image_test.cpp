// Golden images that hold on every machine (tests/support/golden.h has the statistics,
// tests/golden/README.md how the references were recorded, docs/testing.md why exact
// hashes cannot be recorded across machines). Each case is rendered through the command
// line with every balancer and device count: within one machine and run the pixels must be
// bit-identical (the same hash), and the image must be a plausible draw from the recorded
// distribution. The same tolerance is then shown to admit what another machine does (other
// Embree kernels, another libm variant, other seeds altogether).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "golden/cases.h"
#include "golden/golden_run.h"
#include "support/golden.h"

namespace multiray::testing {
namespace golden_image_test {

const std::vector<std::string> kBalancers = {"uniform",     "static", "queue:tile=16",
                                             "semi-static", "dlb",    "hybrid"};
const std::vector<std::string> kDevices = {"cpu:threads=1", "cpu:threads=1,cpu:threads=1",
                                           "cpu:threads=2,cpu:threads=1,cpu:threads=1"};

std::string reference_dir(const GoldenCase& c) {
  return std::string(MULTIRAY_SOURCE_DIR) + "/tests/golden/" + c.name;
}

// Skips (returns false) when the case's scene is not here.
bool available(const GoldenCase& c) {
  return c.scene.empty() ||
         std::filesystem::exists(std::string(MULTIRAY_SHARED_DATA_DIR) + "/" + c.scene);
}

const GoldenCase& get(const std::string& name) {
  const GoldenCase* c = find_golden_case(name);
  if (!c) throw std::runtime_error("no golden case " + name);
  return *c;
}

CaseRender render(const GoldenCase& c, const std::string& extra, const std::string& tag,
                  const std::string& env = "") {
  return render_golden_case(MULTIRAY_BIN, c, MULTIRAY_SHARED_DATA_DIR, extra,
                            ::testing::TempDir() + "/golden_" + c.name + "_" + tag, env);
}

// Every image of `r` against the recorded reference; returns whether all passed.
bool matches_reference(const GoldenCase& c, const CaseRender& r, const std::string& what) {
  std::ifstream in(reference_dir(c) + "/reference.json");
  if (!in) {
    ADD_FAILURE() << c.name << ": no reference in " << reference_dir(c);
    return false;
  }
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("args").get<std::string>(), c.args)
      << c.name << ": the case changed since it was recorded; record it again";
  EXPECT_EQ(doc.at("images").get<size_t>(), r.images.size()) << c.name;
  bool all = !r.images.empty();
  for (const auto& [stem, img] : r.images) {
    std::map<std::string, NullDistribution> null;
    for (const auto& [name, d] : doc.at("null").at(stem).items()) null[name] = {d[0], d[1]};
    const GoldenVerdict v = compare_to_golden(
        img, read_golden(reference_dir(c) + "/" + stem, doc.at("renders").get<int>(), null));
    std::printf("golden %s %s %s: %s\n", c.name.c_str(), what.c_str(), stem.c_str(),
                v.summary().c_str());
    EXPECT_TRUE(v.pass()) << c.name << " " << what << " " << stem << ": " << v.summary();
    all = all && v.pass();
  }
  return all;
}

// Every balancer and device count gives the same pixels; they match the reference.
void check(const std::string& name) {
  const GoldenCase& c = get(name);
  if (!available(c)) GTEST_SKIP() << "needs " << c.scene << " in " << MULTIRAY_SHARED_DATA_DIR;
  CaseRender first;
  int run = 0;
  for (const std::string& dev : kDevices)
    for (const std::string& bal : kBalancers) {
      CaseRender r = render(c, "--devices " + dev + " --balancer " + bal, std::to_string(run++));
      ASSERT_EQ(r.cli.code, 0) << r.cli.out;
      ASSERT_EQ(r.hashes.size(), 2u) << c.name;
      if (first.hashes.empty())
        first = std::move(r);
      else
        EXPECT_EQ(r.hashes, first.hashes) << c.name << ": devices " << dev << ", balancer " << bal;
    }
  matches_reference(c, first, "seed 0");
}

TEST(GoldenImages, DefaultScenePathTracer) { check("default"); }
TEST(GoldenImages, DefaultSceneAdaptiveAO) { check("ao"); }
TEST(GoldenImages, DefaultSceneLightField) { check("views"); }
TEST(GoldenImages, DefaultSceneFoveatedAO) { check("foveated"); }
TEST(GoldenImages, Sponza) { check("sponza"); }

// What another machine does to the pixels, done here: Embree's other kernels (AVX2 and
// SSE give other hit distances in the last bits than AVX-512, hence other hashes), libm
// without its FMA and AVX2 variants, and another seed (every sample different). The hash
// changes; the golden still passes.
TEST(GoldenImages, HoldOnAnotherMachinesCodePaths) {
  const GoldenCase& c = get("default");
  const CaseRender here = render(c, "", "here");
  ASSERT_EQ(here.cli.code, 0) << here.cli.out;
  const std::vector<std::pair<std::string, std::string>> paths = {
      {"embree isa=avx2", "MULTIRAY_EMBREE_CONFIG=isa=avx2"},
      {"embree isa=sse2", "MULTIRAY_EMBREE_CONFIG=isa=sse2"},
      {"libm without FMA/AVX2", "GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA"},
  };
  int changed = 0, run = 0;
  for (const auto& [what, env] : paths) {
    const CaseRender r = render(c, "", "path" + std::to_string(run++), env);
    ASSERT_EQ(r.cli.code, 0) << r.cli.out;
    changed += r.hashes != here.hashes;
    std::printf("%s: hashes %s\n", what.c_str(), r.hashes != here.hashes ? "differ" : "equal");
    EXPECT_TRUE(matches_reference(c, r, what));
  }
  // At least one forced path must really change the pixels, or this test shows nothing.
  EXPECT_GE(changed, 1);
  for (const char* seed : {"7", "123456789"}) {
    const CaseRender r = render(c, std::string("--seed ") + seed, std::string("seed") + seed);
    ASSERT_EQ(r.cli.code, 0) << r.cli.out;
    EXPECT_NE(r.hashes, here.hashes);
    EXPECT_TRUE(matches_reference(c, r, std::string("seed ") + seed));
  }
}

}  // namespace golden_image_test
}  // namespace multiray::testing
