// The CPU device's work per item (issue 30): its arena is entered once a frame, with
// several threads each thread takes small items itself, the items' times still add up to
// the device's time, and the image does not depend on threads or item sizes.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "balance/balancer.h"
#include "core/clock.h"
#include "device/cpu/cpu_device.h"
#include "device/work_list.h"
#include "engine/engine.h"
#include "scene/builders.h"

namespace multiray {
namespace cpu_items_test {

constexpr int kW = 64, kH = 48;

// Items of side `side` covering the kW x kH frame, row by row.
std::vector<WorkItem> squares(int side) {
  std::vector<WorkItem> items;
  for (int y = 0; y < kH; y += side)
    for (int x = 0; x < kW; x += side)
      items.push_back(WorkItem{Rect{x, y, std::min(kW, x + side), std::min(kH, y + side)}, 0});
  return items;
}

struct Rendered {
  DeviceReport report;
  std::vector<Vec3> pixels;
};

// Renders the frame as `items` on `device` from a thread of its own (as the engine does).
Rendered render(CpuDevice& device, const Scene& scene, const std::vector<WorkItem>& items,
                int spp = 1) {
  std::vector<Framebuffer> out{Framebuffer(kW, kH)};
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = kW, view.height = kH;
  FrameJob job{{view}, RenderSettings{.spp = spp, .max_bounces = 3}, &out};
  ListWorkSource source(items);
  Rendered r;
  std::thread([&] { r.report = device.render(job, source, 0); }).join();
  r.pixels = out[0].pixels;
  return r;
}

bool same(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(CpuItems, ArenaIsEnteredOncePerFrame) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  for (int threads : {1, 2}) {
    CpuDevice device(cache, CpuDeviceOptions{.threads = threads}, "cpu");
    const Rendered a = render(device, scene, squares(4));  // 192 items
    ASSERT_FALSE(a.report.failed) << a.report.error;
    EXPECT_EQ(a.report.items.size(), squares(4).size());
    EXPECT_EQ(device.arena_entries(), 1u) << threads << " threads";
    render(device, scene, squares(8));
    EXPECT_EQ(device.arena_entries(), 2u) << threads << " threads";
  }
}

// Frames of 192 items of 4 x 4 pixels at 8 spp on `device` until one has items taken by
// two threads, for at most ~20 s: on a loaded machine (and under nice) the arena's second
// thread can wait for a core longer than a frame lasts. Calls `check` on every frame.
template <class Check>
bool until_two_takers(CpuDevice& device, const Scene& scene, Check check) {
  const Stopwatch clock;
  for (int frame = 0; frame < 2000 && clock.elapsed_ms() < 20000; ++frame) {
    check(render(device, scene, squares(4), 8).report);
    if (device.item_takers() == 2) return true;
  }
  return false;
}

// With two threads both take small items.
TEST(CpuItems, SmallItemsAreTakenBySeveralThreads) {
  if (std::thread::hardware_concurrency() < 2)
    GTEST_SKIP() << "one core: the arena's second thread has no core to run on";
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice device(cache, CpuDeviceOptions{.threads = 2}, "cpu:threads=2");
  EXPECT_TRUE(until_two_takers(device, scene, [](const DeviceReport&) {}));
  // An emulated speed keeps items one at a time (it idles after each).
  device.set_emulated_speed(0.99);
  render(device, scene, squares(8));
  EXPECT_EQ(device.item_takers(), 1);
}

// Items rendered at the same time share the wall time: their times add up to no more
// than the device's frame, and busy_ms is their sum.
TEST(CpuItems, ConcurrentItemsShareTheDevicesTime) {
  if (std::thread::hardware_concurrency() < 2)
    GTEST_SKIP() << "one core: the arena's second thread has no core to run on";
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice device(cache, CpuDeviceOptions{.threads = 2}, "cpu:threads=2");
  const bool concurrent = until_two_takers(device, scene, [&](const DeviceReport& r) {
    ASSERT_FALSE(r.failed) << r.error;
    double items_ms = 0;
    for (const ItemReport& it : r.items) {
      EXPECT_GE(it.time_ms, 0.0);
      EXPECT_EQ(it.busy_ms, it.time_ms);
      items_ms += it.time_ms;
    }
    EXPECT_NEAR(items_ms, r.busy_ms, 1e-6);
    EXPECT_LE(items_ms, r.time_ms + 1e-3) << device.item_takers() << " takers";
    EXPECT_GT(items_ms, 0.0);
  });
  EXPECT_TRUE(concurrent);  // else this test saw no items at the same time
}

// Pixels do not depend on the threads or on how the frame was cut.
TEST(CpuItems, ImageIsBitIdenticalForThreadsAndItemSizes) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice one(cache, CpuDeviceOptions{.threads = 1}, "cpu");
  const std::vector<WorkItem> whole{WorkItem{Rect{0, 0, kW, kH}, 0}};
  const Rendered reference = render(one, scene, whole, 2);
  CpuDevice two(cache, CpuDeviceOptions{.threads = 2, .tile = 8}, "cpu:threads=2");
  for (const std::vector<WorkItem>& items : {whole, squares(4), squares(13), squares(32)}) {
    EXPECT_TRUE(same(render(one, scene, items, 2).pixels, reference.pixels)) << items.size();
    EXPECT_TRUE(same(render(two, scene, items, 2).pixels, reference.pixels)) << items.size();
  }
}

// Through the engine, two two-thread devices give every balancer's items (queue tiles,
// hybrid chunks, dlb strips) the image of one one-thread device.
TEST(CpuItems, TwoThreadDevicesKeepEveryBalancersImage) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = kW, view.height = kH;
  const RenderSettings settings{.spp = 1, .max_bounces = 2};
  CpuDevice alone(cache, {}, "cpu");
  Engine reference({&alone}, balance::make_balancer("uniform", 1));
  for (int frame = 0; frame < 2; ++frame) reference.render_frame(frame, {view}, settings);
  for (const std::string& name : balance::balancer_names()) {
    CpuDevice a(cache, CpuDeviceOptions{.threads = 2, .tile = 4}, "cpu:threads=2");
    CpuDevice b(cache, CpuDeviceOptions{.threads = 2}, "cpu:threads=2");
    Engine engine({&a, &b}, balance::make_balancer(name, 2));
    for (int frame = 0; frame < 2; ++frame) {
      const FrameRecord rec = engine.render_frame(frame, {view}, settings);
      EXPECT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW) * kH) << name;
    }
    EXPECT_TRUE(same(engine.images()[0].pixels, reference.images()[0].pixels)) << name;
  }
}

