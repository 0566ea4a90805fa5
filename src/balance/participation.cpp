#include "balance/participation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace multiray::balance {

void DeviceCostFit::add(double work, double time_ms) {
  if (!(work >= 0) || !(time_ms > 0) || !std::isfinite(work) || !std::isfinite(time_ms)) return;
  w_ *= memory_, x_ *= memory_, y_ *= memory_;
  xx_ *= memory_, xy_ *= memory_, yy_ *= memory_, w2_ *= memory_ * memory_;
  w_ += 1, x_ += work, y_ += time_ms;
  xx_ += work * work, xy_ += work * time_ms, yy_ += time_ms * time_ms, w2_ += 1;
  ++frames_;
}

void DeviceCostFit::rescale_work(double r) {
  if (!(r > 0) || !std::isfinite(r)) return;
  x_ *= r, xx_ *= r * r, xy_ *= r;
}

DeviceCostModel DeviceCostFit::model() const {
  DeviceCostModel m;
  if (!(w_ > 0)) return m;
  const double mx = x_ / w_, my = y_ / w_;
  m.speed = mx / my;  // no fixed cost: the mean speed
  // Weighted spreads about the means; the work must vary by 10% (coefficient of
  // variation) or intercept and slope cannot be told apart.
  const double sxx = std::max(xx_ - w_ * mx * mx, 0.0), sxy = xy_ - w_ * mx * my;
  const double syy = std::max(yy_ - w_ * my * my, 0.0);
  const double n_eff = w_ * w_ / w2_;
  if (x_ == 0 && frames_ >= 3 && n_eff > 1.5) {
    // Started every time and given nothing to do (all stolen while it was starting): its
    // time is all fixed cost; its speed is unknown (0).
    m.speed = 0;
    m.fixed_ms = my;
    m.fixed_sigma = std::sqrt(syy / w_ / (n_eff - 1));
    m.determined = true;
    return m;
  }
  if (frames_ < 3 || n_eff <= 2.5 || !(sxx / w_ > 0.01 * mx * mx)) return m;
  const double slope = sxy / sxx;
  if (!(slope > 0) || !std::isfinite(slope)) return m;
  const double intercept = my - slope * mx;
  // Residual variance per frame, then the intercept's standard error as in ordinary
  // least squares with n_eff frames.
  const double residual = std::max(syy - slope * sxy, 0.0) / w_ * n_eff / (n_eff - 2);
  const double var = residual * (1 / n_eff + mx * mx / (sxx / w_ * n_eff));
  if (!std::isfinite(intercept) || !std::isfinite(var)) return m;
  m.speed = 1 / slope;
  m.fixed_ms = std::max(intercept, 0.0);
  m.fixed_sigma = std::sqrt(var);
  m.determined = true;
  return m;
}

namespace {
// The fixed cost the frames show clearly: two standard errors below the fit's (a fit
// over frames that mixed contended and uncontended times can claim a large F with a
// larger error).
double judged_fixed(const DeviceCostModel& m) {
  return m.determined ? std::max(m.fixed_ms - 2 * m.fixed_sigma, 0.0) : 0.0;
}
bool judged(const DeviceCostModel& m) {
  return m.determined || m.contention < ParticipationTracker::kContentionSeen;
}
}  // namespace

double predicted_frame_ms(const std::vector<DeviceCostModel>& models,
                          const std::vector<bool>& take, double total) {
  // T = (total + Σ s_i F_i) / Σ s_i over the taken devices, each s_i slowed by the others'
  // contention; a device whose F_i is above that T would get no work, so it is dropped
  // from the sum and T recomputed.
  std::vector<size_t> in;
  double slow = 1;  // product of the taken devices' contention
  for (size_t i = 0; i < models.size() && i < take.size(); ++i)
    if (take[i] && models[i].speed > 0) {
      in.push_back(i);
      slow *= std::clamp(models[i].contention, 0.05, 1.0);
    }
  auto speed = [&](size_t i) {
    return models[i].speed * slow / std::clamp(models[i].contention, 0.05, 1.0);
  };
  std::sort(in.begin(), in.end(),
            [&](size_t a, size_t b) { return judged_fixed(models[a]) < judged_fixed(models[b]); });
  double best = std::numeric_limits<double>::infinity(), s = 0, sf = 0;
  for (size_t i : in) {
    const double f = judged_fixed(models[i]);
    if (f >= best) break;
    s += speed(i), sf += speed(i) * f;
    best = (total + sf) / s;
  }
  // A device with fixed cost above T still waits for its report: T is at least its F.
  for (size_t i : in) best = std::max(best, judged_fixed(models[i]));
  return best;
}

