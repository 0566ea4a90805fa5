// The CPU backend's registry entry (device_factory.h): its --devices keys, capabilities,
// the devices this machine offers and its factory.
#include <unistd.h>

#include <algorithm>
#include <thread>

#include "device/backend_options.h"
#include "device/backends.h"
#include "device/cpu/cpu_device.h"

namespace multiray {

namespace {

using namespace backend_options;

CpuDeviceOptions read_cpu_options(Spec& spec) {
  CpuDeviceOptions o;
  o.threads = spec.get_int("threads", o.threads, 1, 1024);
  o.cores = read_cores(spec);
  const LoopOptions loop = read_loop_options(spec);
  o.speed = loop.speed, o.fail_after = loop.fail_after;
  o.quota = spec.get_positive("quota", o.quota, 1.0);  // of a core per thread
  o.tile = spec.get_int("tile", o.tile, 1, 4096);
  read_memory_options(spec, o.compact, o.memory_limit);
  spec.finish();
  return o;
}

// Every core as one device, and each core alone.
std::vector<OfferedDevice> offer_cpu() {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const uint64_t ram = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
  std::vector<OfferedDevice> out;
  out.push_back({"cpu", "all cores (oneTBB + Embree)", cores, ram,
                 "cpu:threads=" + std::to_string(cores), ""});
  for (unsigned c = 0; c < cores; ++c)
    out.push_back({"cpu", "core " + std::to_string(c), 1, ram,
                   "cpu:threads=1:cores=" + std::to_string(c), ""});
  return out;
}

}  // namespace

BackendEntry cpu_backend() {
  BackendEntry b;
  b.name = "cpu";
  b.help = "CPU cores through oneTBB and Embree";
  b.params = {{"threads", "1..1024", "1", "worker threads (--devices cpu:threads=0: all)"},
              cores_param(),
              speed_param(),
              {"quota", "(0, 1]", "", "real throttle: a fraction of a core per thread (cgroup)"},
              {"tile", "1..4096", "16", "pixel block handed to a thread"},
              fail_after_param(),
              compact_param(),
              mem_param()};
  b.capabilities = &CpuDevice::capabilities;
  b.offer = &offer_cpu;
  b.check = [](Spec& spec) { read_cpu_options(spec); };
  b.create = [](Spec& spec, SceneCache& scenes) -> std::unique_ptr<Device> {
    return std::make_unique<CpuDevice>(scenes, read_cpu_options(spec), spec.text());
  };
  return b;
}

}  // namespace multiray
