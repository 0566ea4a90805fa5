// `multiray bench` run as a user would: a bad --balancers entry is named as such.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "support/cli_expect.h"

namespace {

using Result = multiray::testing::CliResult;

Result run(const std::string& args) { return multiray::testing::run_cli(MULTIRAY_BIN, args); }

constexpr const char* kSmall = "bench --res 24x16 --spp 1 --devices cpu:threads=1,cpu:threads=1 ";

TEST(BenchCli, BadBalancersEntryIsNamedAsSuch) {
  for (const std::string mapping : {"", "--mapping strips "}) {
    const std::string args = std::string(kSmall) + "--frames 2 --warmup 0 " + mapping +
                             "--balancers uniform,dlb:interval";
    const Result r = run(args);
    multiray::testing::expect_input_error(r, args, "--balancers: ");
    EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("--balancer:"))) << args;
  }
}

}  // namespace
