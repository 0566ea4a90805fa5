#include "device/device_factory.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "device/cpu/cpu_device.h"
#include "device/scene_memory.h"
#include "util/parse.h"
#include "util/spec.h"
#ifdef MULTIRAY_HAS_OPENCL
#include "device/opencl/opencl_device.h"
#endif

namespace multiray {

namespace {

// Runs `f`, turning the std::invalid_argument of a bad spec (whose message already starts
// "--devices '<device>': ") into the InputError the CLI reports.
template <class F>
auto as_input_error(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
}

std::vector<std::string> param_keys(const BackendEntry& b) {
  std::vector<std::string> keys;
  for (const BackendParam& p : b.params) keys.push_back(p.key);
  return keys;
}

// One device of a `--devices` list, with a known type that this multiray can run and no
// key its backend does not take.
Spec device_spec(const std::string& item) {
  SpecSyntax syntax;
  syntax.label = "--devices";
  syntax.positional_key = "index";  // opencl:N
  Spec spec(item, syntax);
  if (!find_backend(spec.name())) {
#ifndef MULTIRAY_HAS_OPENCL
    if (spec.name() == "opencl")
      spec.fail(
          "this multiray was built without OpenCL (install ocl-icd-opencl-dev, "
          "opencl-clhpp-headers and configure with -DMULTIRAY_WITH_OPENCL=ON)");
#endif
    std::vector<std::string> known;
    for (const BackendEntry& b : device_backends()) known.push_back(b.name);
    spec.fail("unknown device type '" + spec.name() + "' (known: " + join(known) + ")");
  }
  spec.accept_only(param_keys(*find_backend(spec.name())));
  return spec;
}

// compact=1 (the compact scene representation) and mem=SIZE (an emulated memory limit).
void read_memory_options(Spec& spec, bool& compact, uint64_t& limit) {
  compact = spec.get_bool("compact", compact);
  if (!spec.has("mem")) return;
  const std::string text = spec.get_string("mem", "", {});
  try {
    limit = parse_memory_size(text);
  } catch (const std::invalid_argument& e) {
    spec.fail(e.what());
  }
}

// A core id: decimal digits only, below 100000 (so "-1", "1.5" and "0x2" are no ids).
int core_id(const std::string& s) {
  if (s.empty() || s.size() > 5 ||
      !std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); }))
    return -1;
  return std::stoi(s);
}

// "0", "0+2", "0-3", "0-1+4"; empty when `cores` is absent.
std::vector<int> read_cores(Spec& spec) {
  const std::string list = spec.get_string("cores", "", {});
  if (!spec.has("cores")) return {};
  std::vector<int> cores;
  size_t start = 0;
  for (;;) {
    const size_t plus = list.find('+', start);
    const std::string part = list.substr(start, plus - start);
    const size_t dash = part.find('-');
    const int a = core_id(part.substr(0, dash));
    const int b = dash == std::string::npos ? a : core_id(part.substr(dash + 1));
    if (a < 0 || b < a || b - a > 4096)
      spec.fail("cores=" + list + " is not a core list like 0, 0+2 or 0-3");
    for (int c = a; c <= b; ++c) cores.push_back(c);
    if (plus == std::string::npos) return cores;
    start = plus + 1;
  }
}

CpuDeviceOptions read_cpu_options(Spec& spec) {
  CpuDeviceOptions o;
  o.threads = spec.get_int("threads", o.threads, 1, 1024);
  o.cores = read_cores(spec);
  o.speed = spec.get_double("speed", o.speed, kMinEmulatedSpeed, 1.0);  // emulated
  o.quota = spec.get_positive("quota", o.quota, 1.0);                   // of a core per thread
  o.tile = spec.get_int("tile", o.tile, 1, 4096);
  o.fail_after = spec.get_int("fail_after", o.fail_after, 0, std::numeric_limits<int>::max());
  read_memory_options(spec, o.compact, o.memory_limit);
  spec.finish();
  return o;
}

#ifdef MULTIRAY_HAS_OPENCL
OpenClDeviceOptions read_opencl_options(Spec& spec) {
  OpenClDeviceOptions o;
  o.index = spec.get_int("index", o.index, 0, 65535);
  o.speed = spec.get_double("speed", o.speed, kMinEmulatedSpeed, 1.0);  // emulated
  o.tile = spec.get_int("tile", o.tile, 1, 4096);
  o.work_group = spec.get_int("wg", o.work_group, 1, 4096);
  o.batch = spec.get_int("batch", o.batch, 1, 64);  // MR_BATCH_MAX (kernels/batch_rects.h)
  o.cores = read_cores(spec);
  o.fail_after = spec.get_int("fail_after", o.fail_after, 0, std::numeric_limits<int>::max());
  read_memory_options(spec, o.compact, o.memory_limit);
  o.work_group_given = spec.has("wg");  // a wg= asked for is noted when fitted
  spec.finish();
  return o;
}
#endif

