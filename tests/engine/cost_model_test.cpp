// The cost model (engine/cost_model.h) offline: a synthetic, deterministic sequence of
// frames with transfer-function switches fed into the KRLS models frame by frame, as the
// advisor does (predict, then train on the measured cost). No rendering, no timing: the
// errors depend on the numbers only.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/cost_model.h"
#include "engine/volume_advisor.h"

namespace multiray {
namespace {

// 300 frames: the camera swings ±45° about the volume every 75 frames and zooms in and
// out, so every view comes back; transfer function A on frames 0–74 and 150–224, B (more
// of the volume visible) on 75–149 and 225–299. A frame's shaded share follows the
// transfer function and wobbles with the view. Its cost per fetch-weighted sample, as the
// pre-pass counts it (shaded 1, transparent 1/7), is what a device measures whose shaded
// samples cost 30 transparent ones rather than 7 (gradient, shading and their cache
// misses): the pre-pass's weights then undercount a costlier transfer function, which
// the learned part has to make up.
struct Frame {
  CostFeatures x;
  double sigma;
};

std::vector<Frame> tf_switch_sequence() {
  std::vector<Frame> out;
  for (int f = 0; f < 300; ++f) {
    const double phase = 2 * 3.14159265358979 * f / 75;
    const double az = 0.785 * std::sin(phase), zoom = 0.85 + 0.15 * std::cos(phase);
    const bool b = (f / 75) % 2 == 1;
    const double share = (b ? 0.7 : 0.2) + 0.05 * std::sin(3 * az);
    const double fetches = 30 * share + (1 - share);  // per sample, transparent = 1
    const double weighted = 7 * share + (1 - share);  // what the pre-pass counts
    const double sigma = 1e-4 * fetches / weighted * (1 + 0.1 * std::sin(az)) / zoom;
    out.push_back({{az, 0.4, 0.8 * zoom, 0.5, 2.0, 230, share}, sigma});
  }
  return out;
}

// |predicted − measured| / measured of each frame, predicted before training on it.
std::vector<double> errors(const std::vector<Frame>& seq, const CostModelConfig& config) {
  CostModel m(config);
  std::vector<double> e;
  for (const Frame& fr : seq) {
    const double p = m.predict(fr.x);
    e.push_back(p > 0 ? std::abs(p - fr.sigma) / fr.sigma : 1.0);
    m.train(fr.x, fr.sigma);
  }
  return e;
}

double mean(const std::vector<double>& e, size_t from, size_t to) {
  double s = 0;
  for (size_t i = from; i < to; ++i) s += e[i];
  return s / double(to - from);
}

TEST(CostModel, SharedShareOfThePrepass) {
  EXPECT_DOUBLE_EQ(shaded_share(10, 10), 1.0);
  EXPECT_NEAR(shaded_share(10.0 / 7, 10), 0.0, 1e-12);
  EXPECT_NEAR(shaded_share(0.5 + 0.5 / 7, 1), 0.5, 1e-12);
  EXPECT_EQ(shaded_share(0, 0), 0.0);
  EXPECT_EQ(shaded_share(2, 1), 1.0);  // clamped
}

TEST(CostModel, TransferFunctionFeaturePredictsASwitchBack) {
  // Frames 150 and 225 switch to a transfer function seen before, at views seen before:
  // with the feature the model knows its cost on the frame of the switch; without it,
  // the model predicts the cost of the transfer function it just left (1.33x apart).
  const std::vector<Frame> seq = tf_switch_sequence();
  CostModelConfig without = CostModelConfig::ours();
  without.transfer_feature = false;
  const std::vector<double> with_tf = errors(seq, CostModelConfig::ours()),
                            no_tf = errors(seq, without);
  for (size_t f : {150, 225}) {
    std::printf("frame %zu: error %.3f with the feature, %.3f without\n", f, with_tf[f], no_tf[f]);
    EXPECT_LT(with_tf[f], 0.08) << f;
    EXPECT_GT(no_tf[f], 0.12) << f;
  }
  EXPECT_LT(mean(with_tf, 150, 300), 0.5 * mean(no_tf, 150, 300));
}

TEST(CostModel, PapersModelPredictsWorseThanOursAcrossSwitches) {
  // The paper's model (no transfer-function feature, σ learnt on unscaled features) does
  // not tell the two transfer functions apart: on the frames after each switch it
  // predicts the one it left, where ours, with the feature, knows both.
  const std::vector<Frame> seq = tf_switch_sequence();
  const std::vector<double> ours = errors(seq, CostModelConfig::ours()),
                            paper = errors(seq, CostModelConfig::paper());
  const double ours_mean = mean(ours, 10, 300), paper_mean = mean(paper, 10, 300);
  std::printf("mean prediction error, frames 10-299: ours %.4f, paper %.4f\n", ours_mean,
              paper_mean);
  EXPECT_LT(ours_mean, 0.5 * paper_mean);
}

TEST(CostModel, PapersModelIsThePapers) {
  const CostModelConfig p = CostModelConfig::paper();
  EXPECT_EQ(p.gamma, 0.00025);
  EXPECT_EQ(p.tolerance, 0.006);
  EXPECT_EQ(p.max_dictionary, 10000000u);
  EXPECT_FALSE(p.transfer_feature);
  EXPECT_FALSE(p.scaled_features);
  EXPECT_FALSE(p.log_cost);
  // σ itself is learnt on the features as given: a model of one observation predicts it
  // there and tends to (nearly) 0 away from it — dlib's KRLS adds 0.01 to the kernel, a
  // bias, so 1% of the cost remains. A log target would tend to the first cost seen, and
  // the span scaled by 1/256 would keep the far frame inside the kernel.
  CostModel m(p);
  const CostFeatures x{0.1, 0.2, 1.5, 0.5, 3.0, 200, 0.4}, far{0.1, 0.2, 1.5, 0.5, 3.0, 600, 0.4};
  m.train(x, 2e-4);
  EXPECT_NEAR(m.predict(x), 2e-4, 1e-9);
  // γ on the unscaled span: 400 voxels away the kernel is exp(-0.00025·400²) ≈ 4e-18.
  EXPECT_LT(m.predict(far), 0.02 * 2e-4);
  // The transfer function's feature does not count.
  CostFeatures other_tf = x;
  other_tf[kTransferFeature] = 0.9;
  EXPECT_EQ(m.predict(other_tf), m.predict(x));
}

TEST(CostModel, ParsesItsSettings) {
  EXPECT_EQ(parse_cost_model("ours").gamma, 0.5);
  EXPECT_EQ(parse_cost_model("paper").gamma, 0.00025);
  EXPECT_EQ(parse_cost_model("paper").tolerance, 0.006);
  EXPECT_FALSE(parse_cost_model("paper").transfer_feature);
  EXPECT_TRUE(parse_cost_model("paper:tf=1").transfer_feature);
  EXPECT_FALSE(parse_cost_model("paper").scaled_features);
  EXPECT_FALSE(parse_cost_model("ours:tf=0").transfer_feature);
  for (const char* bad : {"", "krls", "ours:tf=2", "paper:gamma=1", "ours:"})
    EXPECT_THROW(parse_cost_model(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace multiray
