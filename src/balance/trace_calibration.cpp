#include "balance/trace_calibration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace multiray::balance {

namespace {

// Rounds of (fixed costs, cost maps) ↔ speeds, alternating least squares: it converges
// slowly (the maps and the speeds trade scale), so it runs until the speeds settle.
constexpr int kMaxRounds = 2000;
constexpr double kSettled = 1e-12;  // largest relative change of a speed in a round
constexpr int kBandsPerView = 8;    // the cost map: this many bands of rows per view, per frame

// One item as the calibration sees it.
struct Item {
  size_t device = 0, frame = 0;
  double time = 0;                           // recorded ms
  int busy = 1;                              // devices at work when it started, itself included
  std::vector<std::pair<int, double>> bins;  // (band, samples in it)
};

// The item's samples (or pixels when none were recorded) per band of rows.
std::vector<std::pair<int, double>> bins_of(const ItemReport& r, const FrameShape& shape) {
  const Rect& q = r.item.rect;
  const double area = std::max(double(q.area()), 1.0);
  const double samples = r.samples > 0 ? r.samples : area;
  std::vector<std::pair<int, double>> out;
  for (int y = q.y0; y < q.y1; ++y) {
    const int band = r.item.view * kBandsPerView + int(int64_t(y) * kBandsPerView / shape.height);
    const double w = samples * double(q.x1 - q.x0) / area;
    if (out.empty() || out.back().first != band)
      out.push_back({band, w});
    else
      out.back().second += w;
  }
  return out;
}

// Items of frames `from` on, with the devices at work at each one's start: a device's
// items run back to back after its frame overhead (time − Σ items), and a device is at
// work until its frame time (as SimDevice::contention counts). A device's launch cost
// `launch[d]` is taken out of its items in proportion to their times (as the OpenCL
// device apportions a launch), one launch per frame.
std::vector<Item> items_of(const Trace& trace, size_t from, const std::vector<double>& launch) {
  std::vector<Item> out;
  for (size_t f = from; f < trace.frames.size(); ++f) {
    const FrameStats& fs = trace.frames[f];
    for (size_t d = 0; d < fs.devices.size(); ++d) {
      const DeviceFrameStats& dev = fs.devices[d];
      double sum = 0;
      for (const ItemReport& r : dev.items) sum += r.time_ms;
      const double keep = launch[d] > 0 && sum > 0 ? std::max(sum - launch[d], 0.0) / sum : 1.0;
      double start = std::max(dev.time_ms - sum, 0.0);
      for (const ItemReport& r : dev.items) {
        int busy = 0;
        for (const DeviceFrameStats& other : fs.devices)
          busy += other.alive && !other.items.empty() && other.time_ms > start;
        out.push_back({d, f, r.time_ms * keep, std::max(busy, 1), bins_of(r, fs.shape)});
        start += r.time_ms;
      }
    }
  }
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Device d's frame times (frames `from` on that it rendered in) and the gaps between
// them and its items (its fixed cost per frame outside any item).
void frame_times(const Trace& trace, size_t from, size_t d, std::vector<double>& times,
                 std::vector<double>& gaps) {
  for (size_t f = from; f < trace.frames.size(); ++f) {
    const DeviceFrameStats& fd = trace.frames[f].devices[d];
    if (fd.items.empty()) continue;
    double sum = 0;
    for (const ItemReport& r : fd.items) sum += r.time_ms;
    times.push_back(fd.time_ms);
    gaps.push_back(std::max(fd.time_ms - sum, 0.0));
  }
}

// The launch cost inside device d's items, from the balancer's last determined model of
// it (frames `from` on): its fixed cost per frame F when F is clear of noise (over two
// standard errors), at least kLaunchShare of the device's median frame, and not in the
// gaps between its items (median gap under F / 2); F less that gap. Else 0.
constexpr double kLaunchShare = 0.05;
double launch_of(const Trace& trace, size_t from, size_t d) {
  const DeviceCostModel* last = nullptr;
  for (size_t f = from; f < trace.models.size(); ++f)
    if (d < trace.models[f].size() && trace.models[f][d].determined) last = &trace.models[f][d];
  if (!last || !(last->fixed_ms > 2 * last->fixed_sigma) || !(last->fixed_ms > 0)) return 0;
  std::vector<double> times, gaps;
  frame_times(trace, from, d, times, gaps);
  const double gap = median(gaps);
  if (times.empty() || !(last->fixed_ms >= kLaunchShare * median(times)) ||
      !(gap < last->fixed_ms / 2))
    return 0;
  return last->fixed_ms - gap;
}

using Matrix = std::vector<std::vector<double>>;

// Solves a·x = b for each column of b (Gaussian elimination, partial pivoting); a pivot
// below `tiny` leaves that unknown at 0.
Matrix solve(Matrix a, Matrix b, double tiny) {
  const size_t n = a.size(), m = b.empty() ? 0 : b[0].size();
  std::vector<bool> dead(n, false);
  for (size_t c = 0; c < n; ++c) {
    size_t p = c;
    for (size_t r = c + 1; r < n; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
    std::swap(a[c], a[p]), std::swap(b[c], b[p]);
    if (!(std::abs(a[c][c]) > tiny)) {
      dead[c] = true;
      continue;
    }
    for (size_t r = c + 1; r < n; ++r) {
      const double k = a[r][c] / a[c][c];
      if (k == 0) continue;
      for (size_t j = c; j < n; ++j) a[r][j] -= k * a[c][j];
      for (size_t j = 0; j < m; ++j) b[r][j] -= k * b[c][j];
    }
  }
  Matrix x(n, std::vector<double>(m, 0.0));
  for (size_t c = n; c-- > 0;) {
    if (dead[c]) continue;
    for (size_t j = 0; j < m; ++j) {
      double v = b[c][j];
      for (size_t k = c + 1; k < n; ++k) v -= a[c][k] * x[k][j];
      x[c][j] = v / a[c][c];
    }
  }
  return x;
}

struct State {
  std::vector<double> speed, overhead;
  double contention = 0;
  std::vector<bool> fitted;
  double slow(int busy) const { return 1 + contention * (busy - 1); }
  double net(const Item& it) const {
    return std::max(it.time - overhead[it.device], 0.0) * speed[it.device] / slow(it.busy);
  }
};

// Given the speeds and contention, the fixed costs o_i and every frame's cost map ρ (ms
// per sample at speed 1, per band of rows) that fit t = o_i + slow·Σ_b samples_b·ρ_b / s_i
// best (least squares weighted by 1/t: times vary in proportion to their size). o_i is
// common to all frames, ρ each frame's own: the maps are eliminated frame by frame (Schur
// complement), leaving an n×n system for the o_i. A small ridge pulls each band towards
// its frame's mean cost (for bands no item covers). Returns every item's model cost
// Σ_b samples_b·ρ_b.
std::vector<double> fit_costs(const std::vector<Item>& items, size_t frames, State& s) {
  const size_t n = s.speed.size();
  if (n == 0 || n > (size_t(1) << 20)) return std::vector<double>(items.size(), 0.0);
  size_t bins = 0;
  for (const Item& it : items)
    for (const auto& [b, w] : it.bins) bins = std::max(bins, size_t(b) + 1);
  std::vector<size_t> begin(frames + 1, items.size());
  for (size_t j = items.size(); j-- > 0;) begin[items[j].frame] = j;
  for (size_t f = frames; f-- > 0;) begin[f] = std::min(begin[f], begin[f + 1]);
  Matrix schur(n, std::vector<double>(n + 1, 0.0));  // [S | r]
  std::vector<Matrix> x_of(frames);                  // per frame: A_ff⁻¹ [A_fo | b_f]
  for (size_t f = 0; f < frames; ++f) {
    if (begin[f] == begin[f + 1]) continue;
    Matrix aff(bins, std::vector<double>(bins, 0.0)), afo(bins, std::vector<double>(n + 1, 0.0));
    double cost = 0, samples = 0;
    for (size_t j = begin[f]; j < begin[f + 1]; ++j) {
      const Item& it = items[j];
      if (!(it.time > 0)) continue;
      const double omega = 1 / it.time, g = s.slow(it.busy) / s.speed[it.device];
      for (const auto& [b, w] : it.bins) {
        for (const auto& [b2, w2] : it.bins) aff[size_t(b)][size_t(b2)] += omega * g * w * g * w2;
        afo[size_t(b)][it.device] += omega * g * w;
        afo[size_t(b)][n] += omega * g * w * it.time;
        samples += w;
      }
      schur[it.device][it.device] += omega;
      schur[it.device][n] += omega * it.time;
      cost += s.net(it);
    }
    double diagonal = 0;
    for (size_t b = 0; b < bins; ++b) diagonal += aff[b][b];
    const double ridge = 1e-6 * diagonal / double(bins) + 1e-300;
    const double mean = samples > 0 ? cost / samples : 0;
    for (size_t b = 0; b < bins; ++b) aff[b][b] += ridge, afo[b][n] += ridge * mean;
    x_of[f] = solve(aff, afo, 0);
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k <= n; ++k)
        for (size_t b = 0; b < bins; ++b) schur[i][k] -= afo[b][i] * x_of[f][b][k];
  }
  Matrix a(n, std::vector<double>(n)), r(n, std::vector<double>(1));
  double scale = 0;
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < n; ++k) a[i][k] = schur[i][k];
    r[i][0] = schur[i][n];
    scale = std::max(scale, std::abs(a[i][i]));
  }
  const Matrix o = solve(a, r, 1e-9 * scale);
  for (size_t i = 0; i < n; ++i) {
    s.fitted[i] = std::abs(a[i][i]) > 1e-9 * scale && o[i][0] > 0;
    s.overhead[i] = s.fitted[i] ? o[i][0] : 0.0;
  }
  std::vector<double> model(items.size(), 0.0);
  for (size_t j = 0; j < items.size(); ++j) {
    const Matrix& x = x_of[items[j].frame];
    for (const auto& [b, w] : items[j].bins) {
      double rho = x[size_t(b)][n];
      for (size_t i = 0; i < n; ++i) rho -= x[size_t(b)][i] * s.overhead[i];
      model[j] += w * rho;
    }
  }
  return model;
}

