// The benchmark harness behind `multiray bench`: every balancer (one Session lane each)
// renders the same frames, interleaved frame by frame, and on sampled frames each device
// renders the whole frame alone first, giving the frame's ideal time 1 / Σ_i (1 / T_i).
// Interleaving makes load from other programs on a shared machine hit every balancer
// alike, so the comparison stays fair. Output formats (table, JSON, plots) are the CLI's.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/image_metrics.h"
#include "engine/session.h"

namespace multiray {

struct BenchConfig {
  int frames = 100;
  int warmup = 10;           // frames left out of summaries (balancers settling)
  int ideal_frames = 20;     // frames (spread over those after the warm-up) timed alone
  int partition_frame = -1;  // frame whose rendered items are kept per lane (-1: none)
  bool keep_stats = false;   // keep every frame's per-item stats per lane (for traces)
  // Volumes: > 0 renders every frame once more at this step (voxel lengths), on device 0
  // before the lanes and outside their times, as the reference of every lane's image
  // error (Bruder et al.'s Table 4 uses 0.1); 0: lane 0's frame when at full quality.
  float reference_step = 0;
};

// What each device measured rendering one sampled frame alone.
struct IdealSample {
  int frame = 0;
  std::vector<double> device_alone_ms;
  double ideal_ms = 0;
};

struct BenchLane {
  std::string spec;  // the balancer's full spec
  std::vector<FrameRecord> records;
  std::vector<uint64_t> image_hashes;                     // per frame, over every view
  std::vector<std::vector<balance::WorkItem>> partition;  // at partition_frame
  Framebuffer partition_image;             // view 0 as rendered at partition_frame (empty: none)
  std::vector<balance::FrameStats> stats;  // per frame, with keep_stats
  // Per frame, view 0 against the reference: the frame rendered at
  // BenchConfig::reference_step when set (every lane), else lane 0's image of the frame
  // when lane 0 rendered it at full quality (lanes 1.., 0 error at equal quality).
  std::vector<ImageError> error_vs_reference;
};

struct BenchResult {
  std::vector<int> sampled;  // frames whose ideal was measured, increasing
  std::vector<IdealSample> ideal;
  std::vector<double> sampling_ms;  // per frame: host set-up of irregular sampling
  // Per frame with reprojected sampling: the fraction of non-reference pixels path-traced
  // as holes (empty otherwise).
  std::vector<double> hole_fraction;
  std::vector<BenchLane> lanes;
  // Per lane, frames whose images differ from those of an earlier lane rendered at the same
  // quality (should be none).
  std::vector<std::vector<int>> mismatched_frames;
};

// `count` frames spread evenly over [first, frames - 1].
std::vector<int> spread_frames(int first, int frames, int count);

// Runs the benchmark on `session` (its devices are `devices`; `speeds` their emulated
// speeds before any perturbation; `perturbations` as given to the session). `on_frame`,
// if set, is called with each frame number before it renders (progress display).
BenchResult run_bench(Session& session, const std::vector<Device*>& devices,
                      const std::vector<double>& speeds,
                      const std::vector<Perturbation>& perturbations,
                      const RenderSettings& settings, const BenchConfig& config,
                      const std::function<void(int)>& on_frame = {});

}  // namespace multiray
