// Turning `--devices` strings into devices.
//
// Grammar: DEVICE[,DEVICE...] where DEVICE is TYPE[:KEY=VALUE...].
//   cpu:threads=N:cores=LIST:speed=S:quota=Q:tile=T
//     threads  worker threads (default 1)
//     cores    cores to pin to: "0", "0+2", "0-3" (default: not pinned)
//     speed    emulated speed in (0, 1]: idles after each unit (default 1)
//     quota    real throttle: fraction of a core per thread via cgroup v1 (default none)
//     tile     pixel block size handed to threads (default 16)
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "device/device.h"

namespace multiray {

struct DeviceSpec {
  std::string type;
  std::map<std::string, std::string> options;
  std::string text;  // the original text of this device
};

// Throws InputError with a one-line message naming the bad part.
std::vector<DeviceSpec> parse_device_specs(const std::string& text);

// Creates one device. Throws InputError (bad option) or DeviceError (cannot be created here).
std::unique_ptr<Device> create_device(const DeviceSpec& spec, const RenderScene& rs);

std::vector<std::unique_ptr<Device>> create_devices(const std::string& text, const RenderScene& rs);

}  // namespace multiray
