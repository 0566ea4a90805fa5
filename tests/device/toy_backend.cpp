#include "device/toy_backend.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "device/backend_options.h"
#include "device/device_factory.h"
#include "device/device_loop.h"
#include "render/kernel.h"

namespace multiray::testing {

namespace {

// Renders a batch item by item with the CPU kernel of the frame, on the calling thread.
class ToyBatches : public BatchRenderer {
 public:
  ToyBatches(const FrameJob& job, const Kernel& kernel) : job_(job), kernel_(kernel) {}
  size_t batch_limit(const WorkItem& /*first*/) const override { return 4; }
  std::vector<KernelStats> render(const std::vector<WorkItem>& items) override {
    std::vector<KernelStats> stats;
    for (const WorkItem& item : items)
      stats.push_back(kernel_.render_rect(job_.views.at(size_t(item.view)), job_.settings,
                                          item.rect, job_.outputs->at(size_t(item.view))));
    return stats;
  }

 private:
  const FrameJob& job_;
  const Kernel& kernel_;
};

// The backend's set-up: every CPU kernel that accepts the scene. Its render() is the loop.
class ToyDevice : public LoopDevice {
 public:
  ToyDevice(SceneCache& scenes, LoopOptions options, std::string spec) : LoopDevice(options) {
    for (const KernelEntry& e : cpu_kernels())
      if (e.accepts(scenes.scene())) kernels_.emplace(e.name, e.make(scenes, false));
    info_.type = "toy";
    info_.spec = std::move(spec);
    info_.caps = capabilities();
    info_.name = "toy (the calling thread" + emulated_label(options.speed) + ")";
  }
  static DeviceCapabilities capabilities() {
    DeviceCapabilities caps;
    for (const KernelEntry& e : cpu_kernels()) caps.kernels.push_back(e.name);
    caps.sampling = sampling_modes(false);  // no foveation
    caps.representation = "embree";
    return caps;
  }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    FrameLoop frame(loop_, info_, job, source, index, FrameMode{false, true});
    if (frame.refused()) return frame.finish();
    const auto kernel = kernels_.find(job.settings.kernel);
    if (kernel == kernels_.end()) {
      frame.fail("toy device has no kernel '" + job.settings.kernel + "' for this scene");
      return frame.finish();
    }
    ToyBatches batches(job, *kernel->second);
    frame.run(batches);
    return frame.finish();
  }

 private:
  std::map<std::string, std::unique_ptr<Kernel>> kernels_;
};

LoopOptions read_toy_options(Spec& spec) {
  const LoopOptions o = backend_options::read_loop_options(spec);
  spec.finish();
  return o;
}

}  // namespace

void register_toy_backend() {
  if (const BackendEntry* b = find_backend("toy"); b) return;
  BackendEntry b;
  b.name = "toy";
  b.help = "a test backend: the CPU kernels on the calling thread";
  b.params = {backend_options::speed_param(), backend_options::fail_after_param()};
  b.notes = "The toy backend exists only in the tests";
  // As a GPU-style backend would: every batch pays a fixed cost, which auto weighs.
  b.features.item_cost = true;
  b.capabilities = &ToyDevice::capabilities;
  b.offer = [] {
    return std::vector<OfferedDevice>{{"toy", "the calling thread", 1, 0, "toy", ""}};
  };
  b.check = [](Spec& spec) { read_toy_options(spec); };
  b.create = [](Spec& spec, SceneCache& scenes) -> std::unique_ptr<Device> {
    return std::make_unique<ToyDevice>(scenes, read_toy_options(spec), spec.text());
  };
  register_backend(std::move(b));
}

}  // namespace multiray::testing
