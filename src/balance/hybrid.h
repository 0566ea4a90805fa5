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
//   its time net of its fixed costs (per item and per frame, below). Stealing equalises
//   the times, so m_i is measured on the work really done. The estimate s_i follows m_i
//   by an exponential average (weight `alpha`) unless m_i is a change, which is taken at
//   once (s_i := m_i). What counts as a change (`detect`):
//   - `noise` (default): each device keeps the noise of its own measurements, sigma_i, the
//     exponentially weighted root mean square of r = log(m_i/s_i) (weight kNoiseWeight, so
//     about the last 10 frames), over the measurements that were no change. r is a change
//     when |r| > max(`z`·sigma_i, kNoiseFloor), or when it and the measurement before it
//     both lie beyond max(kConfirmSigmas·sigma_i, kNoiseFloor) on the same side of the
//     estimate the first was made against (a moderate change is then taken at its second
//     frame, and the first of the two is taken back out of the noise history). Until
//     kMinHistory measurements are in the history the fixed rule below decides, with
//     `jump` as its threshold.
//   - `fixed`: a change is |m_i/s_i − 1| > `jump` (hybrid before issue 30).
//   A noisy device is thus not thrown about by its own noise, and a steady one follows a
//   change of a few percent within a frame or two.
// - Fixed cost per frame (`frame=1`): what device i pays once a frame whatever its items
//   (a wake-up, a kernel set-up) is the gap between its frame time and the sum of its
//   items' times, clamped at 0, averaged over frames with weight kFrameCostWeight: f_i.
//   Frames with an unusable item time measure no gap.
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
//   row costs on each item's time net of o_i (the speed also net of f_i).
// - Bad values (time <= 0, NaN, inf; no items; dropped devices) leave the estimates as
//   they are. A device with no estimate yet gets the mean speed of the others.
//
// Planning with fixed costs (once some o_i > 0 with `overhead` > 0, or some f_i > 0).
// Device i's frame takes t_i = f_i + k_i·o_i + n_i/s_i for n_i cost units in k_i items; the
// split makes every t_i equal (k_i counted on a first layout by speeds alone when some
// o_i > 0, then the frame is laid out again with
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
// o_i = 0 and f_i = 0 hybrid plans exactly as without the model; `overhead=0` and
// `frame=0` turn each model off.
//
// Tail and noise (`detect=noise`, once a device has kMinHistory measurements): a device
// whose speed varies by sigma_i (relative) ends its frame early or late by about sigma_i
// of the frame, which only stealing can even out. Chunks much finer than that add steals
// (and per-item costs) for little gain, so its smallest chunk is
// (`tail` + sigma_i/kNoiseChunks) of the slowest device's share: a thief then overruns the
// ideal frame time by at most a quarter of the noise on top of `tail`. No more than 0.4 of
// a piece; with sigma_i = 0 it is `tail`'s floor, as before. Not for a device with a fixed
// cost per item (o_i > 0): its chunks are sized by that cost, and the fit of o_i needs
// chunks of different sizes.
//
// Devices left out (`leave=1`, balance/participation.h): each device's frame time is also
// fitted as F_i + n/s_i over frames (its whole frame, so a fixed cost inside one batched
// launch is seen too, which the item fit above cannot see when a driver reports only a
// batch's time); a device whose F_i exceeds what it would save the others is given
// nothing (Plan::resting) and probed now and then with a small share. F_i only decides
// who takes part: the shares of those who do are planned as above. (A fixed cost the
// item fit cannot see makes a device's speed look lower than it is, so it is given less
// than it could take: it finishes early, the frame does not wait for it.)
//
// clang-format off
// | parameter | default | meaning
// |-----------|---------|-------------------------------------------------------------------------
// | bands     | 8       | interleaved bands = contiguous pieces per device (1–256)
// | taper     | 0.7     | a chunk is at most (1 − taper) of the device's remaining work, [0, 0.95]
// | tail      | 0.02    | smallest chunk, in units of the slowest device's share
// | alpha     | 0.5     | weight of a new speed measurement, (0, 1]
// | jump      | 0.2     | relative speed change taken at once, >= 0: with detect=fixed always,
// |           |         | with detect=noise until a device has kMinHistory measurements
// | detect    | noise   | what is a change of speed: noise (against the device's own noise)
// |           |         | or fixed (`jump` alone, and the tail ignores noise: hybrid before it)
// | z         | 3       | with detect=noise, a change lies beyond z noise sigmas, [1, 100]
// | gamma     | 0.5     | weight of a new row-cost observation, [0, 1]
// | min_chunk | 256     | smallest chunk in pixels; shorter ones merge (>= 1)
// | steal     | 1       | 0 turns hybrid into a pure bulk split (for comparison)
// | overhead  | 0.1     | most of a chunk's time its device's fixed cost per item may take,
// |           |         | [0, 0.9]; 0: no per-item cost model (hybrid before it)
// | frame     | 1       | 1: learn and plan with a fixed cost per frame; 0: none (as before)
// | leave     | 1       | 1: leave out devices whose fixed cost per frame does not pay; 0: never
// | probe     | 8       | frames before a left-out device is first probed (then 2x, up to 8x);
// |           |         | 0: never probed
// clang-format on
#pragma once

