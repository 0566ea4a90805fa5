// `--devices auto` (run/catalog.h): every core as one cpu device, each GPU or accelerator
// added, and the OpenCL devices that compute on the host's cores named and left out.
#include "run/catalog.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace multiray {
namespace {

OfferedDevice offered(const std::string& type, const std::string& name, const std::string& spec,
                      bool host_cores) {
  OfferedDevice d;
  d.type = type, d.name = name, d.spec = spec, d.host_cores = host_cores;
  return d;
}

TEST(AutoDevices, CoresAreOneDeviceAndGpusJoinIt) {
  const std::vector<OfferedDevice> machine = {
      offered("cpu", "all cores", "cpu:threads=8", true),
      offered("cpu", "core 0", "cpu:threads=1:cores=0", true),
      offered("opencl", "NVIDIA RTX (gpu)", "opencl:0", false),
      offered("opencl", "pthread (cpu)", "opencl:1", true),
      offered("opencl", "Arc (gpu)", "opencl:2", false)};
  const AutoDevices a = auto_devices(machine);
  EXPECT_EQ(a.devices, "cpu:threads=0,opencl:0,opencl:2");
  EXPECT_THAT(a.note, ::testing::HasSubstr("not using opencl:1 (pthread (cpu))"));
  EXPECT_THAT(a.note, ::testing::HasSubstr("--devices cpu,opencl:1"));
}

TEST(AutoDevices, ACpuOnlyMachineSaysNothing) {
  const AutoDevices a = auto_devices({offered("cpu", "all cores", "cpu:threads=2", true)});
  EXPECT_EQ(a.devices, "cpu:threads=0");
  EXPECT_EQ(a.note, "");
}

}  // namespace
}  // namespace multiray
