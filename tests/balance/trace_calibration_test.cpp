// Calibration of the simulator from a trace: traces made by the simulator with known
// fixed costs, contention and noise are calibrated back, and a trace of one balancer,
// calibrated, predicts the frame times of the others on the same devices.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "balance/trace_calibration.h"
#include "sim_harness.h"

namespace multiray::balance {
namespace trace_calibration_test {

const FrameShape kShape{160, 96, 1, {}};

// 0.06 to 0.54 µs a sample, the same within each eighth of the rows: a cost the
// calibration's cost map (a cost per sample for each of 8 bands of rows, docs/traces.md)
// represents exactly. (Cost varying within a band biases the fixed costs: on
// sim_harness's uneven_cost item costs of 0.05 and 0.13 ms came out as 0 and 0.06.)
CostFn banded_cost() {
  return pixel_cost(kShape, [](int, int, int y) {
    const int band = y * 8 / kShape.height;
    return 3e-4 * (1 + 0.8 * std::sin(6.28 * (band + 0.5) / 8));
  });
}

// A run of `spec` on `devices`, written by the trace writer and read back (with the
// balancer's `model` records when `models`).
Trace record(const std::string& spec, const std::vector<SimDevice>& devices, const CostFn& cost,
             int frames, uint64_t seed = 0, bool models = false) {
  auto balancer = make_balancer(spec, int(devices.size()));
  const auto run = simulate_run(
      *balancer, kShape, [&](int) { return devices; }, cost, frames, seed);
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

SimDevice device(double speed, double item_ms, double frame_ms, double contention = 0,
                 double noise = 0) {
  SimDevice d;
  d.speed = speed;
  d.item_overhead_ms = item_ms;
  d.frame_overhead_ms = frame_ms;
  d.contention = contention;
  d.frame_noise = noise;
  return d;
}

TEST(TraceCalibration, LearnsSpeedsAndFixedCostsBack) {
  // A CPU-like device and one half as fast with a dearer launch (the PoCL core).
  const std::vector<SimDevice> devices{device(1.0, 0.05, 0.3), device(0.5, 0.13, 0.8)};
  const Trace t = record("hybrid", devices, banded_cost(), 30);
  const TraceCalibration cal = calibrate(t, 3);
  ASSERT_EQ(cal.devices.size(), 2u);
  EXPECT_NEAR(cal.devices[0].speed, 1.0, 1e-9);  // the fastest is the unit
  EXPECT_NEAR(cal.devices[1].speed, 0.5, 0.01);
  for (size_t d = 0; d < 2; ++d) {
    EXPECT_TRUE(cal.devices[d].overhead_fitted) << d;
    EXPECT_NEAR(cal.devices[d].item_overhead_ms, devices[d].item_overhead_ms, 0.01) << d;
    EXPECT_NEAR(cal.devices[d].frame_overhead_ms, devices[d].frame_overhead_ms, 1e-6) << d;
  }
  EXPECT_FALSE(cal.contention_identified);  // hybrid's devices finish together
  EXPECT_EQ(cal.contention, 0.0);
  EXPECT_NEAR(cal.frame_noise, 0.0, 1e-3);
}

TEST(TraceCalibration, LearnsContentionFromDevicesThatRanAlone) {
  // A static split on a 3:1 pair: the fast device runs dry early and the slow one finishes
  // alone, faster than while both ran.
  const std::vector<SimDevice> devices{device(1.0, 0.02, 0.2, 0.15),
                                       device(0.33, 0.02, 0.2, 0.15)};
  const Trace t = record("uniform:layout=strips", devices, testing::flat_cost(kShape), 20);
  const TraceCalibration cal = calibrate(t, 2);
  EXPECT_TRUE(cal.contention_identified);
  EXPECT_GT(cal.alone_share, 0.1);
  EXPECT_NEAR(cal.contention, 0.15, 0.02);
  EXPECT_NEAR(cal.devices[1].speed, 0.33, 0.01);
  // Told the contention, the calibration keeps it.
  EXPECT_EQ(calibrate(t, 2, 0.4).contention, 0.4);
}

TEST(TraceCalibration, LearnsFrameNoise) {
  const std::vector<SimDevice> devices{device(1.0, 0.0, 0.0, 0, 0.1),
                                       device(0.5, 0.0, 0.0, 0, 0.1)};
  const Trace t = record("hybrid", devices, testing::flat_cost(kShape), 60, 7);
  EXPECT_NEAR(calibrate(t, 2).frame_noise, 0.1, 0.04);
}

TEST(TraceCalibration, NetTraceHoldsTheWorkAlone) {
  const std::vector<SimDevice> devices{device(1.0, 0.05, 0.3), device(0.5, 0.13, 0.8)};
  const Trace t = record("hybrid", devices, testing::flat_cost(kShape), 10);
  const TraceCalibration cal = calibrate(t, 1);
  const Trace net = net_trace(t, cal);
  // Every item's net time × speed is its work: 1 µs per sample.
  for (size_t f = 1; f < net.frames.size(); ++f)
    for (size_t d = 0; d < 2; ++d)
      for (const ItemReport& r : net.frames[f].devices[d].items)
        EXPECT_NEAR(r.time_ms * net.devices[d].speed, 1e-3 * r.samples,
                    2e-3 + 1e-2 * 1e-3 * r.samples);
}

TEST(TraceCalibration, TakesALaunchCostFromTheBalancersModel) {
  // A batching device (one launch per frame of its own list, the launch spread over its
  // items: rusticl's 45-75 ms, scaled) beside a core. Its items never show the launch as
  // a gap, and hybrid's chunks are too few to fit it per item; hybrid's model of the
  // device, in the trace, has it.
  SimDevice batching = device(0.5, 0, 0);
  batching.launch_ms = 1.5;
  const std::vector<SimDevice> devices{device(1.0, 0, 0), batching};
  const Trace t = record("hybrid", devices, testing::flat_cost(kShape), 30, 0, true);
  const TraceCalibration cal = calibrate(t, 3);
  EXPECT_NEAR(cal.devices[1].launch_ms, 1.5, 0.3);
  EXPECT_NEAR(cal.devices[1].speed, 0.5, 0.05);
  EXPECT_EQ(cal.devices[0].launch_ms, 0.0);
  EXPECT_EQ(calibrated_devices(cal)[1].launch_ms, cal.devices[1].launch_ms);
  // Without the model records the launch is seen as a slower device.
  const Trace bare = record("hybrid", devices, testing::flat_cost(kShape), 30);
  EXPECT_EQ(calibrate(bare, 3).devices[1].launch_ms, 0.0);
  EXPECT_LT(calibrate(bare, 3).devices[1].speed, 0.45);
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

TEST(TraceCalibration, PredictsOtherBalancersWithinOnePercent) {
  // Fixed costs a PoCL core pays (~0.13 ms a launch, wake-ups per frame), and contention
  // given (a hybrid trace cannot show it).
  const double contention = 0.08;
  const std::vector<SimDevice> devices{device(1.0, 0.05, 0.4, contention),
                                       device(0.5, 0.13, 0.9, contention)};
  const CostFn cost = banded_cost();
  const Trace cal_trace = record("hybrid", devices, cost, 30);
  const TraceCalibration cal = calibrate(cal_trace, 3, contention);
  const Trace net = net_trace(cal_trace, cal);
  const std::vector<SimDevice> sim = calibrated_devices(cal);
  for (const std::string spec : {"queue", "semi-static", "uniform"}) {
    const Trace real = record(spec, devices, cost, 30);
    auto b1 = make_balancer(real.balancer, 2), b2 = make_balancer(real.balancer, 2);
    const double calibrated =
        mean_error(real, replay_trace(net, *b1, [&](int) { return sim; }), 3);
    const double plain = mean_error(real, replay_trace(cal_trace, *b2), 3);
    EXPECT_LT(calibrated, 0.01) << spec;
    // Without calibration (fixed costs per frame and per item ignored, or counted in the
    // cost of every pixel) the prediction is clearly worse.
    EXPECT_GT(plain, std::max(2 * calibrated, 0.01)) << spec;
  }
}

}  // namespace trace_calibration_test
}  // namespace multiray::balance
