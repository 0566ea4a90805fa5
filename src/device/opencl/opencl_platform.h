// What OpenCL offers on this machine, for `multiray devices` and for error messages. No
// OpenCL types here, so the CLI can include it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace multiray {

struct OpenClDeviceListing {
  int index = 0;     // N in the spec `opencl:N`
  std::string name;  // CL_DEVICE_NAME
  std::string kind;  // "cpu", "gpu", "accelerator" or "other"
  std::string platform;
  std::string driver;  // CL_DRIVER_VERSION
  unsigned compute_units = 0;
  uint64_t memory_bytes = 0;  // CL_DEVICE_GLOBAL_MEM_SIZE
};

// Every OpenCL device, in spec-index order. Empty when there is no platform; never throws.
std::vector<OpenClDeviceListing> list_opencl_devices();

}  // namespace multiray
