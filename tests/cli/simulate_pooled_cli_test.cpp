// `multiray simulate --calibration pooled|leave-one-out`: the simulator calibrated on the
// traces of one run together (balance/trace_calibration.h, calibrate_pooled), and each
// trace predicted by a calibration without it; traces of other devices refused in one line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli_expect.h"

namespace simulate_pooled_cli_test {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

void expect_input_error(const std::string& args, const std::string& word) {
  multiray::testing::expect_input_error(run(args), args, word);
}

TEST(CliSimulatePooled, CalibratesOnEveryTraceAndLeavesEachOut) {
  const std::string dir = ::testing::TempDir() + "/cli_simpool";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto record = [&](const std::string& balancer, const std::string& devices) {
    const std::string name = balancer + (devices == "cpu,cpu" ? "" : "-other");
    const std::string trace = dir + "/" + name + ".trace";
    EXPECT_EQ(
        run("render -q --res 32x24 --spp 1 --frames 4 --devices " + devices + " --balancer " +
            balancer + " --trace " + trace + " --out " + dir + "/out-" + name)
            .code,
        0);
    return trace;
  };
  const std::string hybrid = record("hybrid", "cpu,cpu"), queue = record("queue", "cpu,cpu"),
                    uniform = record("uniform", "cpu,cpu");
  const std::string all = queue + "," + uniform + "," + hybrid;
  const Result pooled = run("simulate " + hybrid + " --predict " + all +
                            " --calibration pooled --warmup 1 --json " + dir + "/pooled.json");
  ASSERT_EQ(pooled.code, 0) << pooled.out;
  EXPECT_THAT(pooled.out, ::testing::HasSubstr("calibration pooled on 3 traces"));
  EXPECT_THAT(pooled.out, ::testing::HasSubstr("take cost ms"));
  EXPECT_THAT(pooled.out, ::testing::HasSubstr("\nqueue"));
  const auto doc = nlohmann::json::parse(std::ifstream(dir + "/pooled.json"));
  EXPECT_EQ(doc.at("calibration_mode"), "pooled");
  EXPECT_EQ(doc.at("calibrated_on").size(), 3u);  // TRACE named again in --predict: once
  EXPECT_EQ(doc.at("calibration").at("traces"), 3);
  EXPECT_EQ(doc.at("rows").size(), 3u);

  const Result loo = run("simulate " + hybrid + " --predict " + all +
                         " --calibration leave-one-out --warmup 1 --json " + dir + "/loo.json");
  ASSERT_EQ(loo.code, 0) << loo.out;
  const auto rows = nlohmann::json::parse(std::ifstream(dir + "/loo.json")).at("rows");
  ASSERT_EQ(rows.size(), 3u);
  const std::vector<std::string> predicted{queue, uniform, hybrid};
  for (size_t k = 0; k < rows.size(); ++k) {
    // Each row's calibration is of the other two traces, never of the one it predicts.
    const auto on = rows[k].at("calibrated_on").get<std::vector<std::string>>();
    EXPECT_EQ(on.size(), 2u) << k;
    EXPECT_EQ(std::count(on.begin(), on.end(), predicted[k]), 0) << k;
    EXPECT_TRUE(rows[k].contains("calibration")) << k;
    EXPECT_TRUE(rows[k].contains("mean_abs_error")) << k;
  }

  // Traces of other devices (an emulated speed), sizes or frame counts: one line, exit 2.
  const std::string other = record("queue", "cpu,cpu:speed=0.5");
  expect_input_error(
      "simulate " + hybrid + " --predict " + queue + "," + other + " --calibration pooled",
      "has device 1");
  expect_input_error("simulate " + hybrid + " --predict " + other + " --calibration leave-one-out",
                     other);
  expect_input_error("simulate " + hybrid + " --calibration pooled", "--predict");
  expect_input_error("simulate " + hybrid + " --predict " + queue + " --calibration sideways",
                     "--calibration");
  expect_input_error(
      "simulate " + hybrid + " --predict " + hybrid + " --calibration leave-one-out", "besides");
  expect_input_error("simulate " + hybrid + " --predict " + queue +
                         " --calibration leave-one-out --balancers uniform",
                     "--balancers");
}

}  // namespace simulate_pooled_cli_test
