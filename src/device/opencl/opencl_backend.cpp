// The OpenCL backend's registry entry (device_factory.h): its --devices keys,
// capabilities, features, the devices this machine offers and its factory. Compiled into
// every multiray: without OpenCL the entry is listed as not built, saying how to build it.
#include <string>

#include "device/backend_options.h"
#include "device/backends.h"
#ifdef MULTIRAY_HAS_OPENCL
#include "core/error.h"
#include "device/opencl/opencl_device.h"
#include "device/opencl/opencl_platform.h"
#endif

namespace multiray {

namespace {

using namespace backend_options;

#ifdef MULTIRAY_HAS_OPENCL
OpenClDeviceOptions read_opencl_options(Spec& spec) {
  OpenClDeviceOptions o;
  o.index = spec.get_int("index", o.index, 0, 65535);
  const LoopOptions loop = read_loop_options(spec);
  o.speed = loop.speed, o.fail_after = loop.fail_after;
  o.tile = spec.get_int("tile", o.tile, 1, 4096);
  o.work_group = spec.get_int("wg", o.work_group, 1, 4096);
  o.work_group_given = spec.has("wg");              // a wg= asked for is noted when fitted
  o.batch = spec.get_int("batch", o.batch, 1, 64);  // MR_BATCH_MAX (kernels/batch_rects.h)
  o.cores = read_cores(spec);
  read_memory_options(spec, o.compact, o.memory_limit);
  spec.finish();
  return o;
}

std::vector<OfferedDevice> offer_opencl() {
  std::vector<OfferedDevice> out;
  for (const OpenClDeviceListing& d : list_opencl_devices())
    out.push_back({"opencl", d.name + " (" + d.kind + ")", d.compute_units, d.memory_bytes,
                   "opencl:" + std::to_string(d.index),
                   "platform " + d.platform + ", driver " + d.driver, d.kind == "cpu"});
  return out;
}

void add_factory(BackendEntry& b) {
  b.capabilities = &OpenClDevice::capabilities;
  b.offer = &offer_opencl;
  b.check = [](Spec& spec) { read_opencl_options(spec); };
  b.create = [](Spec& spec, SceneCache& scenes) -> std::unique_ptr<Device> {
    const OpenClDeviceOptions o = read_opencl_options(spec);
    try {
      return std::make_unique<OpenClDevice>(scenes, o, spec.text());
    } catch (const InputError& e) {
      throw InputError("--devices '" + spec.text() + "': " + e.what());
    }
  };
}
#else
void add_factory(BackendEntry& b) {
  b.built = false;
  b.not_built =
      "this multiray was built without OpenCL (install ocl-icd-opencl-dev, "
      "opencl-clhpp-headers and configure with -DMULTIRAY_WITH_OPENCL=ON)";
}
#endif

}  // namespace

BackendEntry opencl_backend() {
  BackendEntry b;
  b.name = "opencl";
  b.help = "an OpenCL device, opencl:N as `multiray devices` lists it";
  b.params = {{"index", "0..65535", "0", "the device (also written opencl:N)"},
              speed_param(),
              {"tile", "1..4096", "256", "side of the largest square one launch renders"},
              {"wg", "1..4096", "64",
               "work-group size (fitted to each kernel's maximum; a larger one is noted)"},
              {"batch", "1..64", "16",
               "items taken together and rendered in one launch (1: one launch per item)"},
              {"cores", "0, 0+2, 0-3", "", "cores to pin the thread driving the device to"},
              fail_after_param(),
              compact_param(),
              mem_param()};
  b.notes =
      "With PoCL, POCL_DEVICES=\"basic basic\" gives two independent one-core devices "
      "opencl:0 and opencl:1; POCL_MAX_PTHREAD_COUNT=N limits its default pthread device to "
      "N threads";
  b.none_found = "No OpenCL device found (install an ICD, e.g. pocl-opencl-icd).";
  // Every launch has a fixed cost, which hybrid's per-item cost model learns.
  b.features.item_cost = true;
  add_factory(b);
  return b;
}

}  // namespace multiray
