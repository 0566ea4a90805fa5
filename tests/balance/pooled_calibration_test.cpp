// Calibration on several traces at once (calibrate_pooled): traces made by the simulator
// from known devices, of other balancers on the same devices and frames, calibrated
// together recover what one of them alone cannot show.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "balance/trace_calibration.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace pooled_calibration_test {

const FrameShape kShape{160, 96, 1, {}};

// As trace_calibration_test's: a cost per sample the same within each eighth of the rows.
CostFn banded_cost() {
  return pixel_cost(kShape, [](int, int, int y) {
    const int band = y * 8 / kShape.height;
    return 3e-4 * (1 + 0.8 * std::sin(6.28 * (band + 0.5) / 8));
  });
}

Trace record(const std::string& spec, const std::vector<SimDevice>& devices, const CostFn& cost,
             int frames, bool models = false) {
  auto balancer = make_balancer(spec, int(devices.size()));
  const auto run = simulate_run(
      *balancer, kShape, [&](int) { return devices; }, cost, frames);
  std::ostringstream out;
  std::vector<TraceDevice> list;
  for (size_t d = 0; d < devices.size(); ++d)
    list.push_back({"sim " + std::to_string(d), devices[d].speed});
  TraceWriter writer(out, balancer->spec(), list);
  for (const SimFrame& f : run)
    writer.frame(f.stats, models ? f.plan.models : std::vector<DeviceCostModel>{});
  std::istringstream in(out.str());
  return read_trace(in);
}

SimDevice device(double speed, double item_ms, double frame_ms, double launch_ms = 0) {
  SimDevice d;
  d.speed = speed;
  d.item_overhead_ms = item_ms;
  d.frame_overhead_ms = frame_ms;
  d.launch_ms = launch_ms;
  return d;
}

int slow_items(const Trace& t, size_t from) {
  int n = 0;
  for (size_t f = from; f < t.frames.size(); ++f) n += int(t.frames[f].devices[1].items.size());
  return n;
}

// A core (a small fixed cost per item and per frame) beside a device ~14x slower with a
// launch per take of its own list (rusticl's, scaled to these frames: 3 ms on a ~5 ms
// frame).
std::vector<SimDevice> core_and_slow() {
  return {device(1.0, 0.02, 0.2), device(0.07, 0, 0, 3.0)};
}

TEST(PooledCalibration, RecoversASlowDevicesSpeedAndLaunch) {
  const std::vector<SimDevice> devices = core_and_slow();
  const CostFn cost = banded_cost();
  // hybrid gives the slow device a few items (no `model` records: its launch is not
  // told); uniform strips give it half the frame in many items, in one launch a frame.
  const Trace a = record("hybrid", devices, cost, 30);
  const Trace b = record("uniform:layout=strips", devices, cost, 30);
  ASSERT_LT(slow_items(a, 3), 40);
  ASSERT_GT(slow_items(b, 3), 1000);
  // On A alone the launch is not seen, and the speed is far off.
  const TraceCalibration alone = calibrate(a, 3);
  EXPECT_EQ(alone.devices[1].launch_ms, 0.0);
  EXPECT_GT(std::abs(alone.devices[1].speed - 0.07), 0.02);
  // Pooled, both are recovered, and the core's fixed costs too.
  const TraceCalibration cal = calibrate_pooled({&a, &b}, 3);
  EXPECT_TRUE(cal.pooled);
  EXPECT_EQ(cal.traces, 2);
  EXPECT_EQ(cal.plans_matched, cal.plans);  // every plan made again as recorded
  ASSERT_EQ(cal.devices.size(), 2u);
  EXPECT_NEAR(cal.devices[1].speed, 0.07, 0.0007);
  EXPECT_TRUE(cal.devices[1].batching);
  EXPECT_NEAR(cal.devices[1].launch_ms, 3.0, 0.03);
  EXPECT_EQ(cal.devices[1].item_overhead_ms, 0.0);
  EXPECT_LT(cal.devices[1].takes, cal.devices[1].items);
  EXPECT_NEAR(cal.devices[0].speed, 1.0, 1e-9);
  EXPECT_FALSE(cal.devices[0].batching);
  EXPECT_NEAR(cal.devices[0].item_overhead_ms, 0.02, 0.002);
  EXPECT_NEAR(cal.devices[0].frame_overhead_ms, 0.2, 1e-6);
  const std::vector<SimDevice> sim = calibrated_devices(cal);
  EXPECT_EQ(sim[1].launch_ms, cal.devices[1].launch_ms);
  EXPECT_EQ(sim[0].launch_ms, 0.0);
}

// Mean |error| per frame of `predicted` against `real`, frames from `warmup` on.
double mean_error(const Trace& real, const std::vector<SimFrame>& predicted, size_t warmup) {
  double e = 0;
  for (size_t f = warmup; f < real.frames.size(); ++f) {
    const double truth = frame_time_ms(real.frames[f]);
    e += std::abs(predicted[f].frame_ms - truth) / truth;
  }
  return e / double(real.frames.size() - warmup);
}