std::vector<bool> choose_participants(const std::vector<DeviceCostModel>& models,
                                      const std::vector<bool>& eligible, double total,
                                      double margin) {
  const size_t n = models.size();
  std::vector<bool> take(n, false);
  // Judged devices by fixed cost: those whose fit is determined, and those whose cost to
  // the others has been measured (contention below 1), judged at a fixed cost of 0 if the
  // fit is not determined. The others are always taken.
  std::vector<size_t> order;
  for (size_t i = 0; i < n; ++i) {
    if (i >= eligible.size() || !eligible[i]) continue;
    if (judged(models[i]) && models[i].speed > 0)
      order.push_back(i);
    else
      take[i] = true;
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return judged_fixed(models[a]) < judged_fixed(models[b]);
  });
  // Grow the set device by device in that order while each saves more than `margin`.
  const bool any_taken = std::find(take.begin(), take.end(), true) != take.end();
  double t = any_taken ? predicted_frame_ms(models, take, total)
                       : std::numeric_limits<double>::infinity();
  for (size_t i : order) {
    take[i] = true;
    const double with = predicted_frame_ms(models, take, total);
    if (std::isfinite(t) && !(with < t * (1 - margin))) {
      take[i] = false;
      continue;
    }
    t = with;
  }
  return take;
}

std::string left_out_reason(const DeviceCostModel& model, double frame_ms, double margin) {
  char line[128];
  if (model.fixed_ms >= frame_ms)
    std::snprintf(line, sizeof line, "%.0f ms fixed per frame against a %.0f ms frame",
                  model.fixed_ms, frame_ms);
  else
    std::snprintf(line, sizeof line,
                  "it would save less than %.0f%% of a %.0f ms frame (%.0f ms fixed per frame)",
                  100 * margin, frame_ms, model.fixed_ms);
  return line;
}

ParticipationTracker::ParticipationTracker(int devices, const Options& options)
    : opt_(options),
      fit_(size_t(std::max(devices, 0))),
      out_(fit_.size(), false),
      since_(fit_.size(), 0),
      every_(fit_.size(), std::max(options.probe, 1)),
      probes_(fit_.size(), 0),
      since_in_(fit_.size(), 0),
      every_in_(fit_.size(), std::min(kFirstRest, std::max(options.probe, 1))),
      rests_(fit_.size(), 0),
      log_contention_(fit_.size(), 0.0),
      contention_samples_(fit_.size(), 0),
      last_took_(fit_.size(), false),
      last_speed_(fit_.size(), 0.0) {}

ParticipationTracker::Decision ParticipationTracker::decide(const std::vector<bool>& alive,
                                                            double total,
                                                            const std::vector<double>& speed) {
  const size_t n = fit_.size();
  Decision d;
  d.rest.assign(n, false);
  d.probe.assign(n, 0.0);
  d.reason.assign(n, "");
  for (size_t i = 0; i < n; ++i) {
    d.models.push_back(fit_[i].model());
    const bool known = d.models[i].determined && d.models[i].speed > 0;
    if (!known && i < speed.size() && speed[i] > 0) d.models[i].speed = speed[i];
    if (contention_samples_[i] > 0)
      d.models[i].contention = std::clamp(std::exp(log_contention_[i]), 0.05, 1.0);
  }
  if (!opt_.leave) return d;
  // A left-out device comes back only once its fit says it pays.
  std::vector<bool> eligible(n, false);
  bool any = false;
  for (size_t i = 0; i < n && i < alive.size(); ++i)
    any |= eligible[i] = alive[i] && !(out_[i] && !judged(d.models[i]));
  if (!any) eligible = alive;
  const std::vector<bool> take = choose_participants(d.models, eligible, total, opt_.margin);
  d.predicted_ms = predicted_frame_ms(d.models, take, total);
  // One device rested to measure per frame (a contention sample needs exactly one change
  // from the frame before, and someone must work): the others wait for a later frame.
  bool measuring = false;
  for (size_t i = 0; i < n && i < alive.size(); ++i) {
    if (alive[i] && take[i] && rest_to_measure(i, d, take, total, !measuring)) {
      measuring = true;
      d.rest[i] = true;
      d.reason[i] = kMeasuringRestReason;
      out_[i] = false;
      continue;
    }
    if (!alive[i] || take[i]) {
      out_[i] = false;
      continue;
    }
    if (!out_[i]) out_[i] = true, since_[i] = 0, every_[i] = std::max(opt_.probe, 1);
    ++since_[i];
    const bool due = recheck_ || since_[i] >= every_[i] || !judged(d.models[i]);
    if (opt_.probe > 0 && due) {
      d.probe[i] = kProbeShares[probes_[i]++ % 2];
      if (!recheck_ && judged(d.models[i]))
        every_[i] = std::min(2 * every_[i], 8 * std::max(opt_.probe, 1));
      since_[i] = 0;
      continue;
    }
    d.rest[i] = true;
    d.reason[i] = left_out_reason(d.models[i], d.predicted_ms, opt_.margin);
  }
  recheck_ = false;
  return d;
}

