#include "balance/calibration_fit.h"

#include <algorithm>
#include <cmath>

#include "balance/trace_calibration.h"

namespace multiray::balance::calib {

namespace {

// Rounds of (fixed costs, cost maps) ↔ speeds, alternating least squares: it converges
// slowly (the maps and the speeds trade scale), so it runs until the speeds settle.
constexpr int kMaxRounds = 2000;
constexpr double kSettled = 1e-12;  // largest relative change of a speed in a round

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

double fixed_of(const Obs& o, const Fit& s) {
  double sum = 0;
  for (size_t u : o.fixed) sum += s.fixed[u];
  return sum;
}

// Given the speeds and contention, the fixed costs and every frame's cost map ρ (ms per
// sample at speed 1, per band of rows) that fit t = Σ fixed + slow·Σ_b samples_b·ρ_b / s_i
// best (least squares weighted by 1/t: times vary in proportion to their size). The fixed
// costs are common to all frames, ρ each frame's own: the maps are eliminated frame by
// frame (Schur complement), leaving a system for the fixed costs. A small ridge pulls each
// band towards its frame's mean cost (for bands nothing covers). Returns every
// observation's model cost Σ_b samples_b·ρ_b.
std::vector<double> fit_costs(const std::vector<Obs>& items, size_t frames, Fit& s) {
  const size_t n = s.speed.size(), m = s.fixed.size();
  if (n == 0 || m > (size_t(1) << 20)) return std::vector<double>(items.size(), 0.0);
  size_t bins = 0;
  for (const Obs& it : items)
    for (const auto& [b, w] : it.bins) bins = std::max(bins, size_t(b) + 1);
  std::vector<size_t> begin(frames + 1, items.size());
  for (size_t j = items.size(); j-- > 0;) begin[items[j].frame] = j;
  for (size_t f = frames; f-- > 0;) begin[f] = std::min(begin[f], begin[f + 1]);
  Matrix schur(m, std::vector<double>(m + 1, 0.0));  // [S | r]
  std::vector<Matrix> x_of(frames);                  // per frame: A_ff⁻¹ [A_fo | b_f]
  for (size_t f = 0; f < frames; ++f) {
    if (begin[f] == begin[f + 1]) continue;
    Matrix aff(bins, std::vector<double>(bins, 0.0)), afo(bins, std::vector<double>(m + 1, 0.0));
    double cost = 0, samples = 0;
    for (size_t j = begin[f]; j < begin[f + 1]; ++j) {
      const Obs& it = items[j];
      if (!(it.time > 0)) continue;
      const double omega = 1 / it.time, g = s.slow(it.busy) / s.speed[it.device];
      for (const auto& [b, w] : it.bins) {
        for (const auto& [b2, w2] : it.bins) aff[size_t(b)][size_t(b2)] += omega * g * w * g * w2;
        for (size_t u : it.fixed) afo[size_t(b)][u] += omega * g * w;
        afo[size_t(b)][m] += omega * g * w * it.time;
        samples += w;
      }
      for (size_t u : it.fixed) {
        for (size_t v : it.fixed) schur[u][v] += omega;
        schur[u][m] += omega * it.time;
      }
      cost += s.net(it);
    }
    double diagonal = 0;
    for (size_t b = 0; b < bins; ++b) diagonal += aff[b][b];
    const double ridge = 1e-6 * diagonal / double(bins) + 1e-300;
    const double mean = samples > 0 ? cost / samples : 0;
    for (size_t b = 0; b < bins; ++b) aff[b][b] += ridge, afo[b][m] += ridge * mean;
    x_of[f] = solve(aff, afo, 0);
    for (size_t i = 0; i < m; ++i)
      for (size_t k = 0; k <= m; ++k)
        for (size_t b = 0; b < bins; ++b) schur[i][k] -= afo[b][i] * x_of[f][b][k];
  }
  Matrix a(m, std::vector<double>(m)), r(m, std::vector<double>(1));
  double scale = 0;
  for (size_t i = 0; i < m; ++i) {
    for (size_t k = 0; k < m; ++k) a[i][k] = schur[i][k];
    r[i][0] = schur[i][m];
    scale = std::max(scale, std::abs(a[i][i]));
  }
  const Matrix o = solve(a, r, 1e-9 * scale);
  for (size_t i = 0; i < m; ++i) {
    s.fitted[i] = std::abs(a[i][i]) > 1e-9 * scale && o[i][0] > 0;
    s.fixed[i] = s.fitted[i] ? o[i][0] : 0.0;
  }
  s.maps.assign(frames, std::vector<double>(bins, 0.0));
  for (size_t f = 0; f < frames; ++f)
    for (size_t b = 0; b < bins && !x_of[f].empty(); ++b) {
      double rho = x_of[f][b][m];
      for (size_t i = 0; i < m; ++i) rho -= x_of[f][b][i] * s.fixed[i];
      s.maps[f][b] = rho;
    }
  std::vector<double> model(items.size(), 0.0);
  for (size_t j = 0; j < items.size(); ++j) {
    const Matrix& x = x_of[items[j].frame];
    for (const auto& [b, w] : items[j].bins) {
      double rho = x[size_t(b)][m];
      for (size_t i = 0; i < m; ++i) rho -= x[size_t(b)][i] * s.fixed[i];
      model[j] += w * rho;
    }
  }
  return model;
}

// Each device's speed from its observations' model costs, 1/s_i the slope through the
// origin of t − fixed against slow·c (weighted by 1/t); rescaled so the fastest is 1.
void fit_speeds(const std::vector<Obs>& items, const std::vector<double>& model, Fit& s) {
  std::vector<double> num(s.speed.size(), 0.0), den(s.speed.size(), 0.0);
  for (size_t j = 0; j < items.size(); ++j) {
    const Obs& it = items[j];
    if (!(it.time > 0)) continue;
    const double c = model[j] * s.slow(it.busy), omega = 1 / it.time;
    num[it.device] += omega * c * c;
    den[it.device] += omega * c * (it.time - fixed_of(it, s));
  }
  for (size_t i = 0; i < s.speed.size(); ++i)
    if (num[i] > 0 && den[i] > 0) s.speed[i] = num[i] / den[i];
  const double top = *std::max_element(s.speed.begin(), s.speed.end());
  if (top > 0)
    for (double& v : s.speed) v /= top;
}

// Contention from the observations that ran alone against those that ran beside others:
// per device, cost per model cost ρ_k of its observations started with k at work; ρ_k /
// ρ_1 − 1 = contention·(k − 1), fitted through the origin weighted by cost, over every
// device that ran alone on at least kMinAloneShare of its cost. False when none did.
bool fit_contention(const std::vector<Obs>& items, const std::vector<double>& model, const Fit& s,
                    double& contention, double& alone_share) {
  const size_t n = s.speed.size(), most = n + 1;
  Matrix spent(n, std::vector<double>(most, 0.0)), modelled = spent;
  double all = 0, alone = 0;
  for (size_t j = 0; j < items.size(); ++j) {
    const Obs& it = items[j];
    spent[it.device][size_t(it.busy)] +=
        std::max(it.time - fixed_of(it, s), 0.0) * s.speed[it.device];
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

// Per-frame speed noise: each device's cost per model cost frame by frame (each run's
// frames apart), ρ_if, varies as its own speed and (through the frame's cost map)
// everyone's; with a common variance σ² per device, Var ρ_i = σ²·((1 − π_i)² + Σ_{m≠i}
// π_m²) for cost shares π. Returned as the half-width √3·σ of a uniform noise.
double fit_noise(const std::vector<Obs>& items, const std::vector<double>& model, const Fit& s,
                 size_t frames_per_run, size_t runs) {
  const size_t n = s.speed.size(), frames = frames_per_run * runs;
  std::vector<double> spent(n * frames, 0.0), cost(n * frames, 0.0), share(n, 0.0);
  double all = 0;
  for (size_t j = 0; j < items.size(); ++j) {
    const Obs& it = items[j];
    const size_t f = it.run * frames_per_run + it.frame;
    spent[it.device * frames + f] += s.net(it);
    cost[it.device * frames + f] += model[j];
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

void add_bins(std::vector<std::pair<int, double>>& bins,
              const std::vector<std::pair<int, double>>& more) {
  std::vector<std::pair<int, double>> out;
  size_t i = 0, j = 0;
  while (i < bins.size() || j < more.size()) {
    if (j == more.size() || (i < bins.size() && bins[i].first < more[j].first))
      out.push_back(bins[i++]);
    else if (i == bins.size() || more[j].first < bins[i].first)
      out.push_back(more[j++]);
    else
      out.push_back({bins[i].first, bins[i].second + more[j].second}), ++i, ++j;
  }
  bins = std::move(out);
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double Fit::cost(size_t frame, const std::vector<std::pair<int, double>>& bins) const {
  double c = 0;
  if (frame < maps.size())
    for (const auto& [b, w] : bins)
      c += size_t(b) < maps[frame].size() ? w * maps[frame][size_t(b)] : 0.0;
  return c;
}

double Fit::net(const Obs& o) const {
  return std::max(o.time - fixed_of(o, *this), 0.0) * speed[o.device] / slow(o.busy);
}

Fit fit_observations(const std::vector<Obs>& obs, size_t n, size_t unknowns, size_t frames,
                     size_t runs, double contention) {
  Fit s;
  s.speed.assign(n, 1.0);
  s.fixed.assign(unknowns, 0.0);
  s.fitted.assign(unknowns, false);
  s.contention = contention >= 0 ? contention : 0.0;
  std::vector<double> model;
  for (int round = 0; round < kMaxRounds; ++round) {
    const std::vector<double> before = s.speed;
    model = fit_costs(obs, frames, s);
    fit_speeds(obs, model, s);
    double change = 0;
    for (size_t d = 0; d < n; ++d) change = std::max(change, std::abs(s.speed[d] / before[d] - 1));
    if (contention < 0)
      s.contention_identified = fit_contention(obs, model, s, s.contention, s.alone_share);
    if (change < kSettled) break;
  }
  model = fit_costs(obs, frames, s);
  double learnt = 0;
  if (contention >= 0) fit_contention(obs, model, s, learnt, s.alone_share);
  s.frame_noise = fit_noise(obs, model, s, frames, std::max<size_t>(runs, 1));
  return s;
}

}  // namespace multiray::balance::calib
