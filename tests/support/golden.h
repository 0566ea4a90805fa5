// Golden images that hold across machines. A reference is the distribution of a render
// at fixed settings over many seeds: per pixel and channel the mean and the variance of
// one render (tests/golden/<case>/, recorded by golden_record). A render on another
// machine differs from this machine's in the last bits of some hit distances, which sends
// some paths elsewhere: no worse than another seed. So the test asks whether the image
// could have come from the recorded distribution.
//
// Path-traced pixels are heavy-tailed (a rare path brings 100x the mean; a pixel that was
// black in all K recorded renders gets light in the next one), so no per-pixel variance
// from K renders bounds them and a plain chi-square over pixels fails honest renders.
// The statistics therefore give every block and channel a bounded influence:
//   z_B = sum_B (x - mean) / sqrt((1 + 1/K) sum_B var)     per block B and channel
//   "blocks NxN": sum over blocks of min(z_B^2, 16)         (local changes: a shifted
//                                                            camera, a missing object)
//   "mean shift": max over channels of |sum_B clip(z_B, -4, 4)| / sqrt(#B), 8x8 blocks
//                                                           (a global change: a BSDF)
// Each is a sum of many bounded terms, so it is close to normal; its mean and standard
// deviation under the null are measured when the reference is recorded, on seeds never
// recorded, and the limit is mean + 6 standard deviations (a normal statistic passes it
// falsely about once in 10^9 runs; estimating mean and deviation from 64 seeds costs a
// fraction of one deviation). (1 + 1/K) counts the reference mean's own noise.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/image.h"

namespace multiray::testing {

constexpr double kGoldenSigmas = 6;  // limit = null mean + 6 null standard deviations

// A statistic's distribution over seeds that were not recorded.
struct NullDistribution {
  double mean = 0, sd = 0;
  double limit() const { return mean + kGoldenSigmas * sd; }
};

struct GoldenReference {
  Framebuffer mean, var;  // var: variance of one render's pixel channel over seeds
  int renders = 0;        // K, the renders the statistics came from
  std::map<std::string, NullDistribution> null;  // by statistic name
};

struct GoldenStatistic {
  std::string name;  // "blocks 2x2", "blocks 8x8", "mean shift"
  double value = 0, limit = 0;
  bool pass() const { return value <= limit; }
};

struct GoldenVerdict {
  std::vector<GoldenStatistic> statistics;
  std::string problem;  // non-empty when the images cannot be compared at all
  bool pass() const;
  std::string summary() const;  // one line: every statistic against its limit
};

// The statistics of `image` against the reference's mean and variance (edge blocks are
// smaller). Limits come from ref.null; a statistic without one gets limit 0 (fails).
// A non-finite pixel or a size mismatch is a problem (fails).
GoldenVerdict compare_to_golden(const Framebuffer& image, const GoldenReference& ref);

// The null distributions of the statistics from `verdicts` of renders never recorded.
std::map<std::string, NullDistribution> null_of(const std::vector<GoldenVerdict>& verdicts);

// Running per-pixel mean and variance (Welford) of the renders of one image.
class GoldenAccumulator {
 public:
  void add(const Framebuffer& fb);
  GoldenReference reference() const;

 private:
  int n_ = 0;
  std::vector<double> mean_, m2_;
  int width_ = 0, height_ = 0;
};

// Files of one image of a reference: <stem>.mean.exr and <stem>.var.exr (32-bit float);
// the renders and null distributions live in the case's reference.json.
void write_golden(const std::string& stem, const GoldenReference& ref);
GoldenReference read_golden(const std::string& stem, int renders,
                            const std::map<std::string, NullDistribution>& null);

}  // namespace multiray::testing
