// Turning `--devices` strings into devices, through the registry of backends.
//
// Grammar: DEVICE[,DEVICE...] where DEVICE is TYPE[:KEY=VALUE...], a Spec (see
// util/spec.h) whose options are checked when the list is parsed. Each backend's keys,
// ranges and defaults are in its registry entry (cpu/cpu_backend.cpp,
// opencl/opencl_backend.cpp), printed by `multiray devices` and --help, and documented in
// docs/devices.md (checked against the registry). Keys every backend shares (speed,
// fail_after, cores, compact, mem) are read by backend_options.h.
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
// keys, capabilities and features comes from (the --devices help, `multiray devices`, the
// factory, `--balancer auto`'s device features and the contract tests in
// tests/engine/device_registry_test.cpp and tests/device/). Adding a backend is one folder
// under device/ plus one entry: nothing in run/, balance/ or app/ names a backend.
struct BackendParam {
  std::string key;
  std::string values;    // what it accepts, for help: "1..1024", "[0.01, 1]", "0+2, 0-3"
  std::string fallback;  // its value when absent, for help ("" when there is none)
  std::string help;
};

// One device of a backend this machine offers, as `multiray devices` lists it.
struct OfferedDevice {
  std::string type, name;  // "cpu", "all cores (oneTBB + Embree)"
  unsigned units = 0;      // cores or compute units
  uint64_t memory_bytes = 0;
  std::string spec;    // the --devices text that makes it
  std::string driver;  // e.g. OpenCL's "platform NAME, driver VERSION"; empty when none
  // It computes on the host's CPU cores (the cpu backend; an OpenCL CPU device such as
  // PoCL's or llvmpipe's): beside the cpu device it adds no compute, only contention.
  bool host_cores = true;
};

// What the run layer tells `--balancer auto` about a backend's devices (as plain data:
// balance/ knows no backend; see balance::AutoDevice).
struct BackendFeatures {
  // Each batch of items pays a fixed cost (a kernel launch), which hybrid's per-item cost
  // model learns (GPU-style backends).
  bool item_cost = false;
};

struct BackendEntry {
  std::string name, help;
  std::vector<BackendParam> params;  // every key the backend accepts, nothing else
  // False when this multiray was built without the backend: it is still listed (help,
  // `multiray devices`), `not_built` says how to build it, and the functions below are
  // not called.
  bool built = true;
  std::string not_built;
  // Further help for --devices and `multiray devices` (drivers, environment); may be "".
  std::string notes;
  BackendFeatures features;
  DeviceCapabilities (*capabilities)() = nullptr;
  // The devices of this backend the machine offers; an empty list is printed with
  // `none_found` (what to install).
  std::vector<OfferedDevice> (*offer)() = nullptr;
  std::string none_found;
  // Reads and range-checks every option of `spec` (named as a --devices entry); throws
  // std::invalid_argument "--devices '<device>': <what>".
  void (*check)(Spec& spec) = nullptr;
  // Makes the device (check() passed); throws InputError or DeviceError.
  std::unique_ptr<Device> (*create)(Spec& spec, SceneCache& scenes) = nullptr;
};
// Every backend, built or not, in the order `multiray devices` lists them: the built-in
// ones (backends.cpp), then those added by register_backend().
const std::vector<BackendEntry>& device_backends();
// The entry named `name`, or nullptr.
const BackendEntry* find_backend(const std::string& name);
// Adds `entry` to the registry (a backend outside this library: a test's, a plug-in's).
// Replaces an entry of the same name. Not thread-safe: call before devices are listed or
// made, as the registry is read without locks.
void register_backend(BackendEntry entry);

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

// What devices of backend `type` can run, known before any is created (so the CLI refuses
// an impossible job before loading the scene); empty for a backend this multiray was built
// without, or one it does not know.
DeviceCapabilities backend_capabilities(const std::string& type);
// The features of backend `type` (default ones for a type it does not know).
BackendFeatures backend_features(const std::string& type);

// Creates one device on the scene representations of `scenes` (each backend asks for the
// one it renders; `scenes` must outlive the device). Throws InputError (bad option) or
// DeviceError (cannot be created here).
std::unique_ptr<Device> create_device(const DeviceSpec& spec, SceneCache& scenes);

std::vector<std::unique_ptr<Device>> create_devices(const std::string& text, SceneCache& scenes);

}  // namespace multiray
