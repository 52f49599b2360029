// SPDX-License-Identifier: Apache-2.0
// The χ² gate (core/measurement_gate.hpp) and the views' noise scales (core/view_noise_scales.hpp).

#include <random>

#include <gtest/gtest.h>

#include "stgf/core/measurement_gate.hpp"
#include "stgf/core/view_noise_scales.hpp"

namespace stgf {
namespace {

Gaussian3 at(double x, double variance = 0.01) {
  return Gaussian3::from_covariance(Vector3d(x, 0.0, 0.0), variance * Matrix3d::Identity());
}

TEST(MeasurementGate, ThresholdIsTheChiSquareQuantile) {
  EXPECT_NEAR(chi_square_3_quantile(0.5), 2.365973884, 1e-8);
  EXPECT_NEAR(chi_square_3_quantile(0.95), 7.814727903, 1e-8);
  EXPECT_NEAR(chi_square_3_quantile(0.999), 16.26623620, 1e-7);
  EXPECT_NEAR(MeasurementGate(GateOptions{true, 0.999}).threshold(), 16.26623620, 1e-7);
  EXPECT_THROW(MeasurementGate(GateOptions{true, 1.0}), std::invalid_argument);
  EXPECT_THROW(MeasurementGate(GateOptions{true, 0.0}), std::invalid_argument);
}

TEST(MeasurementGate, ConsensusLeavesOutTheOneThatAgreesWithNoOne) {
  const MeasurementGate gate(GateOptions{true, 0.999});
  const std::vector<Gaussian3> rows{at(5.0), at(0.0), at(0.05), at(-0.05)};  // σ = 0.1 m; 5 m is 35σ off
  const MeasurementGate::Consensus consensus = gate.consensus(rows);
  EXPECT_TRUE(consensus.agreement);
  EXPECT_EQ(consensus.anchor, 1u);
  EXPECT_EQ(consensus.passes, (std::vector<bool>{false, true, true, true}));
  // Two that disagree: nothing tells which is faulty; both pass.
  const std::vector<Gaussian3> two{at(5.0), at(0.0)};
  EXPECT_FALSE(gate.consensus(two).agreement);
  EXPECT_EQ(gate.consensus(two).passes, (std::vector<bool>{true, true}));
  // Disabled: everything passes.
  EXPECT_EQ(MeasurementGate(GateOptions{false, 0.999}).consensus(rows).passes, (std::vector<bool>(4, true)));
}

TEST(MeasurementGate, DecidesAgainstThePredictionAndRestartsAWrongTrack) {
  const MeasurementGate gate(GateOptions{true, 0.999});
  const std::vector<Gaussian3> rows{at(0.0), at(0.05), at(8.0)};
  // The prediction agrees with the first two: the third is left out, no restart.
  MeasurementGate::Decision decision = gate.decide(std::vector<double>{1.0, 2.0, 900.0}, rows, 0);
  EXPECT_TRUE(decision.checked);
  EXPECT_FALSE(decision.restart);
  EXPECT_EQ(decision.passes, (std::vector<bool>{true, true, false}));
  // The prediction agrees with the outlier only, and the other two agree with each other: the track
  // is what is wrong; it starts again from the two.
  decision = gate.decide(std::vector<double>{400.0, 420.0, 3.0}, rows, 0);
  EXPECT_TRUE(decision.restart);
  EXPECT_EQ(decision.passes, (std::vector<bool>{true, true, false}));
  // One view, failing: left out twice, then the track starts again from it.
  const std::vector<Gaussian3> one{at(3.0)};
  EXPECT_FALSE(gate.decide(std::vector<double>{100.0}, one, 0).restart);
  EXPECT_EQ(gate.decide(std::vector<double>{100.0}, one, 0).passes, std::vector<bool>{false});
  EXPECT_FALSE(gate.decide(std::vector<double>{100.0}, one, kGatedEventsBeforeRestart - 2).restart);
  EXPECT_TRUE(gate.decide(std::vector<double>{100.0}, one, kGatedEventsBeforeRestart - 1).restart);
  // A younger track (restart_after 1): the first failure starts it again.
  EXPECT_TRUE(gate.decide(std::vector<double>{100.0}, one, 0, 1).restart);
  // No prediction: the consensus decides.
  decision = gate.decide({}, rows, 0);
  EXPECT_FALSE(decision.restart);
  EXPECT_FALSE(decision.conflicting);
  EXPECT_EQ(decision.passes, (std::vector<bool>{true, true, false}));
}

// Two measurements of a new object that do not agree: both pass, and the decision says they conflict
// (the filter then widens what it starts from them); with a prediction to check against, or one that
// agrees, they do not.
TEST(MeasurementGate, SaysWhenMeasurementsWithoutAPredictionConflict) {
  const MeasurementGate gate(GateOptions{true, 0.999});
  const std::vector<Gaussian3> two{at(5.0), at(0.0)};
  MeasurementGate::Decision decision = gate.decide({}, two, 0);
  EXPECT_TRUE(decision.conflicting);
  EXPECT_EQ(decision.passes, (std::vector<bool>{true, true}));
  EXPECT_FALSE(gate.decide(std::vector<double>{400.0, 1.0}, two, 0).conflicting);
  EXPECT_FALSE(gate.decide({}, std::vector<Gaussian3>{at(0.05), at(0.0)}, 0).conflicting);
  EXPECT_FALSE(gate.decide({}, std::vector<Gaussian3>{at(5.0)}, 0).conflicting);
  EXPECT_FALSE(MeasurementGate(GateOptions{false, 0.999}).decide({}, two, 0).conflicting);
}

// Innovations of a view against the others' mean, with noise `factor` times what R states.
void feed(ViewNoiseScales& scales, const std::string& view, double factor, int count, std::mt19937_64& random,
          double outlier_share = 0.0) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform;
  const Matrix3d r = 0.04 * Matrix3d::Identity();
  const Matrix3d others = 0.01 * Matrix3d::Identity();
  for (int k = 0; k < count; ++k) {
    const double sd = std::sqrt(0.04 * factor + 0.01);
    Vector3d innovation(sd * normal(random), sd * normal(random), sd * normal(random));
    if (uniform(random) < outlier_share) innovation.x() += 10.0;
    scales.add(view, 0.1 * k, innovation, others, Matrix3d::Zero(), r);  // the others' noise does not recur
  }
}

TEST(ViewNoiseScales, RaisesOnlyTheViewThatUnderstatesItsNoise) {
  std::mt19937_64 random(3);
  ViewNoiseScales scales;
  feed(scales, "good", 1.0, 300, random);
  feed(scales, "outliers", 1.0, 300, random, 0.05);
  feed(scales, "understated", 100.0, 300, random);
  EXPECT_EQ(scales.scale("good"), 1.0);
  EXPECT_EQ(scales.scale("outliers"), 1.0);  // the median ignores them (the gate handles them)
  EXPECT_GT(scales.scale("understated"), 30.0);
  EXPECT_LT(scales.scale("understated"), 300.0);
  EXPECT_EQ(scales.scale("unknown"), 1.0);
  const auto reports = scales.reports();
  EXPECT_EQ(reports.at("good").largest_scale, 1.0);
  EXPECT_TRUE(std::isnan(reports.at("good").first_flagged_time));
  EXPECT_GT(reports.at("understated").largest_scale, 30.0);
  // Found within its first window (the tests start at kRecent measurements).
  EXPECT_GE(reports.at("understated").first_flagged_time, 0.1 * (ViewNoiseScales::kRecent - 1) - 1e-12);
  EXPECT_LE(reports.at("understated").first_flagged_time, 0.1 * (ViewNoiseScales::kWindow - 1) + 1e-12);
}

TEST(ViewNoiseScales, CountsWhatTheGateChecked) {
  ViewNoiseScales scales;
  scales.count("a", true);
  scales.count("a", false);
  scales.count("b", true);
  GatingSummary summary;
  summary.add("s", scales);
  EXPECT_EQ(summary.checked, 3u);
  EXPECT_EQ(summary.gated, 1u);
  ASSERT_EQ(summary.views.size(), 1u);  // only views with something to report
  EXPECT_EQ(summary.views[0].view, "a");
  EXPECT_EQ(summary.views[0].scene, "s");
}

}  // namespace
}  // namespace stgf
