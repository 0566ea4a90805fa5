#include "device/device_factory.h"

#include <stdexcept>

#include "core/error.h"
#include "device/backends.h"
#include "util/parse.h"
#include "util/spec.h"

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
  const BackendEntry* backend = find_backend(spec.name());
  if (!backend) {
    std::vector<std::string> known;
    for (const BackendEntry& b : device_backends()) known.push_back(b.name);
    // Users of CUDA, HIP or Metal renderers try those names: say how GPUs are reached.
    const std::string& n = spec.name();
    const bool gpu_word = n == "gpu" || n == "cuda" || n == "hip" || n == "optix" ||
                          n == "metal" || n == "rocm" || n == "vulkan" || n == "sycl";
    spec.fail("unknown device type '" + n + "' (known: " + join(known) + ")" +
              (gpu_word ? std::string("; GPUs are reached through OpenCL (opencl:N): "
                                      "`multiray devices` lists them")
                        : std::string()));
  }
  if (!backend->built) spec.fail(backend->not_built);
  spec.accept_only(param_keys(*backend));
  return spec;
}

std::vector<BackendEntry>& registry() {
  static std::vector<BackendEntry> backends = builtin_backends();
  return backends;
}

}  // namespace

const std::vector<BackendEntry>& device_backends() { return registry(); }

void register_backend(BackendEntry entry) {
  for (BackendEntry& b : registry())
    if (b.name == entry.name) {
      b = std::move(entry);
      return;
    }
  registry().push_back(std::move(entry));
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
  return b && b->built ? b->capabilities() : DeviceCapabilities{};
}

BackendFeatures backend_features(const std::string& type) {
  const BackendEntry* b = find_backend(type);
  return b ? b->features : BackendFeatures{};
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
