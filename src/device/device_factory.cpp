#include "device/device_factory.h"

#include <cmath>
#include <set>

#include "core/error.h"
#include "device/cpu/cpu_device.h"
#ifdef MULTIRAY_HAS_OPENCL
#include "device/opencl/opencl_device.h"
#endif

namespace multiray {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t pos = s.find(sep, start);
    out.push_back(s.substr(start, pos - start));
    if (pos == std::string::npos) return out;
    start = pos + 1;
  }
}

double parse_number(const DeviceSpec& d, const std::string& key) {
  const std::string& v = d.options.at(key);
  size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (...) {
    used = 0;
  }
  if (used != v.size() || v.empty() || !std::isfinite(x))
    throw InputError("--devices '" + d.text + "': " + key + "=" + v + " is not a number");
  return x;
}

int parse_int(const DeviceSpec& d, const std::string& key) {
  const double x = parse_number(d, key);
  if (x != std::floor(x))
    throw InputError("--devices '" + d.text + "': " + key + " must be an integer");
  return int(x);
}

std::vector<int> parse_cores(const DeviceSpec& d) {
  std::vector<int> cores;
  for (const std::string& part : split(d.options.at("cores"), '+')) {
    const auto dash = part.find('-');
    try {
      size_t used = 0;
      if (dash == std::string::npos) {
        cores.push_back(std::stoi(part, &used));
        if (used != part.size()) throw std::invalid_argument(part);
      } else {
        const int a = std::stoi(part.substr(0, dash)), b = std::stoi(part.substr(dash + 1));
        if (b < a || b - a > 4096) throw std::invalid_argument(part);
        for (int c = a; c <= b; ++c) cores.push_back(c);
      }
    } catch (const std::exception&) {
      throw InputError("--devices '" + d.text + "': cores=" + d.options.at("cores") +
                       " is not a core list like 0, 0+2 or 0-3");
    }
  }
  return cores;
}

const std::set<std::string> kCpuKeys{"threads", "cores", "speed", "quota", "tile"};
const std::set<std::string> kOpenClKeys{"speed", "tile", "wg", "cores", "fail_after"};

}  // namespace

std::vector<DeviceSpec> parse_device_specs(const std::string& text) {
  if (text.empty()) throw InputError("--devices is empty; try --devices cpu");
  std::vector<DeviceSpec> specs;
  for (const std::string& item : split(text, ',')) {
    DeviceSpec d;
    d.text = item;
    const auto parts = split(item, ':');
    d.type = parts[0];
    if (d.type != "cpu" && d.type != "opencl")
      throw InputError("--devices: unknown device type '" + d.type + "' in '" + item +
                       "' (known: cpu, opencl)");
#ifndef MULTIRAY_HAS_OPENCL
    if (d.type == "opencl")
      throw InputError("--devices '" + item +
                       "': this multiray was built without OpenCL (install ocl-icd-opencl-dev, "
                       "opencl-clhpp-headers and configure with -DMULTIRAY_WITH_OPENCL=ON)");
#endif
    size_t first = 1;
    // opencl:N — the device index may be given bare, before the KEY=VALUE options.
    if (d.type == "opencl" && parts.size() > 1 && !parts[1].empty() &&
        parts[1].find('=') == std::string::npos) {
      d.options["index"] = parts[1];
      first = 2;
    }
    for (size_t i = first; i < parts.size(); ++i) {
      const auto eq = parts[i].find('=');
      if (eq == std::string::npos || eq == 0)
        throw InputError("--devices '" + item + "': expected KEY=VALUE, got '" + parts[i] + "'");
      const std::string key = parts[i].substr(0, eq);
      const std::set<std::string>& known = d.type == "cpu" ? kCpuKeys : kOpenClKeys;
      if (!known.count(key)) {
        std::string list;
        for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
        throw InputError("--devices '" + item + "': unknown option '" + key + "' (known: " + list +
                         ")");
      }
      if (!d.options.emplace(key, parts[i].substr(eq + 1)).second)
        throw InputError("--devices '" + item + "': option '" + key + "' given twice");
    }
    specs.push_back(std::move(d));
  }
  if (specs.size() > 64) throw InputError("--devices: at most 64 devices are supported");
  return specs;
}

