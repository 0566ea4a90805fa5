// The one device loop (device/device_loop.h) behaves the same on every backend of the
// registry, the test's toy backend included: each item reported once with its samples and
// times, the injected failure after exactly fail_after items over the device's life, an
// emulated speed that idles (and says so in the name), a frame refused before any work
// when the kernel is missing. Backends this machine cannot make (no OpenCL device) skip.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <thread>

#include "core/error.h"
#include "device/device_factory.h"
#include "device/toy_backend.h"
#include "device/work_list.h"
#include "scene/builders.h"

namespace multiray {
namespace device_loop_test {

constexpr int kW = 64, kH = 48, kSide = 16;  // 12 items

std::vector<WorkItem> squares() {
  std::vector<WorkItem> items;
  for (int y = 0; y < kH; y += kSide)
    for (int x = 0; x < kW; x += kSide)
      items.push_back(WorkItem{Rect{x, y, x + kSide, y + kSide}, 0});
  return items;
}

// Every backend of the registry that is built, the toy one registered first; a CPU team
// (two threads taking items at once) besides.
std::vector<std::string> backend_specs() {
  testing::register_toy_backend();
  std::vector<std::string> specs;
  for (const BackendEntry& b : device_backends())
    if (b.built) specs.push_back(b.name);
  specs.push_back("cpu:threads=2");
  return specs;
}

class DeviceLoop : public ::testing::TestWithParam<std::string> {
 protected:
  DeviceLoop() : cache_(scene_) {}
  // The device of the parameter's spec with `options` added; skips the test when this
  // machine cannot make it.
  std::unique_ptr<Device> make(const std::string& options = "") {
    const std::string spec = GetParam() + (options.empty() ? "" : ":" + options);
    try {
      return create_device(parse_device_specs(spec).at(0), cache_);
    } catch (const std::runtime_error& e) {  // InputError, DeviceError
      skipped_ = e.what();
      return nullptr;
    }
  }
  // Renders the 12 items on `device` from a thread of its own, as the engine does.
  DeviceReport render(Device& device, const std::string& kernel = "path") {
    ViewSetup view;
    view.camera = scene_.cameras.at(0);
    view.width = kW, view.height = kH;
    RenderSettings settings{.spp = 2, .max_bounces = 2};
    settings.kernel = kernel;
    FrameJob job{{view}, settings, &out_};
    source_ = std::make_unique<ListWorkSource>(squares());
    DeviceReport r;
    std::thread([&] { r = device.render(job, *source_, 0); }).join();
    return r;
  }

  const Scene scene_ = make_cornell_box();
  SceneCache cache_;
  std::vector<Framebuffer> out_{Framebuffer(kW, kH)};
  std::unique_ptr<ListWorkSource> source_;
  std::string skipped_;
};

#define MAKE_OR_SKIP(device, options) \
  const auto device = make(options);  \
  if (!device) GTEST_SKIP() << skipped_;

TEST_P(DeviceLoop, ReportsEveryItemOnceWithItsSamplesAndTimes) {
  MAKE_OR_SKIP(device, "");
  const DeviceReport r = render(*device);
  ASSERT_FALSE(r.failed) << r.error;
  ASSERT_EQ(r.items.size(), squares().size());
  std::set<uint32_t> ids;
  double busy = 0, time = 0, samples = 0;
  for (const ItemReport& it : r.items) {
    ids.insert(it.id);
    EXPECT_EQ(it.item.rect, squares().at(it.id).rect);
    EXPECT_EQ(it.samples, double(kSide * kSide * 2)) << "2 spp";
    EXPECT_GE(it.busy_ms, 0.0);
    EXPECT_GE(it.time_ms + 1e-9, it.busy_ms);
    busy += it.busy_ms, time += it.time_ms, samples += it.samples;
  }
  EXPECT_EQ(ids.size(), squares().size()) << "each item once";
  EXPECT_NEAR(r.busy_ms, busy, 1e-6);
  EXPECT_EQ(double(r.samples), samples);
  EXPECT_EQ(r.pixels, uint64_t(kW * kH));
  EXPECT_GT(r.rays, 0u);
  EXPECT_LE(time, r.time_ms + 1e-3) << "items' times add up to no more than the frame";
  EXPECT_NE(device->info().name.find(device->info().type), std::string::npos);
}

TEST_P(DeviceLoop, FailsAfterExactlyFailAfterItemsOverItsLife) {
  MAKE_OR_SKIP(device, "fail_after=3");
  DeviceReport r = render(*device);
  EXPECT_TRUE(r.failed);
  EXPECT_THAT(r.error, ::testing::HasSubstr("injected failure after 3 items"));
  EXPECT_EQ(r.items.size(), 3u) << "a batch stops at fail_after too";
  // The count is over the device's life: the next frame fails at its first item.
  r = render(*device);
  EXPECT_TRUE(r.failed);
  EXPECT_TRUE(r.items.empty());
}

TEST_P(DeviceLoop, AnEmulatedSpeedIdlesAndIsLabelled) {
  constexpr double kSpeed = 0.25;
  MAKE_OR_SKIP(device, "speed=0.25");
  EXPECT_EQ(device->info().emulated_speed, kSpeed);
  EXPECT_THAT(device->info().name, ::testing::HasSubstr("emulated speed 0.25"));
  const DeviceReport r = render(*device);
  ASSERT_FALSE(r.failed) << r.error;
  // The device sleeps until its work (busy time less what other processes took from a
  // thread that renders alone) over its speed has passed; each item's time holds its idle.
  const double work_ms = r.busy_ms - r.stolen_ms;
  EXPECT_GT(work_ms, 0.0);
  EXPECT_GE(r.time_ms + 1e-6, work_ms / kSpeed);
  double items_ms = 0;
  for (const ItemReport& it : r.items) items_ms += it.time_ms;
  EXPECT_GE(items_ms, 0.9 * work_ms / kSpeed) << "the idle belongs to the items' times";
  device->set_emulated_speed(1.0);
  EXPECT_EQ(device->info().emulated_speed, 1.0);
}

TEST_P(DeviceLoop, RefusesAKernelItLacksBeforeTakingAnyItem) {
  MAKE_OR_SKIP(device, "");
  const DeviceReport r = render(*device, "no-such-kernel");
  EXPECT_TRUE(r.failed);
  EXPECT_THAT(r.error, ::testing::HasSubstr("no-such-kernel"));
  EXPECT_TRUE(r.items.empty());
  EXPECT_EQ(source_->pending(0), squares().size()) << "nothing taken";
}

INSTANTIATE_TEST_SUITE_P(Registry, DeviceLoop, ::testing::ValuesIn(backend_specs()),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           std::string name = p.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace device_loop_test
}  // namespace multiray