// A two-thread device that fails after taking k items renders at most k and loses no
// pixel: what it took and did not finish is rendered by the other device.
TEST(CpuItems, TwoThreadDeviceFailingLosesNoPixel) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = kW, view.height = kH;
  const RenderSettings settings{.spp = 1, .max_bounces = 2};
  CpuDevice alone(cache, {}, "cpu");
  Engine reference({&alone}, balance::make_balancer("uniform", 1));
  reference.render_frame(0, {view}, settings);
  for (int k : {0, 1, 5, 20}) {
    CpuDevice failing(cache, CpuDeviceOptions{.threads = 2, .fail_after = k}, "cpu:fail");
    // The other device idles (emulated speed) so that the failing one takes its k items.
    CpuDevice good(cache, CpuDeviceOptions{.speed = 0.2}, "cpu:speed=0.2");
    Engine engine({&failing, &good}, balance::make_balancer("queue:tile=8", 2));
    const FrameRecord rec = engine.render_frame(0, {view}, settings);
    EXPECT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW) * kH) << k;
    EXPECT_TRUE(same(engine.images()[0].pixels, reference.images()[0].pixels)) << k;
    // Its two threads together rendered no more than k items (8 x 8 tiles).
    EXPECT_LE(rec.devices[0].pixels, uint64_t(64 * k)) << k;
  }
}

}  // namespace cpu_items_test
}  // namespace multiray
