// A toy device backend, registered only inside the test binary: it renders through the CPU
// kernels on the calling thread, in batches of up to 4 items, through the one device loop
// (device/device_loop.h). It proves that a backend is one folder plus one registry entry:
// once register_toy_backend() has run, `multiray devices`, the help text and
// `--balancer auto` know it, with no other edit.
#pragma once

namespace multiray::testing {

// Adds the "toy" backend to the registry (device_backends()); idempotent.
void register_toy_backend();

}  // namespace multiray::testing