#include <cstdint>
#include <utility>

#include "balance/balancer_base.h"
#include "balance/participation.h"

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
    bool detect_noise = true;  // detect=noise; false: detect=fixed
    double z = 3;
    bool frame_cost = true;
    bool leave = true;
    int probe = 8;
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
  // The noise of each device's speed measurements (root mean square of log(m_i/s_i), see
  // above; 0 = none measured); its fixed cost per frame in ms (0 = none, or `frame=0`); and
  // how many changes of speed were taken at once (first measurements not counted).
  std::vector<double> noise() const;
  const std::vector<double>& frame_costs() const { return frame_cost_; }
  const std::vector<int>& changes() const { return changes_; }
  // Device i's frame-level cost model (participation.h) and whether it is left out now.
  DeviceCostModel cost_model(size_t i) const { return part_.model(i); }
  bool left_out(size_t i) const { return part_.left_out(i); }

 private:
  void reset_cost(const FrameShape& shape);
  double noise(size_t i) const;
  // Whether measurement m of device i's speed is a change to take at once by itself (the
  // `z` or `jump` threshold; the confirmation by two measurements is take_speed's).
  bool jumps(size_t i, double m) const;
  // Takes measurement m into device i's speed estimate and noise history.
  void take_speed(size_t i, double m);
  // Device i's gap between frame time and its items' times into f_i.
  void take_frame_cost(size_t i, const DeviceFrameStats& d);
  // The devices taking part jumped by speed ratios `jumps` (the cost of work changed):
  // the left-out devices' speeds and frame fits are restated by their geometric mean,
  // and they are probed.
  void restate_left_out(const std::vector<double>& jumps);
  // The participants' ratios and items, with `probe` shares given to probed devices.
  void add_probes(Plan& plan, const std::vector<double>& probe, const FrameShape& shape,
                  const std::vector<double>& row_cost, const std::vector<double>& speed) const;
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
  // A device with a determined fixed cost per frame above this share of the predicted
  // frame does not steal (Plan::no_steal).
  static constexpr double kNoStealFixed = 0.02;
  // The speed ratio of the devices taking part (geometric mean of their jumps) beyond
  // which the cost of work is taken to have changed for the left-out devices.
  static constexpr double kRestateJump = 2.0;
  // Weight left to the earlier fits of the fixed cost per item after each frame.
  static constexpr double kOverheadMemory = 0.8;
  // A cut moves to a row boundary if that changes neither neighbour's share by more than
  // this (or saves more fixed cost than the moved pixels take).
  static constexpr double kSnapShare = 0.02;
  // Speed noise: weight of a new sample in sigma_i's history; measurements needed before
  // it decides; the least |log(m/s)| that can be a change (1%: a steady device does not
  // jump on rounding or the row-cost model's small errors).
  static constexpr double kNoiseWeight = 0.1;
  static constexpr int kMinHistory = 4;
  static constexpr double kNoiseFloor = 0.01;
  // Two measurements in a row beyond this many sigmas on the same side are a change. At
  // one sigma, noise alone would do that one frame in twenty (normal noise); at two, one
  // in a thousand, while a change of 2–3 sigmas is still taken at its second frame.
  static constexpr double kConfirmSigmas = 2;
  // The tail floor grows by 1/kNoiseChunks of the device's noise.
  static constexpr double kNoiseChunks = 4;
  // Weight of a new gap in the fixed cost per frame.
  static constexpr double kFrameCostWeight = 0.3;

  Options opt_;
  std::vector<double> speed_;
  std::vector<double> overhead_;  // fixed cost per item, ms: overhead_sum_ / overhead_weight_
  std::vector<double> overhead_sum_, overhead_weight_;  // fits × precision, precision; fading
  std::vector<double> cost_;                            // k per flat row
  FrameShape cost_shape_;  // the size cost_ applies to (no weights kept)
  // Noise history: Σ weight·r², Σ weight and the sample count, and the same before the
  // last sample (to take it back out); the side (±1, 0: none) of the last measurement if
  // it lay beyond the confirmation bound without being a change.
  std::vector<double> noise_sum_, noise_weight_, undo_sum_, undo_weight_;
  std::vector<int> noise_count_, pending_, changes_;
  std::vector<double> pending_base_;  // the estimate the pending measurement was made against
  std::vector<double> frame_cost_;    // f_i, ms
  std::vector<bool> frame_seen_;      // some gap measured
  ParticipationTracker part_;
  std::vector<bool> probing_;   // devices probed in the frame last planned
  int frames_since_probe_ = 2;  // frames updated since the last with a probe
};

}  // namespace multiray::balance
