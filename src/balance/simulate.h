// A pure, deterministic model of the engine, for unit tests, docs and experiments without
// devices. Event driven, in virtual time: each device owns a clock; the device whose clock
// is earliest asks the same Dispatcher the engine uses for its next item, and its clock
// advances by the item's time. So a steal only ever takes an item no one has started.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "balance/balancer.h"

namespace multiray::balance {

// A synthetic device. An item of cost c (ms at speed 1) takes c / speed ms.
struct SimDevice {
  double speed = 1;             // > 0
  double frame_noise = 0;       // speed scaled by 1 + U(−x, x), drawn once per frame
  double item_noise = 0;        // each item's cost scaled by 1 + U(−x, x)
  double item_overhead_ms = 0;  // fixed cost per item (dispatch, transfer)
  // Fixed cost per frame (start-up, thread wake-ups): the device's first item starts this
  // many ms after the frame reached it. Counted in its time_ms, not in any item.
  double frame_overhead_ms = 0;
  // Fixed cost per launch, as a batching device (OpenCL) pays it: when it takes an item
  // of its own list it takes every not-started item of that list with it (they can no
  // longer be stolen) and renders them in one launch of launch_ms + their cost / speed,
  // each item reported with a share of that time by its cost. 0: items one by one.
  double launch_ms = 0;
  // Slowdown by the other devices (shared caches, memory bandwidth): an item runs at
  // speed / (1 + contention·(k − 1)) where k counts the devices at work when the item
  // starts, this one included (per item, not re-timed when k changes during it). A device
  // is at work from the moment the frame reaches it until it runs out of items.
  double contention = 0;
  // Mid-frame change: from `change_at_ms` on (frame-relative) the device runs at
  // `speed_after`. An item straddling the change is split exactly.
  double change_at_ms = std::numeric_limits<double>::infinity();
  double speed_after = 1;
  bool alive = true;  // a dead device renders nothing (its items may be stolen)
};

// A network between the devices and the master that hands out work and gathers results,
// after Seo, Park & Ihm (Sensors 2022, Fig. 6). Emulated in virtual time: every message
// takes `latency_ms`; a result of B bytes then takes B / bandwidth to cross. With
// `shared_master` the master's one link carries every device's results in turn (first
// ready, first sent), as on Seo's Wi-Fi cluster; otherwise each device has its own.
// Protocol: a frame's start (and the device's own list) reaches every device after one
// latency; each pull from the shared queue and each steal is a round trip (2 latencies)
// before the device can render; results are sent as items finish, overlapping rendering
// (a sender thread), except for plans without a shared queue and without stealing, whose
// devices send everything in one message when they finish (Seo's static batched
// strategy).
struct SimLink {
  double latency_ms = 0;                                  // one way
  double mbit_per_s = 0;                                  // link bandwidth; 0: unlimited
  bool shared_master = true;                              // one link at the master for all results
  double bytes_per_pixel = 4;                             // result bytes per pixel (8-bit RGBA)
  static SimLink lan() { return {0.1, 10000, true, 4}; }  // 0.1 ms, 10 Gbit/s
  static SimLink wifi() { return {5.0, 200, true, 4}; }   // 5 ms, 200 Mbit/s (mobile)
  bool active() const { return latency_ms > 0 || mbit_per_s > 0; }
};

// Cost of an item in ms at speed 1.
using CostFn = std::function<double(const WorkItem&)>;

// Cost = `ms_per_sample` × the item's samples (its pixel_weight sum, or area).
CostFn uniform_cost(const FrameShape& shape, double ms_per_sample);
// Cost = Σ over the item's pixels of ms_per_sample(view, x, y) × the pixel's weight;
// precomputed into a summed-area table, so each call is O(1).
CostFn pixel_cost(const FrameShape& shape,
                  const std::function<double(int view, int x, int y)>& ms_per_sample);

// Runs one frame of `plan` on `devices` (one per plan list; std::invalid_argument
// otherwise, or for a speed <= 0 on an alive device). Per device: time_ms = busy_ms = the
// clock when it ran out of work, samples and pixels rendered, and an ItemReport per item.
// Items nobody could take (a dead device's list without stealing) stay unrendered.
// Same inputs and `seed` give the same result.
FrameStats simulate(const Plan& plan, const FrameShape& shape,
                    const std::vector<SimDevice>& devices, const CostFn& cost, int frame = 0,
                    uint64_t seed = 0);

// One simulated frame: what the devices measured, and when the master had every result
// (frame_ms; without a link, the last device's finish).
struct SimFrame {
  Plan plan;
  FrameStats stats;
  double frame_ms = 0;
  // The frame's own speed: the sum over live devices of speed x this frame's noise factor
  // (before any mid-frame change or contention). The frame's cost over it is the frame
  // time no split can beat, so an efficiency against it never passes 1.
  double speed_sum = 0;
};

// simulate() behind `link`: device times include the waits for work; frame_ms when the
// last result arrived at the master. Same inputs and `seed` give the same result.
SimFrame simulate_linked(const Plan& plan, const FrameShape& shape,
                         const std::vector<SimDevice>& devices, const CostFn& cost,
                         const SimLink& link, int frame = 0, uint64_t seed = 0);

// plan → simulate → update for frames 0..frames-1. `devices_at(frame)` gives the device
// models of each frame (speed changes between frames, deaths); a device reported dead is
// dropped by the balancer through update().
std::vector<SimFrame> simulate_run(
    Balancer& balancer, const FrameShape& shape,
    const std::function<std::vector<SimDevice>(int frame)>& devices_at, const CostFn& cost,
    int frames, uint64_t seed = 0, const SimLink& link = {});

}  // namespace multiray::balance
