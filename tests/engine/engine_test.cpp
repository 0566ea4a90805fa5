// The engine over real CPU devices: the image never depends on the balancer or the
// number of devices, every pixel is rendered once, and failures are survived.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

#include <cstring>

#include "balance/balancer.h"
#include "core/clock.h"
#include "core/error.h"
#include "device/cpu/cpu_device.h"
#include "engine/engine.h"
#include "scene/builders.h"

namespace multiray {
namespace engine_test {

constexpr int kW = 53, kH = 31;

std::vector<ViewSetup> views(const Scene& s, int frame) {
  ViewSetup v;
  v.camera = s.cameras[0];
  v.width = kW, v.height = kH, v.frame = uint32_t(frame);
  return {v};
}

// Renders frames 0..frames-1 and returns the last image.
std::vector<Vec3> render_with(SceneCache& rs, const std::string& spec, int devices, int frames,
                              std::vector<double> speeds = {}) {
  std::vector<std::unique_ptr<CpuDevice>> owned;
  std::vector<Device*> ptrs;
  for (int i = 0; i < devices; ++i) {
    CpuDeviceOptions o;
    o.speed = i < int(speeds.size()) ? speeds[size_t(i)] : 1.0;
    owned.push_back(std::make_unique<CpuDevice>(rs, o, "cpu"));
    ptrs.push_back(owned.back().get());
  }
  Engine engine(ptrs, balance::make_balancer(spec, devices));
  RenderSettings settings{.spp = 1, .max_bounces = 4};
  for (int f = 0; f < frames; ++f) {
    const FrameRecord rec = engine.render_frame(f, views(rs.scene(), f), settings);
    uint64_t pixels = 0;
    for (const auto& d : rec.devices) pixels += d.pixels;
    EXPECT_EQ(pixels, uint64_t(kW) * kH) << spec << " frame " << f;  // each pixel once
  }
  return engine.images()[0].pixels;
}

TEST(Engine, ImageIsBitIdenticalForEveryBalancerAndDeviceCount) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const auto reference = render_with(rs, "uniform", 1, 3);
  for (const std::string& name : balance::balancer_names())
    for (int devices : {1, 2, 5}) {
      const auto img = render_with(rs, name, devices, 3);
      ASSERT_EQ(img.size(), reference.size());
      EXPECT_EQ(std::memcmp(img.data(), reference.data(), img.size() * sizeof(Vec3)), 0)
          << name << " on " << devices << " devices";
    }
}

// A device's render() with the CPU time its (engine) thread spent in it: the emulated
// idle of a one-thread CPU device is set by that CPU time, not by the wall time.
class CpuMeteredDevice : public Device {
 public:
  explicit CpuMeteredDevice(Device& inner) : inner_(inner) {}
  const DeviceInfo& info() const override { return inner_.info(); }
  void set_emulated_speed(double speed) override { inner_.set_emulated_speed(speed); }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    const double start = SlowdownEmulator::thread_cpu_ms();
    DeviceReport r = inner_.render(job, source, index);
    cpu_ms = SlowdownEmulator::thread_cpu_ms() - start;
    return r;
  }
  double cpu_ms = 0;  // of the last render()

 private:
  Device& inner_;
};