namespace {

std::unique_ptr<Device> create_cpu_device(const DeviceSpec& d, SceneCache& scenes) {
  CpuDeviceOptions o;
  if (d.options.count("threads")) o.threads = parse_int(d, "threads");
  if (d.options.count("cores")) o.cores = parse_cores(d);
  if (d.options.count("speed")) o.speed = parse_number(d, "speed");
  if (d.options.count("quota")) o.quota = parse_number(d, "quota");
  if (d.options.count("tile")) o.tile = parse_int(d, "tile");
  if (o.threads < 1 || o.threads > 1024)
    throw InputError("--devices '" + d.text + "': threads must be in 1..1024");
  if (!(o.speed > 0 && o.speed <= 1))
    throw InputError("--devices '" + d.text + "': speed must be in (0, 1] (emulated slowdown)");
  if (d.options.count("quota") && !(o.quota > 0 && o.quota <= 1))
    throw InputError("--devices '" + d.text + "': quota must be in (0, 1] of a core per thread");
  if (o.tile < 1 || o.tile > 4096)
    throw InputError("--devices '" + d.text + "': tile must be in 1..4096");
  return std::make_unique<CpuDevice>(scenes, o, d.text);
}

#ifdef MULTIRAY_HAS_OPENCL
std::unique_ptr<Device> create_opencl_device(const DeviceSpec& d, SceneCache& scenes) {
  OpenClDeviceOptions o;
  if (d.options.count("index")) o.index = parse_int(d, "index");
  if (d.options.count("speed")) o.speed = parse_number(d, "speed");
  if (d.options.count("tile")) o.tile = parse_int(d, "tile");
  if (d.options.count("wg")) o.work_group = parse_int(d, "wg");
  if (d.options.count("cores")) o.cores = parse_cores(d);
  if (d.options.count("fail_after")) o.fail_after = parse_int(d, "fail_after");
  if (o.index < 0)
    throw InputError("--devices '" + d.text + "': the OpenCL device index must be >= 0");
  if (!(o.speed > 0 && o.speed <= 1))
    throw InputError("--devices '" + d.text + "': speed must be in (0, 1] (emulated slowdown)");
  if (o.tile < 1 || o.tile > 4096)
    throw InputError("--devices '" + d.text + "': tile must be in 1..4096");
  if (o.work_group < 1 || o.work_group > 4096)
    throw InputError("--devices '" + d.text + "': wg must be in 1..4096");
  if (o.fail_after < 0 && d.options.count("fail_after"))
    throw InputError("--devices '" + d.text + "': fail_after must be >= 0");
  try {
    return std::make_unique<OpenClDevice>(scenes, o, d.text);
  } catch (const InputError& e) {
    throw InputError("--devices '" + d.text + "': " + e.what());
  }
}
#endif

}  // namespace

DeviceCapabilities backend_capabilities(const std::string& type) {
#ifdef MULTIRAY_HAS_OPENCL
  if (type == "opencl") return OpenClDevice::capabilities();
#endif
  if (type == "cpu") return CpuDevice::capabilities();
  return {};
}

std::unique_ptr<Device> create_device(const DeviceSpec& d, SceneCache& scenes) {
#ifdef MULTIRAY_HAS_OPENCL
  if (d.type == "opencl") return create_opencl_device(d, scenes);
#else
  if (d.type == "opencl")
    throw InputError("--devices '" + d.text + "': this multiray was built without OpenCL");
#endif
  return create_cpu_device(d, scenes);
}

std::vector<std::unique_ptr<Device>> create_devices(const std::string& text, SceneCache& scenes) {
  std::vector<std::unique_ptr<Device>> out;
  for (const DeviceSpec& d : parse_device_specs(text)) out.push_back(create_device(d, scenes));
  return out;
}

}  // namespace multiray