// Each device's speed from its items' model costs, 1/s_i the slope through the origin
// of t − o_i against slow·c (weighted by 1/t); rescaled so the fastest is 1.
void fit_speeds(const std::vector<Item>& items, const std::vector<double>& model, State& s) {
  std::vector<double> num(s.speed.size(), 0.0), den(s.speed.size(), 0.0);
  for (size_t j = 0; j < items.size(); ++j) {
    const Item& it = items[j];
    if (!(it.time > 0)) continue;
    const double c = model[j] * s.slow(it.busy), omega = 1 / it.time;
    num[it.device] += omega * c * c;
    den[it.device] += omega * c * (it.time - s.overhead[it.device]);
  }
  for (size_t i = 0; i < s.speed.size(); ++i)
    if (num[i] > 0 && den[i] > 0) s.speed[i] = num[i] / den[i];
  const double top = *std::max_element(s.speed.begin(), s.speed.end());
  if (top > 0)
    for (double& v : s.speed) v /= top;
}

// Contention from the items that ran alone against those that ran beside others: per
// device, cost per model cost ρ_k of its items started with k at work; ρ_k / ρ_1 − 1 =
// contention·(k − 1), fitted through the origin weighted by cost, over every device that
// ran alone on at least kMinAloneShare of its cost. Returns false when none did.
bool fit_contention(const std::vector<Item>& items, const std::vector<double>& model,
                    const State& s, double& contention, double& alone_share) {
  const size_t n = s.speed.size(), most = n + 1;
  Matrix spent(n, std::vector<double>(most, 0.0)), modelled = spent;
  double all = 0, alone = 0;
  for (size_t j = 0; j < items.size(); ++j) {
    const Item& it = items[j];
    spent[it.device][size_t(it.busy)] +=
        std::max(it.time - s.overhead[it.device], 0.0) * s.speed[it.device];
    modelled[it.device][size_t(it.busy)] += model[j];
    all += model[j];
    alone += it.busy == 1 ? model[j] : 0;
  }
  alone_share = all > 0 ? alone / all : 0;
  double num = 0, den = 0;
  for (size_t d = 0; d < n; ++d) {
    double total = 0;
    for (double c : modelled[d]) total += c;
    if (!(modelled[d][1] >= kMinAloneShare * total) || !(spent[d][1] > 0)) continue;
    const double rho1 = spent[d][1] / modelled[d][1];
    for (size_t k = 2; k < most; ++k) {
      if (!(modelled[d][k] > 0)) continue;
      const double excess = spent[d][k] / modelled[d][k] / rho1 - 1;
      // Weighted by the smaller of the two costs compared: both must be well measured.
      const double w = std::min(modelled[d][1], modelled[d][k]) * double(k - 1);
      num += w * excess, den += w * double(k - 1);
    }
  }
  if (!(den > 0)) return false;
  // At most 1 (two devices at work: each at half speed): beyond, the evidence (a few
  // items, or cost differences the map could not see) is not believed.
  contention = std::clamp(num / den, 0.0, 1.0);
  return true;
}