// Every check here holds whatever the load of the machine. The frame is ~1 ms of work per
// device, less than one preemption by the scheduler, so which device's wall time is the
// longer (and how large the imbalance is) depends on the load; what the emulated
// quarter-speed device guarantees is an idle up to four times its CPU time.
TEST(Engine, RecordsTimesSharesAndImbalance) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  constexpr double kSpeed = 0.25;
  CpuDevice fast_cpu(rs, {}, "cpu"), slow_cpu(rs, CpuDeviceOptions{.speed = kSpeed}, "slow");
  CpuMeteredDevice fast(fast_cpu), slow(slow_cpu);
  Engine engine({&fast, &slow}, balance::make_balancer("uniform", 2));
  // Frame 0 warms up: a device's first render() on a thread pins it and enters its arena
  // for the first time, CPU time outside any item that the emulated idle does not scale.
  engine.render_frame(0, views(scene, 0), RenderSettings{.spp = 2});
  const FrameRecord rec = engine.render_frame(1, views(scene, 1), RenderSettings{.spp = 2});
  ASSERT_EQ(rec.devices.size(), 2u);
  EXPECT_NEAR(rec.devices[0].work_share + rec.devices[1].work_share, 1.0, 1e-9);
  const double t0 = rec.devices[0].time_ms, t1 = rec.devices[1].time_ms;
  // Each device's time holds its rendering, and the slow one's its emulated idle too: it
  // sleeps until its items' CPU time / speed has passed (SlowdownEmulator). An item's CPU
  // time is its busy (wall) time less what other processes stole from its thread, both
  // reported; its CPU time outside items (taking items, bookkeeping) is not slowed, so the
  // bound holds at any load. (The thread's whole CPU time in render() is larger by that
  // unslowed part, which grows with the load: it bounds nothing.)
  EXPECT_GE(t0, rec.devices[0].busy_ms);
  EXPECT_GE(t1, rec.devices[1].busy_ms);
  const double item_cpu_ms = rec.devices[1].busy_ms - rec.devices[1].stolen_ms;
  EXPECT_GT(item_cpu_ms, 0.0);
  EXPECT_LE(item_cpu_ms, slow.cpu_ms + 1e-3);  // within the thread's CPU time in render()
  EXPECT_GE(t1 + 1e-6, item_cpu_ms / kSpeed) << "items' CPU time " << item_cpu_ms << " ms";
  // The record's imbalance is λ = t_max / t_mean - 1 of the device times it records.
  EXPECT_NEAR(rec.imbalance, std::max(t0, t1) / (0.5 * (t0 + t1)) - 1.0, 1e-9);
  EXPECT_GT(rec.imbalance, 0.0);
  // The engine's frame holds both devices' frames (the same clock, nested intervals).
  EXPECT_GE(rec.frame_ms, std::max(t0, t1));
}

// A device that throws mid-frame loses nothing: its work is re-rendered, it is dropped,
// and the image equals a healthy run's.
class FailingDevice : public Device {
 public:
  explicit FailingDevice(SceneCache& rs) : inner_(rs, {}, "cpu") {
    info_ = inner_.info();
    info_.name = "failing test device";
  }
  const DeviceInfo& info() const override { return info_; }
  void set_emulated_speed(double) override {}
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    DeviceReport r;
    uint32_t id;
    if (source.next(index, id)) {  // takes one item and "loses" it
      r.failed = true;
      r.error = "injected failure";
    }
    (void)job;
    return r;
  }

 private:
  CpuDevice inner_;
  DeviceInfo info_;
};

TEST(Engine, FailedDeviceIsDroppedAndItsWorkRedone) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const auto reference = render_with(rs, "uniform", 1, 1);
  CpuDevice good(rs, {}, "cpu");
  FailingDevice bad(rs);
  Engine engine({&good, &bad}, balance::make_balancer("uniform", 2));
  const FrameRecord rec =
      engine.render_frame(0, views(scene, 0), RenderSettings{.spp = 1, .max_bounces = 4});
  EXPECT_FALSE(engine.alive(1));
  ASSERT_EQ(rec.messages.size(), 1u);
  EXPECT_NE(rec.messages[0].find("injected failure"), std::string::npos);
  EXPECT_EQ(std::memcmp(engine.images()[0].pixels.data(), reference.data(),
                        reference.size() * sizeof(Vec3)),
            0);
  // Next frame runs on the survivor alone.
  const FrameRecord next =
      engine.render_frame(1, views(scene, 1), RenderSettings{.spp = 1, .max_bounces = 4});
  EXPECT_EQ(next.devices[0].pixels, uint64_t(kW) * kH);
}

// Renders its own items, then fails on the next call of the frame (the engine asking it to
// re-render another device's items) after taking one of them.
class FailsWhenHelping : public Device {
 public:
  explicit FailsWhenHelping(SceneCache& rs) : inner_(rs, {}, "cpu") {
    info_ = inner_.info();
    info_.name = "fails when helping";
  }
  const DeviceInfo& info() const override { return info_; }
  void set_emulated_speed(double) override {}
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    if (calls_++ == 0) return inner_.render(job, source, index);
    DeviceReport r;
    uint32_t id;
    r.failed = source.next(index, id);  // takes one item and "loses" it
    r.error = "failed while helping";
    return r;
  }

 private:
  CpuDevice inner_;
  DeviceInfo info_;
  int calls_ = 0;
};

