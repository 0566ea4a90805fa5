#include "device/device_factory.h"

#include <cmath>
#include <set>

#include "core/error.h"
#include "device/cpu/cpu_device.h"

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
  if (x != std::floor(x)) throw InputError("--devices '" + d.text + "': " + key + " must be an integer");
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

}  // namespace

std::vector<DeviceSpec> parse_device_specs(const std::string& text) {
  if (text.empty()) throw InputError("--devices is empty; try --devices cpu");
  std::vector<DeviceSpec> specs;
  for (const std::string& item : split(text, ',')) {
    DeviceSpec d;
    d.text = item;
    const auto parts = split(item, ':');
    d.type = parts[0];
    if (d.type != "cpu")
      throw InputError("--devices: unknown device type '" + d.type + "' in '" + item +
                       "' (known: cpu)");
    for (size_t i = 1; i < parts.size(); ++i) {
      const auto eq = parts[i].find('=');
      if (eq == std::string::npos || eq == 0)
        throw InputError("--devices '" + item + "': expected KEY=VALUE, got '" + parts[i] + "'");
      const std::string key = parts[i].substr(0, eq);
      static const std::set<std::string> known{"threads", "cores", "speed", "quota", "tile"};
      if (!known.count(key))
        throw InputError("--devices '" + item + "': unknown option '" + key +
                         "' (known: threads, cores, speed, quota, tile)");
      if (!d.options.emplace(key, parts[i].substr(eq + 1)).second)
        throw InputError("--devices '" + item + "': option '" + key + "' given twice");
    }
    specs.push_back(std::move(d));
  }
  if (specs.size() > 64) throw InputError("--devices: at most 64 devices are supported");
  return specs;
}

std::unique_ptr<Device> create_device(const DeviceSpec& d, const RenderScene& rs) {
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
  if (o.tile < 1 || o.tile > 4096) throw InputError("--devices '" + d.text + "': tile must be in 1..4096");
  return std::make_unique<CpuDevice>(rs, o, d.text);
}

std::vector<std::unique_ptr<Device>> create_devices(const std::string& text, const RenderScene& rs) {
  std::vector<std::unique_ptr<Device>> out;
  for (const DeviceSpec& d : parse_device_specs(text)) out.push_back(create_device(d, rs));
  return out;
}

}  // namespace multiray