// Per-frame speed noise: each device's cost per model cost frame by frame, ρ_if, varies
// as its own speed and (through the frame's cost map) everyone's; with a common variance
// σ² per device, Var ρ_i = σ²·((1 − π_i)² + Σ_{m≠i} π_m²) for cost shares π. Returned as
// the half-width √3·σ of a uniform noise.
double fit_noise(const std::vector<Item>& items, const std::vector<double>& model, const State& s,
                 size_t frames) {
  const size_t n = s.speed.size();
  std::vector<double> spent(n * frames, 0.0), cost(n * frames, 0.0), share(n, 0.0);
  double all = 0;
  for (size_t j = 0; j < items.size(); ++j) {
    const Item& it = items[j];
    spent[it.device * frames + it.frame] += s.net(it);
    cost[it.device * frames + it.frame] += model[j];
    share[it.device] += model[j];
    all += model[j];
  }
  if (!(all > 0)) return 0;
  for (double& p : share) p /= all;
  double variance = 0, scale = 0;
  for (size_t d = 0; d < n; ++d) {
    std::vector<double> rho;
    for (size_t f = 0; f < frames; ++f)
      if (cost[d * frames + f] > 0) rho.push_back(spent[d * frames + f] / cost[d * frames + f]);
    if (rho.size() < 3) continue;
    double mean = 0, sq = 0;
    for (double r : rho) mean += r;
    mean /= double(rho.size());
    for (double r : rho) sq += (r - mean) * (r - mean);
    variance += sq / double(rho.size() - 1) / (mean * mean);
    double k = (1 - share[d]) * (1 - share[d]);
    for (size_t m = 0; m < n; ++m) k += m != d ? share[m] * share[m] : 0;
    scale += k;
  }
  return scale > 0 ? std::sqrt(3 * variance / scale) : 0;
}

}  // namespace

