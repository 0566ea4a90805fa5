// The least-squares fit behind the simulator's calibration (trace_calibration.h): the
// fixed costs, each frame's cost map and the devices' speeds, the contention and the
// frame noise, over observations of one trace (calibrate()) or of several traces of the
// same frames (calibrate_pooled()). Internal to the balance library.
#pragma once

#include <utility>
#include <vector>

#include "balance/trace.h"

namespace multiray::balance::calib {

inline constexpr int kBandsPerView = 8;  // the cost map: bands of rows per view, per frame

// One observation: an item, or a take (items a device rendered in one launch). Its time
// is Σ over `fixed` of the fixed costs x_u, plus slow(busy) · Σ_b samples_b·ρ_b / s_device,
// ρ the frame's cost map (shared by every run of that frame).
struct Obs {
  size_t device = 0, frame = 0, run = 0;     // run: which trace (0 for one trace)
  double time = 0;                           // recorded ms
  int busy = 1;                              // devices at work when it started, itself included
  std::vector<std::pair<int, double>> bins;  // (band, samples in it)
  std::vector<size_t> fixed;                 // indices of the fixed costs it pays
};

// The item's samples (or pixels when none were recorded) per band of rows.
std::vector<std::pair<int, double>> bins_of(const ItemReport& r, const FrameShape& shape);

// Adds `more` to `bins` (both ordered by band).
void add_bins(std::vector<std::pair<int, double>>& bins,
              const std::vector<std::pair<int, double>>& more);

double median(std::vector<double> v);

// Device d's frame times (frames `from` on that it rendered in) and the gaps between
// them and its items (its fixed cost per frame outside any item).
void frame_times(const Trace& trace, size_t from, size_t d, std::vector<double>& times,
                 std::vector<double>& gaps);

// The launch cost inside device d's items from the balancer's own model of it (the
// trace's `model` records), 0 when there is none clear of noise (trace_calibration.h).
double launch_of(const Trace& trace, size_t from, size_t d);

// What the fit learns. `fixed` has one entry per fixed cost (calibrate(): one per device,
// the cost per item; calibrate_pooled(): per take, then per frame in its first take).
struct Fit {
  std::vector<double> speed, fixed;
  std::vector<bool> fitted;  // false: that fixed cost is not identified (left at 0)
  double contention = 0;
  bool contention_identified = false;
  double alone_share = 0, frame_noise = 0;
  std::vector<std::vector<double>> maps;  // per frame, ρ per band (ms per sample at speed 1)
  double slow(int busy) const { return 1 + contention * (busy - 1); }
  // The observation's time net of its fixed costs and the contention, at speed 1.
  double net(const Obs& o) const;
  // The model cost Σ_b samples_b·ρ_b of `bins` in `frame`.
  double cost(size_t frame, const std::vector<std::pair<int, double>>& bins) const;
};

// Fits `n` devices' speeds and `unknowns` fixed costs to `obs` (frames 0..frames-1 of
// `runs` runs): alternating least squares until the speeds settle (docs/traces.md).
// `contention` < 0: learnt (0 when not identifiable), else kept.
Fit fit_observations(const std::vector<Obs>& obs, size_t n, size_t unknowns, size_t frames,
                     size_t runs, double contention);

}  // namespace multiray::balance::calib
