// Turning `--devices` strings into devices.
//
// Grammar: DEVICE[,DEVICE...] where DEVICE is TYPE[:KEY=VALUE...], a Spec (see
// balance/spec.h) whose options are checked as below when the list is parsed.
//   cpu:threads=N:cores=LIST:speed=S:quota=Q:tile=T:compact=B:mem=SIZE:fail_after=K
//     threads  worker threads (default 1)
//     cores    cores to pin to: "0", "0+2", "0-3" (default: not pinned)
//     speed    emulated speed in [0.01, 1]: idles after each item (default 1)
//     fail_after  testing aid: the device fails when it pulls an item after K items
//     quota    real throttle: fraction of a core per thread via cgroup v1 (default none)
//     tile     pixel block size handed to threads (default 16)
//     compact  1: trace the compact scene (quantized mesh and tree, render/compact_scene.h)
//     mem      emulated memory limit, e.g. 512M or 2G: a scene that does not fit the
//              chosen representation is refused (device/scene_memory.h)
//   opencl[:N]:speed=S:tile=T:wg=W:batch=B:cores=LIST:compact=B:mem=SIZE:fail_after=K
//     N        (or index=N) global OpenCL device index over all platforms, as
//              `multiray devices` lists them (default 0)
//     speed    emulated speed in (0, 1], as for cpu
//     tile     side of the largest square one kernel launch renders (default 256)
//     wg       work-group size (default 64, clamped to the kernel's maximum)
//     batch    items taken together and rendered in one launch, 1..64 (default 16; 1:
//              one launch per item)
//     cores    pin the thread that drives the device (with PoCL's `basic` driver the
//              kernels run on that thread)
//     compact, mem  as for cpu
//     fail_after  testing aid: the device fails when it pulls a unit after K units
//   Each OpenCL device runs on its own context. With PoCL, POCL_DEVICES="basic basic" gives
//   two independent one-core devices (opencl:0, opencl:1); its default `pthread` device uses
//   POCL_MAX_PTHREAD_COUNT threads shared by every context on it.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "device/device.h"
#include "render/scene_cache.h"
#include "util/spec.h"

namespace multiray {

// A device backend as `--devices` names it: the registry every list of backends, their
// keys and their capabilities comes from (the --devices help, `multiray devices`, the
// factory and the contract tests in tests/engine/device_registry_test.cpp).
struct BackendParam {
  std::string key;
  std::string values;    // what it accepts, for help: "1..1024", "[0.01, 1]", "0+2, 0-3"
  std::string fallback;  // its value when absent, for help ("" when there is none)
  std::string help;
};
struct BackendEntry {
  std::string name, help;
  std::vector<BackendParam> params;  // every key the backend accepts, nothing else
  DeviceCapabilities (*capabilities)() = nullptr;
  // Reads and range-checks every option of `spec` (named as a --devices entry); throws
  // std::invalid_argument "--devices '<device>': <what>".
  void (*check)(Spec& spec) = nullptr;
  // Makes the device (check() passed); throws InputError or DeviceError.
  std::unique_ptr<Device> (*create)(Spec& spec, SceneCache& scenes) = nullptr;
};
// The backends this multiray was built with, in the order `multiray devices` lists them.
const std::vector<BackendEntry>& device_backends();
// The entry named `name`, or nullptr.
const BackendEntry* find_backend(const std::string& name);

// One checked device of a `--devices` list. create_device() reads `text`; `type` and
// `options` (the bare `opencl:N` under "index") show what it says.
struct DeviceSpec {
  std::string type;
  std::map<std::string, std::string> options;
  std::string text;  // the original text of this device
};

// Parses and checks every option's value, so that a bad list fails before a scene is
// loaded. Throws InputError with a one-line message "--devices '<device>': <what>" (also
// for `opencl` when multiray was built without OpenCL).
std::vector<DeviceSpec> parse_device_specs(const std::string& text);

// What devices of backend `type` ("cpu", "opencl") can run, known before any is created
// (so the CLI refuses an impossible job before loading the scene); empty for a backend
// this multiray was built without.
DeviceCapabilities backend_capabilities(const std::string& type);

// Creates one device on the scene representations of `scenes` (each backend asks for the
// one it renders; `scenes` must outlive the device). Throws InputError (bad option) or
// DeviceError (cannot be created here).
std::unique_ptr<Device> create_device(const DeviceSpec& spec, SceneCache& scenes);

std::vector<std::unique_ptr<Device>> create_devices(const std::string& text, SceneCache& scenes);

}  // namespace multiray