TraceCalibration calibrate(const Trace& trace, int warmup, double contention) {
  const size_t from = size_t(std::max(warmup, 0));
  if (from >= trace.frames.size())
    throw std::invalid_argument("the trace has no frames after the warm-up");
  const size_t n = trace.devices.size(), frames = trace.frames.size();
  TraceCalibration cal;
  cal.devices.resize(n);
  cal.frames = int(frames - from);
  std::vector<double> launch(n, 0.0);
  for (size_t d = 0; d < n; ++d) launch[d] = launch_of(trace, from, d);
  const std::vector<Item> items = items_of(trace, from, launch);
  State s{std::vector<double>(n, 1.0), std::vector<double>(n, 0.0),
          contention >= 0 ? contention : 0.0, std::vector<bool>(n, false)};
  std::vector<double> model;
  for (int round = 0; round < kMaxRounds; ++round) {
    const std::vector<double> before = s.speed;
    model = fit_costs(items, frames, s);
    fit_speeds(items, model, s);
    double change = 0;
    for (size_t d = 0; d < n; ++d) change = std::max(change, std::abs(s.speed[d] / before[d] - 1));
    if (contention < 0)
      cal.contention_identified = fit_contention(items, model, s, s.contention, cal.alone_share);
    if (change < kSettled) break;
  }
  model = fit_costs(items, frames, s);
  double learnt = 0;
  if (contention >= 0) fit_contention(items, model, s, learnt, cal.alone_share);
  cal.contention = s.contention;
  cal.frame_noise = fit_noise(items, model, s, frames);
  for (size_t d = 0; d < n; ++d) {
    CalibratedDevice& dev = cal.devices[d];
    dev.speed = s.speed[d];
    dev.item_overhead_ms = s.overhead[d];
    dev.overhead_fitted = s.fitted[d];
    dev.launch_ms = launch[d];
    std::vector<double> times, gaps;
    frame_times(trace, from, d, times, gaps);
    for (const Item& it : items) dev.items += it.device == d;
    dev.frame_overhead_ms = median(gaps);
  }
  return cal;
}

std::vector<SimDevice> calibrated_devices(const TraceCalibration& cal, double noise) {
  std::vector<SimDevice> out;
  for (const CalibratedDevice& d : cal.devices) {
    SimDevice s;
    s.speed = d.speed;
    s.item_overhead_ms = d.item_overhead_ms;
    s.frame_overhead_ms = d.frame_overhead_ms;
    s.launch_ms = d.launch_ms;
    s.contention = cal.contention;
    s.frame_noise = noise;
    out.push_back(s);
  }
  return out;
}

Trace net_trace(const Trace& trace, const TraceCalibration& cal) {
  Trace out = trace;
  for (size_t d = 0; d < out.devices.size(); ++d) out.devices[d].speed = cal.devices[d].speed;
  State s{std::vector<double>(cal.devices.size(), 1.0), {}, cal.contention, {}};
  std::vector<double> launch;
  for (const CalibratedDevice& d : cal.devices) {
    s.overhead.push_back(d.item_overhead_ms);
    launch.push_back(d.launch_ms);
  }
  const std::vector<Item> items = items_of(trace, 0, launch);
  size_t next = 0;  // items_of lists the items in the trace's order
  for (FrameStats& f : out.frames)
    for (DeviceFrameStats& dev : f.devices)
      for (ItemReport& r : dev.items) r.time_ms = r.busy_ms = s.net(items[next++]);
  return out;
}

}  // namespace multiray::balance
