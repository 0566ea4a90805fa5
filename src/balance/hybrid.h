// `hybrid` (multiray's own): a statistics-driven bulk split whose pieces idle devices
// steal from the back, so that what the statistics could not foresee (noise, a device
// slowing down mid-frame, a camera cut) costs about one small chunk, not a frame.
//
// Cost model. A pixel costs base·k(row): base is its samples (pixel_weight, or 1) and k a
// learnt cost per sample of each flat row (views laid end to end), mean 1. Device i
// renders s_i cost units per ms; its share of the frame is s_i/Σs.
//
// Layout. The frame is cut, by binary search in the cost CDF, into `bands` bands of equal
// cost; in band b every device gets one contiguous piece holding its share of the band,
// the device order rotated by b. Each device thus works on `bands` contiguous pieces that
// sample the whole frame. This interleaving is what makes the speeds measurable: with one
// range per device a region that got dearer cannot be told from a device that got slower
// (in simulation the estimates drifted without bound under a moving cost hotspot), whereas
// a device that sees every part of the frame has a cost close to the frame's average, as
// with shuffled strips, while keeping `bands` pieces instead of thousands of strips.
// A device renders its pieces in van der Corput band order (0, 4, 2, 6, 1, 5, 3, 7), so
// what is left to steal at the end of a frame is spread over the frame too. Its work is
// cut into chunks by guided self-scheduling in that order: a chunk holds at most
// (1 − `taper`) of what the device has left, and no less than `tail` of the slowest
// device's share (any thief finishes a stolen chunk within ~`tail` of the ideal frame
// time). Plan::steal is set: a device that runs dry takes the last chunk of whoever has the
// most left, and the last chunks are the small ones.
//
// Learning, after each frame:
// - Speed: m_i = (model cost of everything device i rendered, stolen items included) /
//   its time. Stealing equalises the times, so m_i is measured on the work really done.
//   The estimate follows m_i by an exponential average (weight `alpha`) and jumps to m_i
//   when they differ by more than `jump`: noise is smoothed, a real change is taken at once.
// - Cost per row: each item's time, scaled so the device's items add up to its frame time
//   and multiplied by m_i, is the item's observed cost; spread over its rows by base weight
//   it gives a new k, blended in with weight `gamma`, then k is renormalised to mean 1.
// - Bad values (time <= 0, NaN, inf; no items; dropped devices) leave the estimates as
//   they are. A device with no estimate yet gets the mean speed of the others.
//
// clang-format off
// | parameter | default | meaning
// |-----------|---------|-------------------------------------------------------------------------
// | bands     | 8       | interleaved bands = contiguous pieces per device (1–256)
// | taper     | 0.7     | a chunk is at most (1 − taper) of the device's remaining work, [0, 0.95]
// | tail      | 0.02    | smallest chunk, in units of the slowest device's share
// | alpha     | 0.5     | weight of a new speed measurement, (0, 1]
// | jump      | 0.2     | relative speed change taken at once, >= 0
// | gamma     | 0.5     | weight of a new row-cost observation, [0, 1]
// | min_chunk | 256     | smallest chunk in pixels; shorter ones merge (>= 1)
// | steal     | 1       | 0 turns hybrid into a pure bulk split (for comparison)
// clang-format on
#pragma once

#include <cstdint>
#include <utility>

#include "balance/balancer_base.h"

namespace multiray::balance {

class HybridBalancer final : public BalancerBase {
 public:
  struct Options {
    int bands = 8;
    double taper = 0.7;
    double tail = 0.02;
    double alpha = 0.5;
    double jump = 0.2;
    double gamma = 0.5;
    int min_chunk = 256;
    bool steal = true;
  };

  explicit HybridBalancer(int device_count);
  HybridBalancer(int device_count, const Options& options);

  std::string name() const override { return "hybrid"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;

  // Estimated speeds in cost units per ms (0 = not measured yet), and the cost per sample
  // of each flat row (mean 1 over the frame).
  const std::vector<double>& speeds() const { return speed_; }
  const std::vector<double>& row_cost() const { return cost_; }

 private:
  void reset_cost(const FrameShape& shape);
  // Share of the frame's cost per device: s_i/Σs over alive devices.
  std::vector<double> shares() const;
  // The order a device renders its bands in.
  std::vector<size_t> band_order() const;
  // Cost fractions of the chunks of every piece: [band][device][chunk], front to back.
  std::vector<std::vector<std::vector<double>>> chunk_costs(
      const std::vector<double>& shares, const std::vector<size_t>& order) const;
  // Appends the chunks between consecutive `cuts` (flat pixel positions), merging chunks
  // shorter than min_chunk into their neighbour.
  void append_chunks(const FrameShape& shape, const std::vector<int64_t>& cuts,
                     std::vector<WorkItem>& out) const;

  static constexpr size_t kMaxChunks = 256;  // per device and frame

  Options opt_;
  std::vector<double> speed_;
  std::vector<double> cost_;  // k per flat row
  FrameShape cost_shape_;     // the size cost_ applies to (no weights kept)
};

}  // namespace multiray::balance
