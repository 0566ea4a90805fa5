// The --devices keys that mean the same on every backend, read once: the device loop's
// (`speed`, `fail_after`), pinning (`cores`) and the scene's memory (`compact`, `mem`).
// A backend's registry entry (device_factory.h) lists the ones it takes with these
// BackendParams, so help and checks agree across backends.
#pragma once

#include <cstdint>
#include <vector>

#include "device/device_factory.h"
#include "device/device_loop.h"
#include "util/spec.h"

namespace multiray::backend_options {

// Help rows of the shared keys (functions, not globals: registry entries may be built
// during static initialisation, e.g. by a test's registration).
BackendParam speed_param();
BackendParam cores_param();
BackendParam compact_param();
BackendParam mem_param();
BackendParam fail_after_param();

// speed=S in [kMinEmulatedSpeed, 1] (emulated) and fail_after=K (testing aid).
LoopOptions read_loop_options(Spec& spec);
// compact=1 (the compact scene representation) and mem=SIZE (an emulated memory limit).
void read_memory_options(Spec& spec, bool& compact, uint64_t& limit);
// cores="0", "0+2", "0-3", "0-1+4"; empty when absent. Fails the spec on anything else.
std::vector<int> read_cores(Spec& spec);

}  // namespace multiray::backend_options
