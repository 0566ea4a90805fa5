#include "device/backends.h"

namespace multiray {

std::vector<BackendEntry> builtin_backends() { return {cpu_backend(), opencl_backend()}; }

}  // namespace multiray
