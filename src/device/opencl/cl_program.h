// Building OpenCL programs once and keeping the binaries on disk between runs.
//
// The cache lives in $XDG_CACHE_HOME/multiray, else ~/.cache/multiray (no cache when
// neither is set or the folder cannot be written). A binary's file name is a hash of
// everything that could change the compiled code: source, build options, device name and
// version, driver version and platform version. A cached binary that the driver rejects is
// ignored and rebuilt from source. (PoCL also keeps its own cache in POCL_CACHE_DIR; this
// one works for every vendor.)
#pragma once

#include <string>

#include "device/opencl/cl_common.h"

namespace multiray::cl_util {

struct BuiltProgram {
  cl::Program program;
  bool from_cache = false;  // loaded from a binary in the disk cache
  std::string cache_file;   // where the binary is (or would be) cached; empty: no cache
};

// Builds `source` for `device` with `options`. Throws DeviceError on a compile error,
// with the device name and the first lines of the compiler's log.
BuiltProgram build_program(const cl::Context& context, const cl::Device& device,
                           const std::string& source, const std::string& options);

// The cache folder in use, or "" when there is none.
std::string program_cache_dir();

}  // namespace multiray::cl_util
