// What a run can be made of, as data for the command line's help and `multiray devices`:
// the kernels, the transfer-function presets, the devices this machine offers and what
// each backend runs, and the memory a scene takes in each device's representation. The
// lists come from the registries (render/kernel.h, device/device_factory.h), so the help
// text cannot go stale.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "device/device_factory.h"

namespace multiray {

struct Choice {
  std::string name, help;
};

// The kernels --integrator takes, each with its one-line help.
std::vector<Choice> kernel_choices();
// The device backends --devices takes (device/device_factory.h's registry), with their keys.
const std::vector<BackendEntry>& device_backend_choices();
// One line per backend for help: "cpu: CPU cores ...; keys: threads (1..1024, default 1), ...",
// with the entry's notes.
std::string device_keys_help();
// For --integrator's help: "cpu runs path, ao, ...; opencl runs path, volume" (built backends).
std::string kernels_by_backend_help();
// The built backends whose devices render the shadow catcher (--ground), e.g. "cpu".
std::string shadow_catcher_backends();
// The transfer-function presets --tf takes.
std::vector<std::string> transfer_presets();
// Whether this build compresses workers' results with zstd (distributed/pixel_codec.h,
// MULTIRAY_WITH_ZSTD): without it --result-encoding's zstd forms are refused, and its
// default is float.
bool zstd_results_available();

// The backends of the registry, built or not, and the devices this machine offers, as
// `multiray devices` lists them: every line comes from the registry
// (device/device_factory.h), so a new backend appears with no edit here.
struct OfferedBackend {
  std::string name, help;
  bool built = true;
  std::string not_built;  // how to build it, when !built
  DeviceCapabilities caps;
  std::string notes;       // the entry's further help ("" when none)
  std::string none_found;  // said when built but no device was found ("" when found)
};
struct Offer {
  std::vector<OfferedDevice> devices;
  std::vector<OfferedBackend> backends;
};
Offer offered_devices();

// `--devices auto` (the default): every core as one cpu device, and each offered device
// that does not compute on the host's cores (a GPU, an accelerator). Devices that do (an
// OpenCL CPU device: PoCL, llvmpipe) would only contend with the cpu device for its
// cores; `note` names them and how to add them anyway ("" when there are none).
struct AutoDevices {
  std::string devices;  // a --devices text
  std::string note;
};
AutoDevices auto_devices(const std::vector<OfferedDevice>& offered);

// The memory `devices` (a --devices text) take on the scene at `scene_path` (empty: the
// Cornell box): the scene's full-precision and compact sizes by part, and each device's
// representation, size and emulated limit. Builds the devices; throws InputError.
struct SceneMemory {
  std::string scene_name;
  size_t triangles = 0, vertices = 0;
  bool has_triangles = false;
  uint64_t full_mesh = 0, full_structure = 0, compact_mesh = 0, compact_structure = 0;
  std::vector<DeviceInfo> devices;
};
// Loads `scene_path` (empty: the Cornell box) within `max_memory` bytes (estimated from
// the file before loading, images charged from their headers, assimp's formats tried in a
// child first: run/run.h memory_guarded_load) and builds `devices` on it. InputError when
// it would pass the limit.
SceneMemory scene_memory(const std::string& scene_path, const std::string& devices,
                         double max_memory);

}  // namespace multiray
