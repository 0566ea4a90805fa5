// A simulation study: a recorded trace replayed on N virtual devices of given speeds,
// behind a given link, with several balancers, in virtual time (what `multiray simulate`
// runs). Device speeds come from a small distribution language so that studies from 2 to
// 4096 devices are one command.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "balance/trace.h"

namespace multiray::balance {

// Speeds (relative, the fastest 1) of `n` devices from `dist`:
//   equal          every device 1
//   linear:MIN     evenly spread from 1 down to MIN (MIN in (0, 1])
//   random:MIN     uniform in [MIN, 1], drawn from `seed`
//   list:A/B/...   the listed speeds (each in (0, 1]), repeated to n devices
// Throws std::invalid_argument with one line for anything else.
std::vector<double> device_speeds(const std::string& dist, int n, uint64_t seed);

// The simulator's link for a --link text (util/link.h's one grammar: none, lan, wifi or
// LATENCY_MS,MBIT[,separate]). Throws std::invalid_argument.
SimLink simulated_link(const std::string& text);

// Result bytes per pixel for `simulate --result-encoding`: rgba8 (4 bytes of 8-bit
// colour, as a display takes it: our assumption, not stated by Seo et al.; the
// simulator's default) or one of render's encodings
// (util/result_encoding.h), the zstd ones at `zstd_ratio` of their raw size (negative:
// the ratio measured on Sponza). Throws std::invalid_argument.
double simulated_bytes_per_pixel(const std::string& encoding, double zstd_ratio = -1);

struct StudyConfig {
  std::vector<double> speeds;  // one per device
  double frame_noise = 0;      // each device's speed scaled by 1 + U(-x, x) per frame
  double slowdown = 1;         // every device this many times slower than the recording one
  SimLink link;
  int frames = 0;  // 0: the trace's frame count
  int warmup = 0;  // frames left out of the summary
  uint64_t seed = 0;
};

struct StudyResult {
  std::string balancer;  // full spec
  int devices = 0;
  double mean_frame_ms = 0;  // frames after the warm-up, until the master has every result
  // Same frames: frame cost / the frame's sum of speeds with its noise (SimFrame::
  // speed_sum), no link: what no split can beat, so efficiency <= 1 (to float rounding).
  double mean_ideal_ms = 0;
  double efficiency = 0;         // sum ideal / sum actual over those frames
  double mean_imbalance = 0;     // device times, as balance::imbalance()
  double mean_deviation = 0;     // device times, as balance::deviation() (Harada)
  std::vector<double> frame_ms;  // every frame
};

// Replays `trace` with the balancer `spec` (made for config.speeds.size() devices), frame
// by frame (replay_trace_each): it holds one simulated frame at a time, plus 8 bytes per
// frame for StudyResult::frame_ms. Throws std::invalid_argument for a bad spec or config.
// `costs` (optional, made for `trace`) keeps the frames' cost tables for the next study.
StudyResult run_study(const Trace& trace, const std::string& spec, const StudyConfig& config,
                      TraceCosts* costs = nullptr);

// Bytes one run_study() of `frames` frames on `devices` devices holds at its peak,
// estimated before it runs (a model, not a measurement): the cost tables of the trace's
// frames (a summed-area table of 8 bytes a pixel, and the density being built), one
// simulated frame (each device's state, statistics and a few items) and the frame times.
double study_memory_bytes(const Trace& trace, int devices, int frames);

}  // namespace multiray::balance