// Keys both backends take.
const BackendParam kSpeed{"speed", "[0.01, 1]", "1",
                          "emulated speed: the device idles after each item (always labelled "
                          "emulated)"};
const BackendParam kCores{"cores", "0, 0+2, 0-3", "", "cores to pin to"};
const BackendParam kCompact{"compact", "0 or 1", "0",
                            "trace the compact scene (quantized mesh and tree)"};
const BackendParam kMem{"mem", "1M..1024T", "",
                        "emulated memory limit (512M, 2G): a scene that does not fit the "
                        "representation is refused"};
const BackendParam kFailAfter{"fail_after", "0..2^31-1", "0",
                              "testing aid: the device fails after this many items (0: never)"};

std::vector<BackendEntry> make_backends() {
  std::vector<BackendEntry> b;
  b.push_back({"cpu",
               "CPU cores through oneTBB and Embree",
               {{"threads", "1..1024", "1", "worker threads (--devices cpu:threads=0: all)"},
                kCores,
                kSpeed,
                {"quota", "(0, 1]", "", "real throttle: a fraction of a core per thread (cgroup)"},
                {"tile", "1..4096", "16", "pixel block handed to a thread"},
                kFailAfter,
                kCompact,
                kMem},
               &CpuDevice::capabilities,
               [](Spec& spec) { read_cpu_options(spec); },
               [](Spec& spec, SceneCache& scenes) -> std::unique_ptr<Device> {
                 return std::make_unique<CpuDevice>(scenes, read_cpu_options(spec), spec.text());
               }});
#ifdef MULTIRAY_HAS_OPENCL
  b.push_back({"opencl",
               "an OpenCL device, opencl:N as `multiray devices` lists it",
               {{"index", "0..65535", "0", "the device (also written opencl:N)"},
                kSpeed,
                {"tile", "1..4096", "256", "side of the largest square one launch renders"},
                {"wg", "1..4096", "64",
                 "work-group size (fitted to each kernel's maximum; a larger one is noted)"},
                {"batch", "1..64", "16",
                 "items taken together and rendered in one launch (1: one launch per item)"},
                {"cores", "0, 0+2, 0-3", "", "cores to pin the thread driving the device to"},
                kFailAfter,
                kCompact,
                kMem},
               &OpenClDevice::capabilities,
               [](Spec& spec) { read_opencl_options(spec); },
               [](Spec& spec, SceneCache& scenes) -> std::unique_ptr<Device> {
                 const OpenClDeviceOptions o = read_opencl_options(spec);
                 try {
                   return std::make_unique<OpenClDevice>(scenes, o, spec.text());
                 } catch (const InputError& e) {
                   throw InputError("--devices '" + spec.text() + "': " + e.what());
                 }
               }});
#endif
  return b;
}

}  // namespace

const std::vector<BackendEntry>& device_backends() {
  static const std::vector<BackendEntry> backends = make_backends();
  return backends;
}

const BackendEntry* find_backend(const std::string& name) {
  for (const BackendEntry& b : device_backends())
    if (b.name == name) return &b;
  return nullptr;
}

std::vector<DeviceSpec> parse_device_specs(const std::string& text) {
  if (text.empty()) throw InputError("--devices is empty; try --devices cpu");
  std::vector<DeviceSpec> specs;
  for (const std::string& item : split_spec_list(text)) {
    if (item.empty())
      throw InputError("--devices '" + text + "': a device is empty (stray comma?)");
    specs.push_back(as_input_error([&] {
      Spec spec = device_spec(item);
      find_backend(spec.name())->check(spec);
      return DeviceSpec{spec.name(), spec.options(), item};
    }));
  }
  if (specs.size() > 64) throw InputError("--devices: at most 64 devices are supported");
  return specs;
}

DeviceCapabilities backend_capabilities(const std::string& type) {
  const BackendEntry* b = find_backend(type);
  return b ? b->capabilities() : DeviceCapabilities{};
}

std::unique_ptr<Device> create_device(const DeviceSpec& d, SceneCache& scenes) {
  Spec spec = as_input_error([&] { return device_spec(d.text); });
  const BackendEntry& backend = *find_backend(spec.name());
  // Options are read again by the factory (a fresh Spec: each getter marks its key).
  return as_input_error([&] { return backend.create(spec, scenes); });
}

std::vector<std::unique_ptr<Device>> create_devices(const std::string& text, SceneCache& scenes) {
  std::vector<std::unique_ptr<Device>> out;
  for (const DeviceSpec& d : parse_device_specs(text)) out.push_back(create_device(d, scenes));
  return out;
}

}  // namespace multiray
