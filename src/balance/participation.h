// Which devices take part in a frame (multiray's own rule, used by hybrid and so by `auto`):
// a device that pays a fixed cost every frame it renders anything (an upload, a kernel
// launch, a read-back, a wake-up; a phone's round trip over Wi-Fi) makes the frame wait
// for that cost however small its share. When the cost is larger than what the device's
// share would save the others, adding the device makes the frame slower; such a device is
// left out: it gets nothing, and a device given nothing does nothing that frame.
//
// Model. Device i renders n cost units of a frame in t_i = F_i + n / s_i: a fixed cost
// F_i per frame and a speed s_i, fitted by least squares to its own (work, time) reports,
// older frames fading (DeviceCostFit). With every device of a set S finishing together at
// T, Σ_{i∈S} s_i (T − F_i) = total, so T(S) = (total + Σ s_i F_i) / Σ s_i, valid while
// every F_i < T. The set with the least T is a prefix of the devices sorted by F_i (a
// device with a larger fixed cost never helps when one with a smaller one does not), so
// choose_participants tries each prefix.
//
// Contention. A device at work can slow the others (two vCPUs shared by a CPU device and
// a driver's threads; a GPU's feeding thread on a busy CPU). Each device's `contention`,
// the others' speed with it over without it, is measured whenever it alone changes
// between two frames (it is left out, or rested for one frame on the probes' schedule
// while it saves under 10% of the frame with a fixed cost over 2% of it), and T(S) takes
// every other device's speed times the contention of the devices taking part with it.
//
// Uncertainty. A device is kept only when it saves more than `margin` of the frame: near
// the break-even point leaving a device out costs at most that margin, keeping a useless
// one costs its whole F_i. Its fit's standard error is reported beside F_i.
// A device whose fixed cost is not determined (fewer than three frames, or frames of too
// alike a work: a device that always renders about the same share) takes part, modelled
// with no fixed cost and its mean speed; a device with no report at all takes part.
#pragma once

#include <string>
#include <vector>

namespace multiray::balance {

// What the fit knows of one device.
struct DeviceCostModel {
  double speed = 0;        // cost units per ms; 0: not determined
  double fixed_ms = 0;     // F_i, ms per frame it renders anything
  double fixed_sigma = 0;  // standard error of fixed_ms
  bool determined = false;
  // The others' speed while this device takes part, over their speed while it does not
  // (shared cores, memory, a driver's threads): measured on consecutive frames whose only
  // difference is this device; 1 until measured, never above 1.
  double contention = 1;
};

// Weighted least squares of a device's frame time on its work, each frame's weight
// multiplied by `memory` per later frame.
class DeviceCostFit {
 public:
  explicit DeviceCostFit(double memory = 0.9) : memory_(memory) {}
  // One frame: `work` cost units (0: it was started and did nothing) in `time_ms`.
  // Ignores negative or non-finite work and non-positive or non-finite times.
  void add(double work, double time_ms);
  // Forgets every frame.
  void clear() { *this = DeviceCostFit(memory_); }
  // The unit of work now costs 1/r of what it did (the device's speed in units per ms was
  // multiplied by r: more samples a pixel, another scene): the frames kept are restated
  // in the new unit (n becomes r·n at the same time), fixed cost untouched.
  void rescale_work(double r);
  DeviceCostModel model() const;
  int frames() const { return frames_; }

