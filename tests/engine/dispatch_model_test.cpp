// The engine and the simulator execute plans with the same Dispatcher. Devices that take
// exactly the simulator's times, and ask for work in the simulator's order (a virtual
// clock serialises them), must get exactly the items the simulator hands out, frame after
// frame, for every balancer; the engine's trace replayed by the simulator gives the same.
#include <gtest/gtest.h>

#include <condition_variable>
#include <cstring>
#include <mutex>
#include <sstream>

#include "balance/simulate.h"
#include "balance/trace.h"
#include "device/cpu/cpu_device.h"
#include "device/work_list.h"
#include "engine/engine.h"
#include "scene/builders.h"

namespace multiray {
namespace dispatch_model_test {

constexpr int kW = 64, kH = 40;

// Item cost in ms at speed 1: uneven, rows further down cost more.
double cost_of(const WorkItem& it) {
  double c = 0;
  for (int y = it.rect.y0; y < it.rect.y1; ++y) c += double(it.rect.width()) * (1 + y / 8);
  return c * 0.01;
}

// Lets the device whose virtual clock is earliest (lowest index on ties) act, one at a
// time: the order in which the simulator's devices ask the Dispatcher for work.
class VirtualClock {
 public:
  void reset(size_t n) {
    std::lock_guard<std::mutex> lock(m_);
    clock_.assign(n, 0.0);
    done_.assign(n, false);
  }
  void wait_turn(size_t d) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] {
      for (size_t e = 0; e < clock_.size(); ++e)
        if (e != d && !done_[e] && (clock_[e] < clock_[d] || (clock_[e] == clock_[d] && e < d)))
          return false;
      return true;
    });
  }
  double advance(size_t d, double dt) {
    std::lock_guard<std::mutex> lock(m_);
    clock_[d] += dt;
    cv_.notify_all();
    return clock_[d];
  }
  void finish(size_t d) {
    std::lock_guard<std::mutex> lock(m_);
    done_[d] = true;
    cv_.notify_all();
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  std::vector<double> clock_;
  std::vector<bool> done_;
};

// Renders nothing; "takes" cost_of(item) / speed ms of virtual time per item.
class VirtualDevice : public Device {
 public:
  VirtualDevice(VirtualClock& clock, double speed) : clock_(clock), speed_(speed) {
    info_.type = "virtual";
    info_.name = info_.spec = "virtual";
  }
  const DeviceInfo& info() const override { return info_; }
  void set_emulated_speed(double) override {}
  DeviceReport render(const FrameJob&, WorkSource& source, int index) override {
    DeviceReport r;
    const size_t d = size_t(index);
    for (;;) {
      clock_.wait_turn(d);
      uint32_t id;
      if (!source.next(index, id)) break;
      const WorkItem& it = source.item(id);
      const double dt = cost_of(it) / speed_;
      r.time_ms = clock_.advance(d, dt);
      r.add(ItemReport{it, dt, double(it.rect.area()), dt, id}, 0);
    }
    clock_.finish(d);
    return r;
  }

 private:
  VirtualClock& clock_;
  double speed_;
  DeviceInfo info_;
};

const std::vector<double> kSpeeds = {1.0, 0.5, 0.25};

