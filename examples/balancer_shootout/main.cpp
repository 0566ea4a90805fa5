// Runs balancers through synthetic scenarios with multiray::balance::simulate and prints
// one table: efficiency (ideal frame time / actual, mean over frames after a warm-up;
// higher is better) for most scenarios, the imbalance of the frame of a speed change and
// the mean deviation with irregular sample counts (lower is better). Deterministic: the
// same numbers on every machine.
//
// Usage: balancer_shootout [SPEC ...]   (default: uniform static queue semi-static dlb
// hybrid; any spec `multiray render --help` lists, e.g. hybrid:bands=1)
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include <multiray/balance.h>

namespace mb = multiray::balance;

struct Scenario {
  const char* name;
  mb::FrameShape shape;
  std::vector<double> speeds;
  double noise = 0.02, overhead_ms = 0;
  // Cost per sample (ms at speed 1) of a pixel in a frame; per-frame sample counts.
  std::function<double(int f, int v, int x, int y)> cost;
  std::function<void(int f, mb::FrameShape&)> samples;
  std::function<void(int f, std::vector<mb::SimDevice>&)> perturb;
  int frames = 60, from = 10;
  enum { Efficiency, ChangeFrame, Deviation } metric = Efficiency;
};

double run(const std::string& spec, const Scenario& s) {
  auto balancer = mb::make_balancer(spec, int(s.speeds.size()));
  double total_speed = 0, sum = 0;
  for (double v : s.speeds) total_speed += v;
  for (int f = 0; f < s.frames; ++f) {
    mb::FrameShape shape = s.shape;
    if (s.samples) s.samples(f, shape);
    const mb::CostFn cost =
        mb::pixel_cost(shape, [&](int v, int x, int y) { return s.cost(f, v, x, y); });
    std::vector<mb::SimDevice> devices(s.speeds.size());
    for (size_t i = 0; i < devices.size(); ++i)
      devices[i].speed = s.speeds[i], devices[i].frame_noise = s.noise,
      devices[i].item_overhead_ms = s.overhead_ms;
    if (s.perturb) s.perturb(f, devices);
    const mb::FrameStats stats =
        mb::simulate(balancer->plan(shape, f), shape, devices, cost, f, 7);
    balancer->update(stats);
    if (s.metric == Scenario::ChangeFrame && f == s.from) return mb::imbalance(stats);
    if (f < s.from) continue;
    if (s.metric == Scenario::Deviation) {
      sum += mb::deviation(stats);
    } else {
      double work = 0;
      for (int v = 0; v < shape.views; ++v)
        work += cost(mb::WorkItem{mb::Rect{0, 0, shape.width, shape.height}, v});
      sum += work / total_speed / mb::frame_time_ms(stats);
    }
  }
  return sum / (s.frames - s.from);
}

int main(int argc, char** argv) {
  std::vector<std::string> specs = {"uniform", "static", "queue", "semi-static", "dlb", "hybrid"};
  if (argc > 1) specs.assign(argv + 1, argv + argc);
  for (const std::string& spec : specs) {
    if (spec == "--help" || spec == "-h") {
      std::printf(
          "Usage: balancer_shootout [SPEC ...]\nRuns balancers (default: uniform static queue "
          "semi-static dlb hybrid) through ten simulated scenarios and prints one table.\n");
      return 0;
    }
    try {
      mb::make_balancer(spec, 2);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "balancer_shootout: error: %s\n", e.what());
      return 2;
    }
  }
  const mb::FrameShape hd{640, 360, 1, {}}, small{320, 180, 1, {}};
  auto flat = [](int, int, int, int) { return 1e-3; };
  auto floor_heavy = [](int, int, int, int y) { return y > 240 ? 6e-3 : 1e-3; };
  auto hotspot = [](double speed) {
    return [speed](int f, int, int x, int y) {
      const double c = 90 + 72 * std::sin(f * speed);
      return 1e-3 * (1 + 8 * std::exp(-std::pow((y - c) / 20.0, 2)) * (x > 160 ? 1.5 : 0.5));
    };
  };
  auto edges = [](int f, mb::FrameShape& s) {  // adaptive sampling: 5 spp on a moving edge
    s.pixel_weight.assign(size_t(s.width * s.height), 1.0f);
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x)
        if (std::abs(x - 160 - 100 * std::sin(f * 0.1) - 0.5 * y) < 20)
          s.pixel_weight[size_t(y * s.width + x)] = 5;
  };
  auto drop_at_50 = [](int f, std::vector<mb::SimDevice>& d) {
    if (f >= 50) d[0].speed /= 2;
  };
  auto drop_mid = [](int f, std::vector<mb::SimDevice>& d) {
    if (f == 50) d[0].change_at_ms = 25, d[0].speed_after = d[0].speed / 3;
    if (f > 50) d[0].speed /= 3;
  };
  std::vector<Scenario> scenarios = {
      {"3:1, flat cost", hd, {3, 1}, 0.02, 0, flat},
      {"3:1, floor 6x dearer", hd, {3, 1}, 0.02, 0, floor_heavy},
      {"3:1, +-5% noise", hd, {3, 1}, 0.05, 0, floor_heavy},
      {"5 devices, slow hotspot", small, {4, 1, 2, 0.5, 3}, 0.03, 0, hotspot(0.02)},
      {"5 devices, fast hotspot", small, {4, 1, 2, 0.5, 3}, 0.03, 0, hotspot(0.15)},
      {"3:1, 0.05 ms per item", small, {3, 1}, 0.03, 0.05, hotspot(0.15)},
      {"3x3 views, 3:1",
       mb::FrameShape{160, 90, 9, {}},
       {3, 1},
       0.02,
       0,
       [](int, int v, int, int y) { return 1e-3 * (1 + v % 3 + (y > 60 ? 4 : 0)); }},
  };
  Scenario step{"lambda at drop to 0.5", hd, {3, 1}, 0.02, 0, floor_heavy};
  step.perturb = drop_at_50, step.from = 50, step.metric = Scenario::ChangeFrame;
  Scenario mid = step;
  mid.name = "lambda, 3x slower mid-frame", mid.perturb = drop_mid;
  Scenario irregular{"deviation, adaptive spp", small, {4, 3, 2, 1}, 0.01, 0, flat, edges};
  irregular.metric = Scenario::Deviation;
  scenarios.insert(scenarios.end(), {step, mid, irregular});

  std::printf("%-34s", "scenario");
  for (const auto& spec : specs) std::printf(" %11.11s", spec.c_str());
  std::printf("\n");
  for (size_t k = 0; k < scenarios.size(); ++k) {
    const Scenario& s = scenarios[k];
    const bool higher = s.metric == Scenario::Efficiency;
    std::printf("%-34s", (std::string(s.name) + (higher ? " (^)" : " (v)")).c_str());
    for (const auto& spec : specs) {
      std::fprintf(stderr, "\r[%zu/%zu] %s ", k + 1, scenarios.size(), spec.c_str());
      std::printf(" %11.3f", run(spec, s));
    }
    std::fprintf(stderr, "\r\033[K");
    std::printf("\n");
  }
  std::printf("(^: efficiency, higher is better; v: imbalance or deviation, lower is better)\n");
}