 private:
  double memory_;
  double w_ = 0, x_ = 0, y_ = 0, xx_ = 0, xy_ = 0, yy_ = 0;  // weighted sums
  double w2_ = 0;  // Σ weight², for the effective number of frames
  int frames_ = 0;
};

// T(S): the frame time when the devices with take[i] split `total` cost units so that
// they finish together; +inf when none is taken.
double predicted_frame_ms(const std::vector<DeviceCostModel>& models,
                          const std::vector<bool>& take, double total);

// The devices to take part of the `eligible` ones (alive, not dropped): the prefix by
// fixed cost with the least T, a device after the fastest prefix kept only while it
// makes T smaller by more than `margin` (relative). Devices without a determined fixed
// cost are always taken. Never empty when some device is eligible.
std::vector<bool> choose_participants(const std::vector<DeviceCostModel>& models,
                                      const std::vector<bool>& eligible, double total,
                                      double margin);

// The reason a device taking part gives when it is rested for one frame to measure what
// it saves (ParticipationTracker, kRestProbeSaving): not left out, only measured.
inline constexpr const char* kMeasuringRestReason = "rested for a frame to measure what it saves";

// One line on why a device is left out of a `frame_ms` frame: "75 ms fixed per frame
// against a 44 ms frame", or when its fixed cost is below the frame, "it would save less
// than 3% of a 44 ms frame (2 ms fixed per frame)".
std::string left_out_reason(const DeviceCostModel& model, double frame_ms, double margin);

// The rule over a run: each device's fit, which devices are left out, and when each is
// probed. A left-out device is probed (given a small share, alternately kProbeShares[0]
// and [1] of the frame, so that its fit sees different amounts of work) `probe` frames
// after it was left out, then after twice as many, up to 8 x `probe`; at once after a
// change (changed()); and every frame while its fit is not determined. A probe that
// shows it would pay brings it back.
class ParticipationTracker {
 public:
  struct Options {
    bool leave = true;     // false: every alive device always takes part (the rule off)
    int probe = 8;         // frames before a left-out device's first probe; 0: never
    double margin = 0.03;  // a device is kept only if it saves more of the frame than this
  };
  static constexpr double kProbeShares[2] = {0.005, 0.02};
  // A device taking part is rested for a frame while it is predicted to save less than
  // kRestProbeSaving of the frame, kFirstRest frames after it starts, so that what it
  // saves, and what it costs the others (its contention, which no fit of its own times
  // can show), is measured, not only predicted. It is rested again (after `probe`
  // frames, then twice as many, up to 8 x `probe`) only while it costs visibly: a fixed
  // cost over kRestProbeFixed of the frame, or contention below kContentionSeen. A rest
  // costs at most kRestProbeSaving of one frame; among equal devices it happens from 11.
  static constexpr double kRestProbeSaving = 0.10;
  static constexpr double kRestProbeFixed = 0.02;
  static constexpr int kFirstRest = 4;
  // Contention below this (the others ~5% slower while the device works) is a measured
  // cost: the device is judged by the rule even without a determined fit.
  static constexpr double kContentionSeen = 0.95;

  ParticipationTracker(int devices, const Options& options);

  struct Decision {
    std::vector<bool> rest;           // left out: no work this frame
    std::vector<double> probe;        // share of the frame each probed device gets, or 0
    std::vector<std::string> reason;  // why each resting device rests ("" otherwise)
    std::vector<DeviceCostModel> models;
    double predicted_ms = 0;  // T of the devices taking part (probes aside)
  };
  // The frame's decision for the `alive` devices and `total` cost units of work. A device
  // without a determined fixed cost, or whose speed the fit does not know, is taken at
  // `speed[i]` (the balancer's own estimate, which follows a change at once; the fit's
  // mean speed trails it), if given and > 0.
  Decision decide(const std::vector<bool>& alive, double total,
                  const std::vector<double>& speed = {});
  // What device i rendered of the frame last decided: `work` cost units in `time_ms`.
  void measured(size_t i, double work, double time_ms);
  // The cost of work changed (a device's speed jumped, or the frame's size): left-out
  // devices are probed next frame; with `refit`, their fits start again.
  void changed(bool refit);
  // Device i's unit of work now costs 1/r of what it did (DeviceCostFit::rescale_work).
  void rescale(size_t i, double r);
  // Who took part in the frame last decided and each device's measured speed (0: none):
  // where exactly one device changed from the frame before, the others' speeds are a
  // sample of its contention. Not with `sample` false (a probe's small share was at work
  // in this frame or the last: too briefly to slow the others as a share would).
  void frame_speeds(const std::vector<bool>& took_part, const std::vector<double>& speed,
                    bool sample = true);
  DeviceCostModel model(size_t i) const {
    return i < fit_.size() ? fit_[i].model() : DeviceCostModel{};
  }
  bool left_out(size_t i) const { return i < out_.size() && out_[i]; }

 private:
  Options opt_;
  std::vector<DeviceCostFit> fit_;
  std::vector<bool> out_;    // left out (probed or not)
  std::vector<int> since_;   // frames since left out or last probed
  std::vector<int> every_;   // frames between probes
  std::vector<int> probes_;  // probes so far (alternates the probe share)
  // A device taking part that saves little is rested for a frame now and then, to see
  // what it saves (and its contention): frames since, and between, those rests.
  std::vector<int> since_in_, every_in_, rests_;
  // Whether taking-part device i rests this frame to be measured (`may`: no other does).
  bool rest_to_measure(size_t i, const Decision& d, const std::vector<bool>& take, double total,
                       bool may);
  std::vector<double> log_contention_;  // mean log of the contention samples
  std::vector<int> contention_samples_;
  std::vector<bool> last_took_;
  std::vector<double> last_speed_;
  bool recheck_ = false;
};

}  // namespace multiray::balance
