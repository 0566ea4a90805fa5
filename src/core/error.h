// Errors that reach the user. Every message is one line that names the thing at fault
// (file, option, value) so the CLI can print it as is and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace multiray {

// Bad input: files, options, scene contents. The CLI maps it to exit code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A device or backend failed at run time (lost device, out of memory). Exit code 3.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace multiray