// Two faults in one frame: the device that re-renders a failed one's items fails too. Its
// share goes on to the third device and the image is whole; it used to be left out, the
// frame returned with those pixels never rendered and no word said.
TEST(Engine, ADeviceFailingWhileReRenderingPassesItsShareOn) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const auto reference = render_with(rs, "uniform", 1, 1);
  FailingDevice bad(rs);
  FailsWhenHelping flaky(rs);
  CpuDevice good(rs, {}, "cpu");
  Engine engine({&bad, &flaky, &good}, balance::make_balancer("uniform", 3));
  const FrameRecord rec =
      engine.render_frame(0, views(scene, 0), RenderSettings{.spp = 1, .max_bounces = 4});
  EXPECT_FALSE(engine.alive(0));
  EXPECT_FALSE(engine.alive(1));
  ASSERT_EQ(rec.messages.size(), 2u);
  EXPECT_NE(rec.messages[1].find("failed while re-rendering the items of device 0"),
            std::string::npos)
      << rec.messages[1];
  EXPECT_EQ(std::memcmp(engine.images()[0].pixels.data(), reference.data(),
                        reference.size() * sizeof(Vec3)),
            0);
}

// When every device fails in one frame, the error names each failure, not only the last
// one looked at: a master whose own link is cut loses every rank at once, and a line naming
// one rank sent its reader after the wrong machine (tests/mpi/netfault.sh master).
TEST(Engine, WhenEveryDeviceFailsEachFailureIsNamed) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  FailingDevice a(rs), b(rs);
  Engine engine({&a, &b}, balance::make_balancer("uniform", 2));
  try {
    engine.render_frame(0, views(scene, 0), RenderSettings{.spp = 1, .max_bounces = 4});
    ADD_FAILURE() << "no error when every device failed";
  } catch (const DeviceError& e) {
    const std::string what = e.what();
    size_t named = 0;
    for (size_t at = what.find("injected failure"); at != std::string::npos;
         at = what.find("injected failure", at + 1))
      ++named;
    EXPECT_EQ(named, 2u) << what;
  }
}

}  // namespace engine_test
}  // namespace multiray

namespace multiray {
namespace engine_test {

// Progress counts the pixels handed to devices: all of them once a frame is done.
TEST(Engine, ProgressReachesOneAtTheEndOfAFrame) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice a(rs, {}, "cpu"), b(rs, {}, "cpu");
  Engine engine({&a, &b}, balance::make_balancer("queue:tile=8", 2));
  EXPECT_EQ(engine.progress(), 0.0);
  engine.render_frame(0, views(scene, 0), RenderSettings{.spp = 1, .max_bounces = 2});
  EXPECT_DOUBLE_EQ(engine.progress(), 1.0);
}

}  // namespace engine_test
}  // namespace multiray

namespace multiray {
namespace engine_test {

// A device that fails at any point of a frame — before its first item, in the middle, at
// its last — loses no pixel: what it took and did not finish is rendered by the other.
TEST(Engine, DeviceFailingAtEveryPositionLosesNoPixel) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  const RenderSettings settings{.spp = 1, .max_bounces = 2};
  CpuDevice alone(cache, {}, "cpu");
  Engine reference({&alone}, balance::make_balancer("uniform", 1));
  reference.render_frame(0, views(scene, 0), settings);
  for (const char* spec : {"queue:tile=8", "hybrid", "uniform"})
    for (int k = 0; k <= 12; ++k) {
      CpuDevice failing(cache, CpuDeviceOptions{.fail_after = k}, "cpu:fail_after");
      CpuDevice good(cache, {}, "cpu");
      Engine engine({&failing, &good}, balance::make_balancer(spec, 2));
      const FrameRecord rec = engine.render_frame(0, views(scene, 0), settings);
      EXPECT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW) * kH)
          << spec << " k=" << k;
      EXPECT_EQ(std::memcmp(engine.images()[0].pixels.data(), reference.images()[0].pixels.data(),
                            size_t(kW * kH) * sizeof(Vec3)),
                0)
          << spec << " fails after " << k;
    }
}

// The emulator's contract, with no timing assumption beyond sleep_until's: after items of
// busy time b_k it has not returned before frame start + (sum of b_k) / speed.
TEST(SlowdownEmulator, SleepsToBusyOverSpeed) {
  const Stopwatch clock;
  SlowdownEmulator emulator(0.25);
  emulator.after_unit(5.0);
  EXPECT_GE(clock.elapsed_ms(), 20.0);
  emulator.after_unit(2.5);
  EXPECT_GE(clock.elapsed_ms(), 30.0);
  SlowdownEmulator full(1.0);  // full speed never idles
  const Stopwatch fast;
  full.after_unit(1000.0);
  EXPECT_LT(fast.elapsed_ms(), 500.0);
  // The thread's CPU time advances with work and not with sleep.
  const double cpu0 = SlowdownEmulator::thread_cpu_ms();
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_LT(SlowdownEmulator::thread_cpu_ms() - cpu0, 15.0);
  volatile double x = 0;
  for (int i = 0; i < 20000000; ++i) x = x + 1e-9 * i;
  EXPECT_GT(SlowdownEmulator::thread_cpu_ms() - cpu0, 0.0);
}

}  // namespace engine_test
}  // namespace multiray

