// How well a run met its frame-time target (Bruder et al. 2017, Fig. 5a and 7): the
// error of frame times against the target, the worst overshoot, the quality spent, and
// how good the prediction was.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image_metrics.h"
#include "engine/frame_record.h"

namespace multiray::study {

struct TargetingSummary {
  int frames = 0;                // after warm-up
  double rmse_ms = 0;            // sqrt(mean (frame_ms - target)^2)
  double worst_ratio = 0;        // max frame_ms / target
  double over_125 = 0;           // share of frames above 1.25 x target
  double mean_step_scale = 0;    // mean of the step multiplier (1: the user's step)
  double mean_image_scale = 0;   // mean of the image scale (1: full resolution)
  double prediction_error = -1;  // mean |predicted - measured| / measured (-1: none)
  double advise_ms = 0;          // mean time of the prediction (pre-pass etc.)
  double learn_ms = 0;           // mean time of learning after a frame
  // Per device: mean |predicted - measured| / measured cost per sample (Bruder et al.'s
  // Fig. 6a), over frames where both are known; -1 where never.
  std::vector<double> cost_error;
  // Against the full-quality image of the first run (Bruder et al.'s Table 4); -1 when not
  // compared. PSNR is averaged over frames with finite PSNR (identical frames are left out).
  double mse = -1, psnr_db = -1, ssim = -1;
};

// Over records[warmup..]; frame times are FrameRecord::frame_ms (engine wall time).
// `errors` (may be empty): each frame's image error against the reference, in frame order.
TargetingSummary targeting_summary(const std::vector<FrameRecord>& records, int warmup,
                                   double target_ms, const std::vector<ImageError>& errors = {});
nlohmann::json targeting_to_json(const TargetingSummary& t);

// Frame-time targeting past this share of the full work (the cost factor
// image_scale^2 / step_scale, balance/targeting.h) shows: a step 4x the user's slices a
// volume into visible slabs, half the pixels per side blurs it.
constexpr double kVisibleCost = 0.25;

// One measured frame of a targeted run: the quality it was rendered at and its time.
struct QualityTime {
  double step_scale = 1, image_scale = 1, frame_ms = 0;
  double cost() const { return image_scale * image_scale / step_scale; }
};

// The frame time of a run as a function of the cost factor c, fitted to its measured
// frames as a fixed part plus a part proportional to the work: t(c) = fixed_ms + work_ms·c
// (least squares). Per-ray set-up, block walks, the pre-pass and the frame's host work do
// not shrink with the work, so "time proportional to c" promises far more than a coarser
// frame gives (the cranium on two cores: 147 ms at full quality, 55 ms at 1/64).
struct FrameTimeFit {
  bool ok = false;  // two or more distinct cost factors, and time growing with c
  double fixed_ms = 0, work_ms = 0;
  double at(double c) const { return fixed_ms + work_ms * c; }
};
FrameTimeFit fit_frame_time(const std::vector<QualityTime>& frames);

// When the last of `frames` did less than kVisibleCost of the full work to hold
// `target_ms`: one line saying so and the target that would keep the quality within
// kVisibleCost. That target comes from the fit of the run's own frames (fit_frame_time),
// so it lies between the frames measured at full and at coarse quality (never above a
// full-quality frame's time); without a fit, from the last frame's time taken as
// proportional to the work. When even the coarsest quality allowed (`lowest_cost`, the
// cost factor targeting stops at) is fitted slower than the target, it says the target
// cannot be met here. "" otherwise.
std::string degraded_quality_warning(const std::vector<QualityTime>& frames, double target_ms,
                                     double lowest_cost);
void print_targeting(const std::vector<std::string>& lanes,
                     const std::vector<TargetingSummary>& summaries, double target_ms);

// Frame time per frame of every lane against the target (a dashed line), frames at which
// the transfer function switches marked, as the paper's Fig. 5a; below, the step
// multiplier of each lane. `switches` are frame numbers.
void write_targeting_svg(const std::string& path, const std::string& title,
                         const std::vector<std::string>& lanes,
                         const std::vector<std::vector<FrameRecord>>& records, double target_ms,
                         const std::vector<int>& switches);

// The prediction error of every frame (Bruder et al.'s Fig. 6a): |predicted - measured| /
// measured of each lane's frame time (top) and of each device's cost per sample in lane
// `cost_lane` (bottom; `devices` name them), each as a centred 9-frame mean,
// transfer-function switches marked.
void write_prediction_svg(const std::string& path, const std::string& title,
                          const std::vector<std::string>& lanes,
                          const std::vector<std::vector<FrameRecord>>& records, size_t cost_lane,
                          const std::vector<std::string>& devices,
                          const std::vector<int>& switches);

}  // namespace multiray::study