TEST(PooledCalibration, PredictsEachBalancerLeftOutWithinOnePercent) {
  const std::vector<SimDevice> devices = core_and_slow();
  const CostFn cost = banded_cost();
  std::vector<Trace> traces;
  for (const char* spec : {"hybrid", "queue:tile=16", "semi-static", "uniform:layout=strips"})
    traces.push_back(record(spec, devices, cost, 30));
  const TraceCalibration single = calibrate(traces[0], 3);
  const Trace single_net = net_trace(traces[0], single);
  const std::vector<SimDevice> single_sim = calibrated_devices(single);
  for (size_t k = 0; k < traces.size(); ++k) {
    std::vector<const Trace*> others;
    for (size_t r = 0; r < traces.size(); ++r)
      if (r != k) others.push_back(&traces[r]);
    const TraceCalibration cal = calibrate_pooled(others, 3);
    const std::vector<SimDevice> sim = calibrated_devices(cal);
    auto b1 = make_balancer(traces[k].balancer, 2), b2 = make_balancer(traces[k].balancer, 2);
    const double pooled = mean_error(
        traces[k], replay_trace(pooled_costs(others, cal), *b1, [&](int) { return sim; }), 3);
    EXPECT_LT(pooled, 0.01) << traces[k].balancer;
    // Calibrated on hybrid's trace alone, the balancers that give the slow device more
    // than hybrid does are predicted far worse.
    if (k == 0) continue;
    const double from_one =
        mean_error(traces[k], replay_trace(single_net, *b2, [&](int) { return single_sim; }), 3);
    EXPECT_GT(from_one, std::max(5 * pooled, 0.05)) << traces[k].balancer;
  }
}

TEST(PooledCalibration, CostsHoldEveryTracesItems) {
  const std::vector<SimDevice> devices = core_and_slow();
  const CostFn cost = banded_cost();
  const Trace a = record("hybrid", devices, cost, 6),
              b = record("queue:tile=16", devices, cost, 6);
  const Trace c = record("semi-static", devices, cost, 6);
  // The devices as they are (a calibration that learnt them exactly).
  TraceCalibration cal;
  cal.pooled = true;
  cal.devices.resize(2);
  cal.devices[0].item_overhead_ms = 0.02;
  cal.devices[0].frame_overhead_ms = 0.2;
  cal.devices[1].speed = 0.07;
  cal.devices[1].batching = true;
  cal.devices[1].launch_ms = 3.0;
  const Trace base = pooled_costs({&a, &b, &c}, cal);
  // Written and read back: every pixel of every frame covered once (read_trace checks).
  std::ostringstream out;
  write_trace(out, base);
  std::istringstream in(out.str());
  EXPECT_NO_THROW(read_trace(in));
  ASSERT_EQ(base.frames.size(), a.frames.size());
  double worst[2] = {0, 0};
  for (size_t f = 1; f < base.frames.size(); ++f) {
    const CostFn pooled = trace_cost(base, f, kShape);
    // Each trace's items cost in the pooled density what they cost net (their work), the
    // semi-static trace's column bands, the queue's tiles and the hybrid's row chunks
    // alike: the pieces' densities are worked out from all of them together (a mean of
    // the traces' densities would blur each by the others' coarser items, by 2.5%).
    for (const Trace* t : {&a, &b, &c}) {
      const Trace net = net_trace(*t, cal);
      for (size_t d = 0; d < 2; ++d)
        for (const ItemReport& r : net.frames[f].devices[d].items) {
          const double work = r.time_ms * net.devices[d].speed;
          worst[d] = std::max(worst[d], std::abs(pooled(r.item) / work - 1));
        }
    }
  }
  // The slow device's items, whose costs are its time less a launch, weigh least.
  EXPECT_LT(worst[0], 0.003);
  EXPECT_LT(worst[1], 0.02);
}

TEST(PooledCalibration, RefusesTracesThatDoNotMatch) {
  const std::vector<SimDevice> devices = core_and_slow();
  const CostFn cost = banded_cost();
  const Trace a = record("hybrid", devices, cost, 6), b = record("queue", devices, cost, 6);
  EXPECT_EQ(trace_mismatch(a, b, "the first"), "");
  const Trace shorter = record("queue", devices, cost, 5);
  EXPECT_EQ(trace_mismatch(a, shorter, "the first"), "has 5 frames, the first 6");
  const Trace three = record("queue", {devices[0], devices[1], devices[1]}, cost, 6);
  EXPECT_EQ(trace_mismatch(a, three, "the first"), "has 3 devices, the first 2");
  Trace renamed = b;
  renamed.devices[1].name = "opencl:1";
  EXPECT_EQ(trace_mismatch(a, renamed, "the first"), "has device 1 'opencl:1', the first 'sim 1'");
  Trace slower = b;
  slower.devices[0].speed = 0.5;  // an emulated speed: another device
  EXPECT_EQ(trace_mismatch(a, slower, "the first"),
            "has device 0 at emulated speed 0.5, the first at 1");
  Trace smaller = b;
  smaller.frames[2].shape.width = 80;
  EXPECT_EQ(trace_mismatch(a, smaller, "the first"),
            "has frames of 80x96 x 1 views, the first 160x96 x 1");
  EXPECT_THROW(calibrate_pooled({&a, &renamed}, 1), std::invalid_argument);
  EXPECT_THROW(calibrate_pooled({&a, &shorter}, 1), std::invalid_argument);
  EXPECT_THROW(calibrate_pooled({}, 1), std::invalid_argument);
  EXPECT_THROW(calibrate_pooled({&a, &b}, 6), std::invalid_argument);  // no frame left
  const TraceCalibration cal = calibrate_pooled({&a, &b}, 1);
  EXPECT_THROW(pooled_costs({&a, &three}, cal), std::invalid_argument);
}

}  // namespace pooled_calibration_test
}  // namespace multiray::balance
