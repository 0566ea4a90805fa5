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
// - Fixed cost per item (`overhead` > 0): a real device pays for every item it takes
//   (kernel launch, read-back, a wake-up after emulated idle) whatever the item's size.
//   Each item's time is t = o_i + c/s_i for its model cost c, so o_i is the intercept of
//   a least-squares fit of t on c over the device's items of the frame, weighted by 1/c
//   (item times vary in proportion to their size). Fits are combined over frames by
//   their precision (1/variance of the intercept), earlier ones fading by
//   kOverheadMemory a frame, and o_i is that mean less two standard errors, at least 0:
//   errors in the model costs bias an intercept upwards, and only what the frames show
//   clearly counts (with too few or too similar items, or the speed jumping, there is no
//   fit and the evidence fades). The speed is then measured on the time net of the fixed
//   costs, s_i = work / (time − k_i·o_i) for the k_i items the device rendered, and the
//   row costs on each item's time net of o_i.
// - Bad values (time <= 0, NaN, inf; no items; dropped devices) leave the estimates as
//   they are. A device with no estimate yet gets the mean speed of the others.
//
// Planning with fixed costs (`overhead` > 0, once some o_i > 0). Device i's frame takes
// t_i = n_i/s_i + k_i·o_i for n_i cost units in k_i items; the split makes every t_i equal
// (k_i counted on a first layout by speeds alone, then the frame is laid out again with
// the new shares; n_i >= 5% of its speed's worth, so that a device whose items alone
// outlast the frame still gets work to be measured on). A device's chunks are made large
// enough that its fixed cost is at most `overhead` of a chunk's time, o_i·s_i·(1 −
// overhead)/overhead cost units, but no more than 0.4 of a piece (its last piece is still
// cut in chunks of different sizes, which the fit needs) and never less than the `tail`
// floor. And a cut next to a device with a fixed cost that splits a row moves to a row
// boundary (a chunk that starts or ends inside a row is up to three rects, i.e. three
// items) when that changes neither neighbour's share by more than kSnapShare, or when
// rendering the moved pixels takes less time than the fixed costs it saves; the side is
// chosen so that each device's accumulated change stays within about one move. With every
// o_i = 0 hybrid plans exactly as without the model, and `overhead=0` is hybrid before it.
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
// | overhead  | 0.1     | most of a chunk's time its device's fixed cost per item may take,
// |           |         | [0, 0.9]; 0: no per-item cost model (hybrid before it)
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
    double overhead = 0.1;
  };

  explicit HybridBalancer(int device_count);
  HybridBalancer(int device_count, const Options& options);

  std::string name() const override { return "hybrid"; }
  std::string spec() const override;
  Plan plan(const FrameShape& shape, int frame) override;
  void update(const FrameStats& stats) override;
  // Scanline ranges of equal-cost bands.
  CutAxis cut_axis() const override { return CutAxis::rows; }

  // Estimated speeds in cost units per ms, net of the fixed cost per item (0 = not
  // measured yet); the fixed cost per item in ms (0 = none measured, or `overhead=0`); and
  // the cost per sample of each flat row (mean 1 over the frame).
  const std::vector<double>& speeds() const { return speed_; }
  const std::vector<double>& overheads() const { return overhead_; }
  const std::vector<double>& row_cost() const { return cost_; }

 private:
  void reset_cost(const FrameShape& shape);
  // The speed each alive device is planned with: its estimate, or the mean of the
  // measured ones (1 if none is); 0 for dropped devices.
  std::vector<double> planning_speeds() const;
  // Shares that give every device the same t_i = n_i/s_i + k_i·o_i for `items` k_i and a
  // frame of `total` cost units.
  std::vector<double> overhead_shares(const std::vector<double>& speed,
                                      const std::vector<double>& items, double total) const;
  // The order a device renders its bands in.
  std::vector<size_t> band_order() const;
  // Each device's item lists for `shares` of a frame whose flat rows cost `row_cost`.
  std::vector<std::vector<WorkItem>> lay_out(const FrameShape& shape,
                                             const std::vector<double>& row_cost,
                                             const std::vector<double>& shares,
                                             const std::vector<double>& speed) const;
  // Cost fractions of the chunks of every piece: [band][device][chunk], front to back;
  // `floor` is each device's smallest chunk.
  std::vector<std::vector<std::vector<double>>> chunk_costs(
      const std::vector<double>& shares, const std::vector<double>& floor,
      const std::vector<size_t>& order) const;
  // Moves the inner `cuts` that split a row to a row boundary next to devices with a fixed
  // cost per item (`owner`: the device of each chunk).
  void snap_to_rows(std::vector<int64_t>& cuts, const std::vector<size_t>& owner,
                    const std::vector<double>& row_cost, int width,
                    const std::vector<double>& shares, const std::vector<double>& speed) const;
  // Appends the chunks between consecutive `cuts` (flat pixel positions), merging chunks
  // shorter than min_chunk into their neighbour.
  void append_chunks(const FrameShape& shape, const std::vector<int64_t>& cuts,
                     std::vector<WorkItem>& out) const;

  static constexpr size_t kMaxChunks = 256;  // per device and frame
  // Weight left to the earlier fits of the fixed cost per item after each frame.
  static constexpr double kOverheadMemory = 0.8;
  // A cut moves to a row boundary if that changes neither neighbour's share by more than
  // this (or saves more fixed cost than the moved pixels take).
  static constexpr double kSnapShare = 0.02;

  Options opt_;
  std::vector<double> speed_;
  std::vector<double> overhead_;  // fixed cost per item, ms: overhead_sum_ / overhead_weight_
  std::vector<double> overhead_sum_, overhead_weight_;  // fits × precision, precision; fading
  std::vector<double> cost_;                            // k per flat row
  FrameShape cost_shape_;  // the size cost_ applies to (no weights kept)
};

}  // namespace multiray::balance
