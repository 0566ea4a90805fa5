// `--balancer auto`, the default of render, as a user meets it: resolved from the devices
// before the session starts, said once on stderr (not with -q), recorded in stats.json
// beside the concrete spec the engine ran; accepted in bench's --balancers.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli_expect.h"

namespace auto_balancer_cli_test {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

nlohmann::json stats_of(const std::string& dir) {
  return nlohmann::json::parse(std::ifstream(dir + "/stats.json"));
}

std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(AutoBalancerCli, RenderWithoutBalancerRecordsWhatAutoPicked) {
  const std::string dir = fresh_dir("auto_default");
  const Result r =
      run("render --res 32x16 --spp 1 --devices cpu:threads=1,cpu:threads=1 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out,
              ::testing::HasSubstr("multiray: --balancer auto: hybrid:bands=1 (2 devices (cpu"));
  const auto doc = stats_of(dir);
  EXPECT_EQ(doc.at("settings").at("balancer"), "auto");  // as asked
  EXPECT_EQ(doc.at("balancer_auto").at("spec"), "hybrid:bands=1");
  EXPECT_THAT(doc.at("balancer_auto").at("reason").get<std::string>(),
              ::testing::HasSubstr("keeps its rays coherent"));
  EXPECT_THAT(doc.at("balancer").get<std::string>(), ::testing::StartsWith("hybrid:bands="));
}

TEST(AutoBalancerCli, OneDeviceRunsUniformAndQuietSaysNothing) {
  const std::string dir = fresh_dir("auto_one");
  const Result r =
      run("render --res 32x16 --spp 1 --devices cpu:threads=1 --balancer auto --mapping strips "
          "-q --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("--balancer auto")));
  const auto doc = stats_of(dir);
  EXPECT_EQ(doc.at("balancer_auto").at("spec"), "uniform");
  EXPECT_THAT(doc.at("balancer_auto").at("reason").get<std::string>(),
              ::testing::HasSubstr("1 device (cpu); nothing to balance"));
  // --mapping applies to what auto picked.
  EXPECT_THAT(doc.at("balancer").get<std::string>(),
              ::testing::StartsWith("uniform:layout=strips"));
  // A named balancer has no balancer_auto.
  const std::string named = fresh_dir("auto_named");
  ASSERT_EQ(
      run("render --res 32x16 --spp 1 --devices cpu:threads=1 --balancer queue -q --out " + named)
          .code,
      0);
  EXPECT_FALSE(stats_of(named).contains("balancer_auto"));
}

// stats.json of a quiet render on two one-thread CPU devices with `options`, into a
// fresh folder `name` (the test fails if the render does).
nlohmann::json two_device_render(const std::string& name, const std::string& options) {
  const std::string dir = fresh_dir(name);
  const Result r = run("render --res 32x16 " + options +
                       " --devices cpu:threads=1,cpu:threads=1 -q --out " + dir);
  EXPECT_EQ(r.code, 0) << r.out;
  return r.code == 0 ? stats_of(dir) : nlohmann::json::object();
}

// The run layer hands the workload to the rules: foveated sampling has a row of its own.
TEST(AutoBalancerCli, FoveatedSamplingReachesTheRules) {
  const auto doc = two_device_render("auto_foveated", "--sampling foveated --integrator ao");
  ASSERT_TRUE(doc.contains("balancer_auto"));
  EXPECT_EQ(doc.at("balancer_auto").at("spec"), "semi-static:split=rows:cdf=frame");
  EXPECT_THAT(doc.at("balancer").get<std::string>(), ::testing::StartsWith("semi-static:"));
}

// --ground (a shadow catcher) reaches the rules: hybrid's interleaved bands.
TEST(AutoBalancerCli, AShadowCatcherReachesTheRules) {
  const auto doc = two_device_render("auto_catcher", "--spp 1 --ground y=0 --sun 40,35");
  ASSERT_TRUE(doc.contains("balancer_auto"));
  EXPECT_EQ(doc.at("balancer_auto").at("spec"), "hybrid");
  EXPECT_THAT(doc.at("balancer_auto").at("reason").get<std::string>(),
              ::testing::HasSubstr("shadow catcher"));
  EXPECT_THAT(doc.at("balancer").get<std::string>(), ::testing::StartsWith("hybrid:bands=8:"));
}

TEST(AutoBalancerCli, AutoTakesNoOptionsAndViewsMappingNamesTheChoice) {
  const Result opts =
      run("render --res 32x16 --spp 1 --balancer auto:bands=4 -q --out " + fresh_dir("auto_opts"));
  EXPECT_NE(opts.code, 0);
  EXPECT_THAT(opts.out, ::testing::HasSubstr("--balancer"));
  EXPECT_THAT(opts.out, ::testing::HasSubstr("bands"));
  const Result views =
      run("render --res 32x16 --spp 1 --views 2x1 --devices cpu:threads=1,cpu:threads=1 "
          "--mapping views -q --out " +
          fresh_dir("auto_views"));
  EXPECT_NE(views.code, 0);
  EXPECT_THAT(views.out, ::testing::HasSubstr("not 'hybrid' (the choice of --balancer auto"));
}

TEST(AutoBalancerCli, BenchResolvesAutoLikeRender) {
  const std::string json = ::testing::TempDir() + "/auto_bench.json";
  const Result r =
      run("bench --res 24x16 --spp 1 --devices cpu:threads=1,cpu:threads=1 --frames 2 --repeats 1 "
          "--balancers uniform,auto --json " +
          json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out,
              ::testing::HasSubstr("multiray: --balancers auto: hybrid:bands=1 (2 devices"));
  const auto doc = nlohmann::json::parse(std::ifstream(json));
  ASSERT_EQ(doc.at("runs").size(), 2u);
  EXPECT_EQ(doc.at("runs")[1].at("lane"), "auto");
  EXPECT_THAT(doc.at("runs")[1].at("balancer").get<std::string>(),
              ::testing::StartsWith("hybrid:"));
}

}  // namespace auto_balancer_cli_test
