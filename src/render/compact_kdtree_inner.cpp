#include "render/compact_kdtree_inner.h"

#include <algorithm>

namespace multiray::kd_inner {

float occupancy(const Bounds3& clipped, const Bounds3& cell) {
  float share[3];
  for (int a = 0; a < 3; ++a) {
    const float c = cell.hi[a] - cell.lo[a];
    // A flat cell: whatever lies in it spans it along that axis.
    share[a] = c > 0 ? std::clamp((clipped.hi[a] - clipped.lo[a]) / c, 0.0f, 1.0f) : 1.0f;
  }
  return std::max({share[0] * share[1], share[1] * share[2], share[2] * share[0]});
}

void CandidatePlanes::add(int axis, float pos, const Bounds3& cell) {
  std::vector<float>& p = pos_[axis];
  if (pos > cell.lo[axis] && pos < cell.hi[axis] && (p.empty() || p.back() != pos))
    p.push_back(pos);
}

float CandidatePlanes::frequency(const Bounds3& clipped) const {
  const size_t total = size();
  if (total == 0) return 0.0f;
  size_t through = 0;
  for (int a = 0; a < 3; ++a) {
    const std::vector<float>& p = pos_[a];
    const auto first = std::upper_bound(p.begin(), p.end(), clipped.lo[a]);
    const auto last = std::lower_bound(first, p.end(), clipped.hi[a]);
    through += size_t(last - first);
  }
  return float(double(through) / double(total));
}

InnerPicker::InnerPicker(const Bounds3& cell, const CandidatePlanes& planes, float tau_occu,
                         float tau_freq, int room)
    : cell_(cell),
      planes_(planes),
      tau_occu_(tau_occu),
      tau_freq_(tau_freq),
      room_(std::clamp(room, 0, 2)) {}

void InnerPicker::offer(uint32_t index, const Bounds3& clipped) {
  if (room_ == 0) return;
  const float occu = occupancy(clipped, cell_);
  if (!(occu >= tau_occu_)) return;
  const float freq = planes_.frequency(clipped);  // the dearer measure second
  if (!(freq >= tau_freq_)) return;
  const Candidate c{index, freq, occu};
  // Strictly better only, so that among equals the first offered stays.
  const auto better = [](const Candidate& x, const Candidate& y) {
    return x.freq > y.freq || (x.freq == y.freq && x.occu > y.occu);
  };
  if (n_ < room_) {
    best_[n_++] = c;
  } else if (better(c, best_[n_ - 1])) {
    best_[n_ - 1] = c;
  } else {
    return;
  }
  // Keep best_ ordered, best first (at most two entries).
  if (n_ == 2 && better(best_[1], best_[0])) std::swap(best_[0], best_[1]);
}

bool InnerPicker::contains(uint32_t index) const {
  for (int i = 0; i < n_; ++i)
    if (best_[i].index == index) return true;
  return false;
}

}  // namespace multiray::kd_inner