namespace multiray {
namespace engine_test {

// A CPU device that pays `fixed_ms` (a sleep) every frame it is started, as a GPU pays
// its upload, launch and read-back whatever its share, and counts the frames it was
// started on.
class FixedCostDevice : public Device {
 public:
  FixedCostDevice(Device& inner, double fixed_ms) : inner_(inner), fixed_ms_(fixed_ms) {}
  const DeviceInfo& info() const override { return inner_.info(); }
  void set_emulated_speed(double speed) override { inner_.set_emulated_speed(speed); }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    ++started;
    const Stopwatch clock;
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(fixed_ms_));
    DeviceReport r = inner_.render(job, source, index);
    r.time_ms = clock.elapsed_ms();
    return r;
  }
  int started = 0;

 private:
  Device& inner_;
  double fixed_ms_;
};

// Issue 50: a device whose fixed cost outlasts the frame is left out by the default
// balancer (hybrid) and then costs nothing: it is not even started. After a change that
// makes it pay (512x the samples: the frame now takes hundreds of ms, its 30 ms are worth
// paying) it comes back within two frames and takes part from then on. The image is
// bit-identical to one device's whichever subset rendered it. What is timed is a sleep of
// 30 ms against a frame of ~0.5 ms (and later against one of ~250 ms): those decisions
// hold with wide margins at any load. What the second device saves beside the first on
// the same two cores after the change does depend on the load, and the rule judges it
// every frame: beside other tests it was rested for one frame, to measure it (saving
// under 10%, participation.h) or left out (saving under 3% once, in a frame the load
// slowed), at frame 23 in about one run in 20-60 (2026-12-04; the test forbade any rest
// then). So the frames after the return allow one rest among three, with its reason shown.
TEST(Engine, ADeviceWhoseFixedCostDoesNotPayIsLeftOutAndComesBackWhenItDoes) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  CpuDevice cpu(rs, {}, "cpu"), inner(rs, {}, "cpu"), alone(rs, {}, "cpu");
  FixedCostDevice slow_start(inner, 30);
  Engine engine({&cpu, &slow_start}, balance::make_balancer("hybrid", 2));
  Engine reference({&alone}, balance::make_balancer("uniform", 1));
  auto small = [&](int frame) {
    std::vector<ViewSetup> v = views(scene, frame);
    v[0].width = 24, v[0].height = 16;
    return v;
  };
  int rested = 0, back_at = -1, rested_after = 0;
  std::string reasons;
  constexpr int kChange = 20, kFrames = 26;
  for (int f = 0; f < kFrames; ++f) {
    const RenderSettings settings{.spp = f < kChange ? 1 : 512, .max_bounces = 4};
    const int started = slow_start.started;
    const FrameRecord rec = engine.render_frame(f, small(f), settings);
    reference.render_frame(f, small(f), settings);
    const auto& img = engine.images()[0].pixels;
    const auto& ref = reference.images()[0].pixels;
    ASSERT_EQ(img.size(), ref.size());
    EXPECT_EQ(std::memcmp(img.data(), ref.data(), img.size() * sizeof(Vec3)), 0) << f;
    if (rec.devices[1].rested) {
      ++rested;
      EXPECT_EQ(slow_start.started, started) << f;  // not started: it costs nothing
      EXPECT_EQ(rec.devices[1].pixels, 0u) << f;
      EXPECT_EQ(rec.devices[0].pixels, 24u * 16u) << f;
    } else if (f >= kChange && back_at < 0) {
      back_at = f;
    }
    if (f >= kChange + 3 && rec.devices[1].rested) {
      ++rested_after;
      reasons += std::to_string(f) + ": " + engine.last_plan().rest_reason.at(1) + "; ";
    }
  }
  EXPECT_LE(rested_after, 1) << reasons;
  EXPECT_GE(rested, 10);  // of the 20 frames before the change: left out after learning
  EXPECT_GE(back_at, kChange);
  EXPECT_LE(back_at, kChange + 2);
}

}  // namespace engine_test
}  // namespace multiray
