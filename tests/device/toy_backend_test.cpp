// A backend is one folder plus one registry entry: the toy backend (toy_backend.h),
// registered inside this test binary only, appears in `multiray devices`, in --help and in
// `--balancer auto`'s choice, and renders a frame through the CLI, with no other edit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/cli.h"
#include "device/toy_backend.h"

namespace multiray {
namespace toy_backend_test {

using ::testing::HasSubstr;

struct Ran {
  int code = 0;
  std::string out;  // stdout, then stderr
};

// The multiray command line, in this process (where the toy backend is registered).
Ran cli(std::vector<std::string> args) {
  testing::register_toy_backend();
  args.insert(args.begin(), "multiray");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  Ran r;
  r.code = app::run_cli(int(argv.size()), argv.data());
  r.out = ::testing::internal::GetCapturedStdout();
  r.out += ::testing::internal::GetCapturedStderr();
  return r;
}

TEST(ToyBackend, AppearsInTheDevicesListing) {
  const Ran r = cli({"devices"});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("the calling thread"));                        // its offered device
  EXPECT_THAT(r.out, HasSubstr("  toy     kernels: path"));                   // its capabilities
  EXPECT_THAT(r.out, HasSubstr("  toy: a test backend"));                     // its keys
  EXPECT_THAT(r.out, HasSubstr("The toy backend exists only in the tests"));  // its notes
}

TEST(ToyBackend, AppearsInTheHelp) {
  const Ran r = cli({"render", "--help-all"});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("toy (a test backend"));  // --devices
  EXPECT_THAT(r.out, HasSubstr("toy runs path"));        // --integrator
}

// auto sees the toy's feature (a fixed cost per item), as it would a GPU backend's, and
// the toy renders its share of the frame through the one device loop.
TEST(ToyBackend, AutoWeighsItsFeaturesAndItRendersThroughTheCli) {
  const std::string dir = ::testing::TempDir() + "/toy_backend_auto";
  std::filesystem::remove_all(dir);
  std::filesystem::remove_all(dir + "_cpu");
  const Ran r = cli({"render", "--res", "32x16", "--spp", "1", "--devices", "cpu,cpu,cpu,cpu,toy",
                     "--balancer", "auto", "--out", dir});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_THAT(r.out, HasSubstr("5 devices (cpu + toy)"));
  EXPECT_THAT(r.out, HasSubstr("a device pays a fixed cost per item"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/stats.json"));
  // Without it, five CPU devices fall to the last row.
  const Ran cpus = cli({"render", "--res", "32x16", "--spp", "1", "--devices",
                        "cpu,cpu,cpu,cpu,cpu", "--balancer", "auto", "--out", dir + "_cpu"});
  ASSERT_EQ(cpus.code, 0) << cpus.out;
  EXPECT_THAT(cpus.out, ::testing::Not(HasSubstr("fixed cost per item")));
}

TEST(ToyBackend, ItsKeysAreCheckedAndItsCapabilitiesRefuseFoveation) {
  EXPECT_EQ(cli({"render", "--res", "32x16", "--devices", "toy:threads=2"}).code, 2);
  const Ran r = cli({"render", "--res", "32x16", "--devices", "toy", "--sampling", "foveated"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_THAT(r.out, HasSubstr("cannot do foveated sampling"));
}

}  // namespace toy_backend_test
}  // namespace multiray
