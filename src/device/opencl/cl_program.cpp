#include "device/opencl/cl_program.h"

#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/error.h"

namespace multiray::cl_util {

namespace {

// FNV-1a, 64 bit: a stable, dependency-free hash for cache keys (not for security).
uint64_t fnv1a(const std::string& text, uint64_t h = 0xcbf29ce484222325ull) {
  for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

std::string cache_key(const cl::Device& device, const std::string& source,
                      const std::string& options) {
  const cl::Platform platform(device.getInfo<CL_DEVICE_PLATFORM>());
  const std::string parts[] = {source,
                               options,
                               device.getInfo<CL_DEVICE_NAME>(),
                               device.getInfo<CL_DEVICE_VERSION>(),
                               device.getInfo<CL_DRIVER_VERSION>(),
                               platform.getInfo<CL_PLATFORM_NAME>(),
                               platform.getInfo<CL_PLATFORM_VERSION>()};
  uint64_t h = 0xcbf29ce484222325ull;
  for (const std::string& p : parts) h = fnv1a(p + '\0', h);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

// The first `max_lines` lines of a compiler log, for an error message.
std::string log_head(const std::string& log, int max_lines) {
  std::istringstream in(log);
  std::string line, out;
  int n = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (n++ == max_lines) {
      out += "\n  ...";
      break;
    }
    out += "\n  " + line.substr(0, 240);
  }
  return out.empty() ? " (the compiler wrote no log)" : out;
}

std::vector<unsigned char> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Writes atomically (temporary file + rename), so concurrent runs never read half a file.
// Failures are ignored: the cache is an optimisation.
void write_file(const std::string& path, const std::vector<unsigned char>& data) {
  static std::atomic<int> counter{0};
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  const std::string tmp =
      path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
    if (!out) {
      std::filesystem::remove(tmp, ec);
      return;
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) std::filesystem::remove(tmp, ec);
}

}  // namespace

std::string program_cache_dir() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && xdg[0] == '/') return std::string(xdg) + "/multiray";
  const char* home = std::getenv("HOME");
  if (home && home[0] == '/') return std::string(home) + "/.cache/multiray";
  return "";
}

BuiltProgram build_program(const cl::Context& context, const cl::Device& device,
                           const std::string& source, const std::string& options) {
  BuiltProgram out;
  const std::string dir = program_cache_dir();
  if (!dir.empty())
    out.cache_file = dir + "/opencl-" + cache_key(device, source, options) + ".bin";

  if (!out.cache_file.empty()) {
    const std::vector<unsigned char> binary = read_file(out.cache_file);
    if (!binary.empty()) {
      try {
        cl::Program program(context, {device}, cl::Program::Binaries{binary});
        program.build(device, options.c_str());
        out.program = program;
        out.from_cache = true;
        return out;
      } catch (const cl::Error&) {
        // A stale or foreign binary: fall through and rebuild from source.
      }
    }
  }

  cl::Program program(context, source);
  try {
    program.build(device, options.c_str());
  } catch (const cl::Error& e) {
    std::string log;
    try {
      log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
    } catch (const cl::Error&) {
    }
    throw DeviceError("OpenCL kernel build failed on '" + device.getInfo<CL_DEVICE_NAME>() +
                      "' (" + describe(e) + "):" + log_head(log, 12));
  }
  out.program = program;
  if (!out.cache_file.empty()) {
    try {
      const auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
      if (binaries.size() == 1 && !binaries[0].empty()) write_file(out.cache_file, binaries[0]);
    } catch (const cl::Error&) {
      // Some drivers cannot return binaries; then only their own cache helps.
    }
  }
  return out;
}

}  // namespace multiray::cl_util
