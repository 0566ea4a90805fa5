#include "balance/sim_study.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "util/link.h"
#include "util/parse.h"
#include "util/result_encoding.h"

namespace multiray::balance {

namespace {

double number(const std::string& text, const std::string& what, double lo, double hi) {
  const double v = parse_number(text).value_or(NAN);
  if (!(v >= lo && v <= hi))
    throw std::invalid_argument(what + ": '" + text + "' is not a number in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

// The cost of every pixel of trace frame `k` at speed 1.
double frame_cost(const Trace& trace, size_t k) {
  double c = 0;
  for (size_t d = 0; d < trace.frames[k].devices.size(); ++d)
    for (const ItemReport& r : trace.frames[k].devices[d].items)
      c += r.time_ms * trace.devices[d].speed;
  return c;
}

}  // namespace

std::vector<double> device_speeds(const std::string& dist, int n, uint64_t seed) {
  if (n < 1 || n > 4096) throw std::invalid_argument("device count must be in 1..4096");
  const auto colon = dist.find(':');
  const std::string kind = dist.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : dist.substr(colon + 1);
  std::vector<double> s(size_t(n), 1.0);
  if (kind == "equal" && colon == std::string::npos) return s;
  if (kind == "linear") {
    const double lo = number(arg, "speeds linear:MIN", 1e-6, 1);
    for (int i = 0; i < n; ++i) s[size_t(i)] = n == 1 ? 1 : 1 - (1 - lo) * i / double(n - 1);
    return s;
  }
  if (kind == "random") {
    const double lo = number(arg, "speeds random:MIN", 1e-6, 1);
    std::mt19937_64 rng(seed ^ 0x5eedull);
    for (double& v : s) v = lo + (1 - lo) * double(rng() >> 11) * 0x1p-53;
    return s;
  }
  if (kind == "list") {
    std::vector<double> list;
    std::stringstream ss(arg);
    for (std::string item; std::getline(ss, item, '/');)
      list.push_back(number(item, "speeds list", 1e-6, 1));
    if (list.empty()) throw std::invalid_argument("speeds list: give at least one speed");
    for (int i = 0; i < n; ++i) s[size_t(i)] = list[size_t(i) % list.size()];
    return s;
  }
  throw std::invalid_argument("speeds '" + dist +
                              "' must be equal, linear:MIN, random:MIN or list:A/B/...");
}

SimLink simulated_link(const std::string& text) {
  const LinkSpec spec = parse_link(text);
  SimLink l;
  l.latency_ms = spec.latency_ms;
  l.mbit_per_s = spec.mbit_per_s;
  l.shared_master = spec.shared;
  return l;
}

double simulated_bytes_per_pixel(const std::string& encoding, double zstd_ratio) {
  if (encoding == "rgba8") return 4;
  ResultEncoding e{};
  try {
    e = parse_result_encoding(encoding);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("'" + encoding +
                                "' must be rgba8, float, half, float+zstd or half+zstd");
  }
  return result_bytes_per_pixel(e, zstd_ratio);  // throws for a ratio outside (0, 1]
}

double study_memory_bytes(const Trace& trace, int devices, int frames) {
  double tables = 0, largest = 0;
  for (const FrameStats& f : trace.frames) {
    const double pixels = double(f.shape.pixels());
    tables += 8 * pixels;
    largest = std::max(largest, pixels);
  }
  // Per device: SimDevice, DeviceFrameStats, the dispatcher's lists and a few ItemReports.
  constexpr double kDeviceBytes = 2048;
  return tables + 4 * largest + kDeviceBytes * devices + 8.0 * frames;
}

StudyResult run_study(const Trace& trace, const std::string& spec, const StudyConfig& cfg,
                      TraceCosts* costs) {
  if (cfg.speeds.empty()) throw std::invalid_argument("no devices to simulate");
  if (trace.frames.empty()) throw std::invalid_argument("the trace has no frames");
  const int n = int(cfg.speeds.size());
  auto balancer = make_balancer(spec, n);
  std::vector<SimDevice> devices(cfg.speeds.size());
  if (!(cfg.slowdown >= 1e-6 && cfg.slowdown <= 1e6))
    throw std::invalid_argument("slowdown must be in [1e-6, 1e6]");
  for (size_t i = 0; i < devices.size(); ++i) {
    devices[i].speed = cfg.speeds[i] / cfg.slowdown;
    devices[i].frame_noise = cfg.frame_noise;
  }
  const int frames = cfg.frames > 0 ? cfg.frames : int(trace.frames.size());
  if (cfg.warmup < 0 || cfg.warmup >= frames)
    throw std::invalid_argument("warm-up must be in 0.." + std::to_string(frames - 1));
  StudyResult r;
  r.balancer = balancer->spec();
  r.devices = n;
  r.frame_ms.reserve(size_t(frames));
  double actual = 0, ideal = 0;
  // Frame by frame: a study keeps 8 bytes per frame, not every frame's plan and stats.
  replay_trace_each(
      trace, *balancer, [&](int) { return devices; }, cfg.link, frames, cfg.seed,
      [&](int f, SimFrame&& sf) {
        r.frame_ms.push_back(sf.frame_ms);
        if (f < cfg.warmup) return;
        actual += sf.frame_ms;
        // Against the frame's own (noisy) speeds: the speeds without their noise made a
        // lucky frame look better than ideal (efficiencies above 1).
        ideal += frame_cost(trace, size_t(f) % trace.frames.size()) / sf.speed_sum;
        r.mean_imbalance += imbalance(sf.stats);
        r.mean_deviation += deviation(sf.stats);
      },
      costs);
  const int counted = frames - cfg.warmup;
  r.mean_frame_ms = actual / counted;
  r.mean_ideal_ms = ideal / counted;
  r.efficiency = actual > 0 ? ideal / actual : 0;
  r.mean_imbalance /= counted;
  r.mean_deviation /= counted;
  return r;
}

}  // namespace multiray::balance