TEST(DispatchModel, EngineHandsOutWhatTheSimulatorPredicts) {
  const balance::FrameShape shape{kW, kH, 1, {}};
  std::vector<balance::SimDevice> sim;
  for (double s : kSpeeds) sim.push_back(balance::SimDevice{s});
  for (const char* spec :
       {"hybrid", "queue:tile=8:batch=2", "semi-static", "dlb", "static", "uniform"}) {
    VirtualClock clock;
    std::vector<std::unique_ptr<VirtualDevice>> owned;
    std::vector<Device*> devices;
    for (double s : kSpeeds) {
      owned.push_back(std::make_unique<VirtualDevice>(clock, s));
      devices.push_back(owned.back().get());
    }
    Engine engine(devices, balance::make_balancer(spec, 3));
    auto model = balance::make_balancer(spec, 3);
    std::ostringstream trace_text;
    balance::TraceWriter trace(trace_text, engine.balancer().spec(),
                               {{"v0", 1.0}, {"v1", 0.5}, {"v2", 0.25}});
    std::vector<balance::FrameStats> engine_frames;
    for (int f = 0; f < 6; ++f) {
      clock.reset(kSpeeds.size());
      ViewSetup v;
      v.width = kW, v.height = kH, v.frame = uint32_t(f);
      engine.render_frame(f, {v}, RenderSettings{});
      const balance::Plan plan = model->plan(shape, f);
      const balance::FrameStats predicted = balance::simulate(
          plan, shape, sim, [](const WorkItem& it) { return cost_of(it); }, f);
      model->update(predicted);
      for (size_t d = 0; d < kSpeeds.size(); ++d) {
        const auto& got = engine.last_stats().devices[d];
        const auto& want = predicted.devices[d];
        ASSERT_EQ(got.items.size(), want.items.size()) << spec << " frame " << f << " dev " << d;
        for (size_t i = 0; i < got.items.size(); ++i) {
          EXPECT_EQ(got.items[i].item, want.items[i].item) << spec << " frame " << f;
          EXPECT_EQ(got.items[i].id, want.items[i].id) << spec << " frame " << f;
        }
        EXPECT_EQ(got.time_ms, want.time_ms) << spec << " frame " << f << " dev " << d;
      }
      trace.frame(engine.last_stats());
      engine_frames.push_back(engine.last_stats());
    }
    // The engine's trace, replayed through the simulator with the same balancer.
    std::istringstream in(trace_text.str());
    auto replayed_by = balance::make_balancer(spec, 3);
    const auto replay = balance::replay_trace(balance::read_trace(in), *replayed_by);
    for (size_t f = 0; f < replay.size(); ++f)
      for (size_t d = 0; d < kSpeeds.size(); ++d) {
        const auto& got = replay[f].stats.devices[d].items;
        const auto& want = engine_frames[f].devices[d].items;
        ASSERT_EQ(got.size(), want.size()) << spec << " replay frame " << f;
        for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].item, want[i].item) << spec;
      }
  }
}

// A device behind a slow link pulls several items per request and prefetches more; the
// engine still renders every pixel once and the image does not change.
class Batching : public Device {
 public:
  Batching(SceneCache& c, size_t k) : inner_(c, {}, "cpu"), k_(k) {}
  const DeviceInfo& info() const override { return inner_.info(); }
  void set_emulated_speed(double s) override { inner_.set_emulated_speed(s); }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    DeviceReport all;
    for (;;) {
      std::vector<uint32_t> ids;
      if (source.next(index, k_, ids) == 0) break;
      source.prefetch(index, k_);  // reserved, still stealable by the other device
      std::vector<WorkItem> items;
      for (uint32_t id : ids) items.push_back(source.item(id));
      ListWorkSource mine(items, ids);
      const DeviceReport r = inner_.render(job, mine, index);
      all.items.insert(all.items.end(), r.items.begin(), r.items.end());
      all.samples += r.samples, all.pixels += r.pixels, all.rays += r.rays;
      all.busy_ms += r.busy_ms, all.time_ms += r.time_ms;
    }
    return all;
  }

 private:
  CpuDevice inner_;
  size_t k_;
};

TEST(DispatchModel, BatchPullsAndPrefetchLoseNothing) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = kW, v.height = kH;
  const RenderSettings settings{.spp = 1, .max_bounces = 2};
  CpuDevice single(cache, {}, "cpu");
  Engine reference({&single}, balance::make_balancer("uniform", 1));
  reference.render_frame(0, {v}, settings);
  for (const char* spec : {"queue:tile=8", "hybrid"}) {
    Batching batched(cache, 3);
    CpuDevice plain(cache, {}, "cpu");
    Engine engine({&batched, &plain}, balance::make_balancer(spec, 2));
    for (int f = 0; f < 2; ++f) {
      const FrameRecord rec = engine.render_frame(0, {v}, settings);
      EXPECT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW * kH)) << spec;
    }
    EXPECT_EQ(std::memcmp(engine.images()[0].pixels.data(), reference.images()[0].pixels.data(),
                          size_t(kW * kH) * sizeof(Vec3)),
              0)
        << spec;
  }
}

}  // namespace dispatch_model_test
}  // namespace multiray