bool ParticipationTracker::rest_to_measure(size_t i, const Decision& d,
                                           const std::vector<bool>& take, double total, bool may) {
  // (Its fit need not be determined: a device without fixed cost, given a steady share,
  // never is; its speed is then the balancer's.)
  const DeviceCostModel& m = d.models[i];
  if (!(m.speed > 0) || opt_.probe <= 0) return false;
  std::vector<bool> without = take;
  without[i] = false;
  const double saves = predicted_frame_ms(d.models, without, total) / d.predicted_ms - 1;
  // Once rested, again only if it costs visibly: a fixed cost, or a measured slowing of
  // the others.
  const bool again = (m.determined && m.fixed_ms > kRestProbeFixed * d.predicted_ms) ||
                     m.contention < kContentionSeen;
  if (++since_in_[i] < every_in_[i] || !(saves < kRestProbeSaving) || (rests_[i] > 0 && !again))
    return false;
  if (!may) {  // another device rests this frame: due next frame
    since_in_[i] = every_in_[i];
    return false;
  }
  since_in_[i] = 0;
  every_in_[i] = std::min(std::max(2 * every_in_[i], opt_.probe), 8 * opt_.probe);
  ++rests_[i];
  return true;
}

void ParticipationTracker::measured(size_t i, double work, double time_ms) {
  if (i < fit_.size()) fit_[i].add(work, time_ms);
}

void ParticipationTracker::rescale(size_t i, double r) {
  if (i < fit_.size()) fit_[i].rescale_work(r);
}

void ParticipationTracker::frame_speeds(const std::vector<bool>& took_part,
                                        const std::vector<double>& speed, bool sample) {
  const size_t n = fit_.size();
  if (took_part.size() != n || speed.size() != n) return;
  int flipped = -1, flips = 0;
  for (size_t i = 0; i < n; ++i)
    if (took_part[i] != last_took_[i]) flipped = int(i), ++flips;
  if (flips == 1 && sample) {
    double now = 0, before = 0;  // the others' speeds, this frame and the last
    bool same = true;
    for (size_t j = 0; j < n; ++j) {
      if (int(j) == flipped || !took_part[j]) continue;
      same &= speed[j] > 0 && last_speed_[j] > 0;
      now += speed[j], before += last_speed_[j];
    }
    if (same && now > 0 && before > 0) {
      const size_t i = size_t(flipped);
      const double sample = took_part[i] ? now / before : before / now;  // with / without
      double& mean = log_contention_[i];
      mean = contention_samples_[i] == 0 ? std::log(sample) : 0.5 * mean + 0.5 * std::log(sample);
      ++contention_samples_[i];
    }
  }
  last_took_ = took_part;
  last_speed_ = speed;
}

void ParticipationTracker::changed(bool refit) {
  recheck_ = true;
  if (refit)
    for (size_t i = 0; i < fit_.size(); ++i)
      if (out_[i]) fit_[i].clear();
}

}  // namespace multiray::balance
