// SPDX-License-Identifier: Apache-2.0
// `ours` as a streaming filter: with one view and a constant-velocity predictor it is exactly a
// Kalman filter (H = I); steps with no views change nothing; views may join mid-scene.

#include "stgf/methods/spatiotemporal_graph_filter.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "stgf/core/metrics.hpp"
#include "stgf/core/multi_view_update.hpp"
#include "support/test_predictors.hpp"

namespace stgf {
namespace {

Measurement measurement(double time, const std::string& view, const std::string& object, const Vector3d& z,
                        const Matrix3d& r) {
  return Measurement{"s", time, view, object, Gaussian3::from_covariance(z, r), std::nullopt};
}

std::vector<Gaussian3> step(SpatiotemporalGraphFilter& filter, double time, const std::vector<Measurement>& rows) {
  std::vector<const Measurement*> pointers;
  for (const Measurement& row : rows) pointers.push_back(&row);
  return filter.step(time, pointers);
}

// The Kalman update with H = I, written out with explicit inverses.
void kalman_update(Vector3d& x, Matrix3d& p, const Vector3d& z, const Matrix3d& r) {
  const Matrix3d gain = p * (p + r).inverse();
  x = x + gain * (z - x);
  p = (Matrix3d::Identity() - gain) * p;
}

TEST(SpatiotemporalGraphFilter, OneViewWithConstantVelocityIsAKalmanFilter) {
  const double q = 0.3, speed = 1.5, dt = 0.25;
  const ConstantVelocityPredictor predictor(q, speed);
  // The textbook filter's prediction trusts the velocity of the last two fused positions as exact: so
  // does this one without the history's velocity error (object_track.hpp).
  FilterOptions options{RegistrationPrior{}, /*adapt_process_noise=*/false};
  options.history_velocity_error = false;
  SpatiotemporalGraphFilter filter(predictor, options);
  Matrix3d r;
  r << 0.04, 0.01, 0, 0.01, 0.09, 0.002, 0, 0.002, 0.02;
  const std::vector<Vector3d> zs = {{1.0, 2.0, 0.0}, {1.4, 2.1, 0.05}, {1.9, 2.3, -0.02}, {2.3, 2.2, 0.0}, {2.8, 2.4, 0.01}};

  // Reference: diffuse start (P⁻¹ = 0: the first estimate is the measurement), then predict with
  // the velocity of the last two fused positions.
  std::vector<Vector3d> fused;
  Vector3d x = zs[0];
  Matrix3d p = r;
  for (std::size_t k = 0; k < zs.size(); ++k) {
    if (k > 0) {
      const Vector3d velocity = k >= 2 ? Vector3d((fused[k - 1] - fused[k - 2]) / dt) : Vector3d::Zero();
      x = fused[k - 1] + velocity * dt;
      p = p + q * dt * dt * Matrix3d::Identity();
      if (k == 1) p += (speed * dt) * (speed * dt) * Matrix3d::Identity();
    }
    if (k > 0) kalman_update(x, p, zs[k], r);
    fused.push_back(x);
    const double time = static_cast<double>(k) * dt;
    const std::vector<Gaussian3> estimates = step(filter, time, {measurement(time, "v", "o", zs[k], r)});
    ASSERT_EQ(estimates.size(), 1u);
    EXPECT_LT((estimates[0].mean() - x).norm(), 1e-9) << "step " << k;
    EXPECT_LT((estimates[0].covariance() - p).norm(), 1e-9) << "step " << k;
  }
}

TEST(SpatiotemporalGraphFilter, StepWithoutViewsChangesNothing) {
  const ConstantVelocityPredictor predictor(0.1, 1.0);
  SpatiotemporalGraphFilter with_gap(predictor), reference(predictor);
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  for (SpatiotemporalGraphFilter* filter : {&with_gap, &reference}) {
    step(*filter, 0.0, {measurement(0.0, "v", "o", Vector3d(0, 0, 0), r)});
    step(*filter, 0.1, {measurement(0.1, "v", "o", Vector3d(0.1, 0, 0), r)});
  }
  EXPECT_TRUE(step(with_gap, 0.2, {}).empty());
  const auto a = step(with_gap, 0.3, {measurement(0.3, "v", "o", Vector3d(0.3, 0, 0), r)});
  const auto b = step(reference, 0.3, {measurement(0.3, "v", "o", Vector3d(0.3, 0, 0), r)});
  EXPECT_EQ(a[0].mean(), b[0].mean());
  EXPECT_EQ(a[0].covariance(), b[0].covariance());
}

// Per-view tracks (the paper's form): a view that joins mid-scene starts diffuse, so its first
// estimate is (almost exactly) the information-weighted mean of the step's measurements, while the
// older view fuses its prediction. With one track per object, both rows get the object's estimate.
TEST(SpatiotemporalGraphFilter, ViewJoiningMidSceneStartsFromTheMeasurements) {
  const ConstantVelocityPredictor predictor(0.1, 1.0);
  FilterOptions per_view;
  per_view.tracks = TrackMode::kPerView;
  SpatiotemporalGraphFilter filter(predictor, per_view), per_object(predictor);
  const Matrix3d r = 0.04 * Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) {
    for (SpatiotemporalGraphFilter* f : {&filter, &per_object}) {
      step(*f, 0.1 * k, {measurement(0.1 * k, "a", "o", Vector3d(0.1 * k, 0, 0), r)});
    }
  }
  const std::vector<Measurement> rows = {measurement(0.3, "a", "o", Vector3d(0.32, 0, 0), r),
                                         measurement(0.3, "b", "o", Vector3d(0.28, 0.02, 0), r)};
  const std::vector<Gaussian3> estimates = step(filter, 0.3, rows);
  ASSERT_EQ(estimates.size(), 2u);
  const Gaussian3 mean = information_weighted_mean(std::vector<Gaussian3>{rows[0].position, rows[1].position});
  EXPECT_LT((estimates[1].mean() - mean.mean()).norm(), 1e-5);
  EXPECT_LT(estimates[0].covariance().trace(), estimates[1].covariance().trace());  // a had a prediction too
  // Both views keep tracking from here.
  const auto next = step(filter, 0.4, {measurement(0.4, "b", "o", Vector3d(0.4, 0.01, 0), r)});
  EXPECT_LT(next[0].covariance().trace(), 3 * 0.04);

  const std::vector<Gaussian3> shared = step(per_object, 0.3, rows);
  EXPECT_EQ(shared[0].mean(), shared[1].mean());
  EXPECT_EQ(shared[0].covariance(), estimates[0].covariance());  // a's track, with both views fused
}

}  // namespace
// An object a view has not seen for longer than the predictor's horizon starts again in that view:
// diffuse, so the estimate is the measurement, however far the old track would have extrapolated.
// Within the horizon the track carries on.
TEST(SpatiotemporalGraphFilter, TrackUnseenBeyondTheHorizonStartsAgain) {
  const ConstantVelocityPredictor predictor(0.1, 1.0, /*horizon=*/0.5);
  // Without the gate: this predictor's typical speed (1 m/s) is far below the object's (10 m/s), so
  // the gate would (rightly) restart the track for that before the horizon does.
  FilterOptions options{RegistrationPrior{}, false};
  options.gate.enabled = false;
  SpatiotemporalGraphFilter filter(predictor, options);
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) step(filter, 0.1 * k, {measurement(0.1 * k, "v", "o", Vector3d(k, 0, 0), r)});  // 10 m/s
  const auto within = step(filter, 0.6, {measurement(0.6, "v", "o", Vector3d(6, 0, 0), r)});  // 0.4 s later
  EXPECT_EQ(filter.restarted_tracks(), 0u);
  EXPECT_LT(within[0].covariance()(0, 0), 0.01);  // the prediction helped
  const auto beyond = step(filter, 1.2, {measurement(1.2, "v", "o", Vector3d(3, 1, 0), r)});  // 0.6 s later, turned back
  EXPECT_EQ(filter.restarted_tracks(), 1u);
  EXPECT_LT((beyond[0].mean() - Vector3d(3, 1, 0)).norm(), 1e-5);
  EXPECT_NEAR(beyond[0].covariance()(0, 0), 0.01, 1e-7);
  ASSERT_TRUE(filter.last_predictions()[0] == std::nullopt);
  // The new track has one position: the next step predicts from it, not from the old track.
  step(filter, 1.3, {measurement(1.3, "v", "o", Vector3d(3, 1.1, 0), r)});
  ASSERT_TRUE(filter.last_predictions()[0].has_value());
  EXPECT_EQ(filter.last_predictions()[0]->history_positions, 1u);
}

// A world frame far from its origin (UTM coordinates) changes nothing: the estimates move with the
// frame, to the precision of the coordinates, with and without registration handling.
TEST(SpatiotemporalGraphFilter, EstimatesDoNotDependOnWhereTheWorldOriginIs) {
  const ConstantVelocityPredictor predictor(0.2, 1.0);
  const Vector3d origin(512345.0, 4123456.0, 210.0);
  for (const RegistrationPrior& registration : {RegistrationPrior{}, RegistrationPrior{Vector3d(0.2, 0.2, 0.0), Vector3d::Constant(0.5)}}) {
    SpatiotemporalGraphFilter near(predictor, {registration, true}), far(predictor, {registration, true});
    std::mt19937_64 random(4);
    std::normal_distribution<double> normal;
    for (int k = 0; k < 30; ++k) {
      const double t = 0.1 * k;
      std::vector<Measurement> rows_near, rows_far;
      for (const char* view : {"a", "b", "c"}) {
        for (const char* object : {"o", "p"}) {
          const Vector3d z = Vector3d(t, object[0] == 'o' ? 0.0 : 2.0, 0.0) +
                             0.1 * Vector3d(normal(random), normal(random), normal(random));
          const Matrix3d r = (view[0] == 'a' ? 0.01 : 0.03) * Matrix3d::Identity();
          if (k == 10 && view[0] == 'b') continue;  // a view missing for a step
          rows_near.push_back(measurement(t, view, object, z, r));
          rows_far.push_back(measurement(t, view, object, z + origin, r));
        }
      }
      const auto a = step(near, t, rows_near);
      const auto b = step(far, t, rows_far);
      for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_LT((b[i].mean() - origin - a[i].mean()).norm(), 1e-6) << "step " << k;
        EXPECT_LT((b[i].covariance() - a[i].covariance()).norm(), 1e-9) << "step " << k;
      }
    }
  }
}

// Two views measure an object that turns hard (6 m/s on a 3 m circle) every 0.1 s for 6 s: the mean
// NEES of each filter's estimates from 1 s on.
std::pair<double, double> nees_on_a_hard_turn(SpatiotemporalGraphFilter& adaptive, SpatiotemporalGraphFilter& fixed) {
  std::mt19937_64 random(9);
  std::normal_distribution<double> normal;
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  double nees_adaptive = 0.0, nees_fixed = 0.0;
  int count = 0;
  for (int k = 0; k < 60; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(3.0 * std::cos(t * 2.0), 3.0 * std::sin(t * 2.0), 0.0);
    std::vector<Measurement> rows;
    for (const char* view : {"a", "b"}) {
      const Vector3d z = truth + 0.1 * Vector3d(normal(random), normal(random), normal(random));
      rows.push_back(Measurement{"s", t, view, "o", Gaussian3::from_covariance(z, r), std::nullopt});
    }
    const Gaussian3 a = step(adaptive, t, rows)[0];
    const Gaussian3 f = step(fixed, t, rows)[0];
    if (k >= 10) {
      nees_adaptive += a.mahalanobis_squared(truth);
      nees_fixed += f.mahalanobis_squared(truth);
      ++count;
    }
  }
  return {nees_adaptive / count, nees_fixed / count};
}

// A predictor far worse than its Q says (constant velocity, tiny Q, the hard turn): with adaptation
// the filter scales Q up and its estimates stay consistent; without, it trusts the predictions and
// its NEES explodes.
TEST(SpatiotemporalGraphFilter, AdaptsQWhenPredictionsAreWorseThanItSays) {
  const ConstantVelocityPredictor predictor(1e-4, 1.0);
  // Without the gate, which would leave out the measurements that Q says are impossible (and restart
  // the track): this is about what the adaptation learns from all of them.
  FilterOptions adaptive_options, fixed_options{RegistrationPrior{}, false};
  adaptive_options.gate.enabled = fixed_options.gate.enabled = false;
  // Q alone: the velocity error read off the noisy positions would otherwise account for much of the
  // turn's (below, HistorysVelocityErrorIsWhatQAdaptationLearntOfIt).
  adaptive_options.history_velocity_error = fixed_options.history_velocity_error = false;
  SpatiotemporalGraphFilter adaptive(predictor, adaptive_options), fixed(predictor, fixed_options);
  const auto [nees_adaptive, nees_fixed] = nees_on_a_hard_turn(adaptive, fixed);
  EXPECT_GT(adaptive.process_noise_scales().x(), 100.0);
  EXPECT_GT(adaptive.process_noise_scales().y(), 100.0);
  EXPECT_EQ(fixed.process_noise_scales(), Vector3d::Ones());
  EXPECT_LT(nees_adaptive, 6.0);
  EXPECT_GT(nees_fixed, 50.0);
}

// Twelve views whose noise (σ = 0.3 m across, 0.01 m up) is far larger than the prediction's error:
// one view's innovation hardly shows that Q is too small, the views' combined innovation (noise
// R/12) does (design §1.2). A pedestrian-like turn (1.5 m/s on a 2 m circle) every 0.1 s for 20 s,
// predicted by constant velocity with a Q far below what the turn needs, the views' offsets
// estimated jointly with the positions: λ grows, also up, where nothing moves but the velocity read
// off the noisy positions errs by more than Q says, and the estimates stay consistent (mean NEES
// from 2 s on; with the first view's innovation alone, λ stayed 1 up and NEES was 318).
// The mean NEES from 2 s on of `filter` on the walk below, seen by twelve noisy views.
double nees_of_twelve_noisy_views(SpatiotemporalGraphFilter& filter) {
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal;
  const Matrix3d r = Vector3d(0.09, 0.09, 1e-4).asDiagonal();
  double nees = 0.0;
  int count = 0;
  for (int k = 0; k < 200; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(2.0 * std::cos(0.75 * t), 2.0 * std::sin(0.75 * t), 0.0);
    std::vector<Measurement> rows;
    for (int view = 0; view < 12; ++view) {
      const Vector3d z = truth + Vector3d(0.3 * normal(random), 0.3 * normal(random), 0.01 * normal(random));
      rows.push_back(measurement(t, "v" + std::to_string(view), "o", z, r));
    }
    const Gaussian3 estimate = step(filter, t, rows)[0];
    if (k >= 20) {
      nees += estimate.mahalanobis_squared(truth);
      ++count;
    }
  }
  return nees / count;
}

FilterOptions twelve_views_options() {
  FilterOptions options;
  options.registration = RegistrationPrior{Vector3d(0.01, 0.01, 0.0), Vector3d::Constant(0.1)};
  options.gate.enabled = false;
  options.motion_fallback = MotionFallback::kOff;
  return options;
}

TEST(SpatiotemporalGraphFilter, LearnsQFromTheViewsCombinedInnovation) {
  const ConstantVelocityPredictor predictor(1e-5, 1.0);
  FilterOptions options = twelve_views_options();
  options.history_velocity_error = false;  // Q alone (the test below counts the velocity's error apart)
  SpatiotemporalGraphFilter filter(predictor, options);
  const double nees = nees_of_twelve_noisy_views(filter);
  EXPECT_GT(filter.process_noise_scales().x(), 10.0);
  EXPECT_GT(filter.process_noise_scales().y(), 10.0);
  EXPECT_GT(filter.process_noise_scales().z(), 4.0);
  EXPECT_LT(nees, 4.5);
}

// On the same walk most of what λ learnt is the error of the velocity read off the noisy fused
// positions (object_track.hpp, Var(v̂)): counted, the filter is honest without scaling Q; left out and
// not learnt, its NEES is many times 3; counted and learnt, honest too. (While Var(v̂) counted the
// positions' errors independent, overstating the slope's error of positions smoothed this much, λ
// also stayed below 3; counted with their correlation, what remains is constant velocity's error on
// the turn, and λ learns it: on this walk λ_y reaches 2^15.5, λQ 0.0046 m² a step, near the views'
// combined noise 0.0075 m², and λ_x stays 1 — one scene's λ on a grid jumps between modes.)
TEST(SpatiotemporalGraphFilter, CountsTheErrorOfTheVelocityReadOffNoisyPositions) {
  const ConstantVelocityPredictor predictor(1e-5, 1.0);
  FilterOptions counted = twelve_views_options(), neither = twelve_views_options();
  counted.adapt_process_noise = neither.adapt_process_noise = false;
  neither.history_velocity_error = false;
  SpatiotemporalGraphFilter with_it(predictor, counted), without(predictor, neither);
  const double nees_with = nees_of_twelve_noisy_views(with_it);
  const double nees_without = nees_of_twelve_noisy_views(without);
  EXPECT_GT(nees_with, 1.5);
  EXPECT_LT(nees_with, 4.5);
  EXPECT_GT(nees_without, 20.0);
  FilterOptions learning = twelve_views_options();
  SpatiotemporalGraphFilter learns(predictor, learning);
  const double nees_learning = nees_of_twelve_noisy_views(learns);
  EXPECT_GT(nees_learning, 1.5);
  EXPECT_LT(nees_learning, 4.5);
}

// Constant velocity that hands every track with two history positions to coasting (its widest history
// spacing is below the step): Φ's Q and the coasting Q are both far too small.
class HandsEveryHistoryToCoastingPredictor final : public testing::ForwardingPredictor {
 public:
  HandsEveryHistoryToCoastingPredictor() : ForwardingPredictor(1e-4, 1.0, std::numeric_limits<double>::infinity()) {}
  double widest_history_spacing() const override { return 0.05; }  // its coasting Q: process_noise
};

// The same with tracks that coast (design §1.9): their innovations teach the coasting λ, which scales
// the coasting Q, and Φ's λ stays as it was. With one track per object and offsets estimated jointly,
// and without offsets.
TEST(SpatiotemporalGraphFilter, AdaptsTheCoastingQWhenCoastingIsWorseThanItSays) {
  for (const bool joint : {false, true}) {
    const HandsEveryHistoryToCoastingPredictor predictor;
    FilterOptions adaptive_options, fixed_options;
    fixed_options.adapt_process_noise = false;
    adaptive_options.gate.enabled = fixed_options.gate.enabled = false;  // as above
    adaptive_options.history_velocity_error = fixed_options.history_velocity_error = false;
    if (joint) adaptive_options.registration.translation_sigma = fixed_options.registration.translation_sigma = Vector3d(0.01, 0.01, 0.0);
    SpatiotemporalGraphFilter adaptive(predictor, adaptive_options), fixed(predictor, fixed_options);
    const auto [nees_adaptive, nees_fixed] = nees_on_a_hard_turn(adaptive, fixed);
    EXPECT_GT(adaptive.coasting_noise_scales().x(), 100.0) << "joint " << joint;
    EXPECT_GT(adaptive.coasting_noise_scales().y(), 100.0) << "joint " << joint;
    EXPECT_EQ(adaptive.process_noise_scales(), Vector3d::Ones()) << "joint " << joint;
    EXPECT_EQ(fixed.coasting_noise_scales(), Vector3d::Ones()) << "joint " << joint;
    // Jointly, the offsets (estimated with every position) take up part of the prediction errors
    // while λ is still small, and the NEES settles a little higher.
    EXPECT_LT(nees_adaptive, joint ? 8.0 : 6.0) << "joint " << joint;
    EXPECT_GT(nees_fixed, 50.0) << "joint " << joint;
  }
}

}  // namespace stgf

namespace stgf {
namespace {

// Three views watch an object walking a straight line; at one time view "b" reports it 10 m off. With
// the gate that measurement is left out, counted, and the estimate stays on the object; without (the
// default), it drags the estimate most of a metre away.
TEST(SpatiotemporalGraphFilter, GatesAGrossErrorOfOneView) {
  const ConstantVelocityPredictor predictor(0.01, 1.0);
  FilterOptions with_gate;
  with_gate.gate.enabled = true;
  SpatiotemporalGraphFilter gated(predictor, with_gate), ungated(predictor);
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal;
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  for (int k = 0; k < 20; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(1.0 * t, 0.5 * t, 0.0);
    std::vector<Measurement> rows;
    for (const char* view : {"a", "b", "c"}) {
      Vector3d z = truth + 0.1 * Vector3d(normal(random), normal(random), normal(random));
      if (k == 12 && std::string(view) == "b") z.x() += 10.0;
      rows.push_back(Measurement{"s", t, view, "o", Gaussian3::from_covariance(z, r), std::nullopt});
    }
    const Gaussian3 with = step(gated, t, rows)[0];
    const Gaussian3 without = step(ungated, t, rows)[0];
    if (k == 12) {
      EXPECT_LT((with.mean() - truth).norm(), 0.3);
      EXPECT_GT((without.mean() - truth).norm(), 0.5);
    }
  }
  const auto reports = gated.view_noise_scales().reports();
  EXPECT_EQ(reports.at("b").gated, 1u);
  EXPECT_EQ(reports.at("a").gated + reports.at("c").gated, 0u);
  EXPECT_EQ(reports.at("b").largest_scale, 1.0);  // one gross error is not a faulty view
  EXPECT_EQ(gated.gate_restarts(), 0u);
  EXPECT_TRUE(ungated.view_noise_scales().reports().empty());
}

// With the views' offsets estimated (a registration prior), a gross error of one of three views moved
// not only the object but that view's offset, and so the estimates after it. The other two views at its
// time outvote it (cross_view_weights, on by default): the offset and the later estimates stay near
// those of the same data without the error, and the measurement is counted.
TEST(SpatiotemporalGraphFilter, TheOtherViewsOutvoteAGrossErrorWithoutTheGate) {
  const ConstantVelocityPredictor predictor(0.01, 1.0);
  FilterOptions weighted{RegistrationPrior{Vector3d(0.1, 0.1, 0.0), Vector3d::Constant(0.5)}, true};
  FilterOptions unweighted = weighted;
  unweighted.cross_view_weights = false;
  SpatiotemporalGraphFilter clean(predictor, weighted), with(predictor, weighted), without(predictor, unweighted);
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal;
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  double with_shift = 0.0, without_shift = 0.0;  // from the clean run's estimates, summed after the error
  for (int k = 0; k < 20; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(1.0 * t, 0.5 * t, 0.0);
    std::vector<Measurement> rows;
    for (const char* view : {"a", "b", "c"}) {
      const Vector3d z = truth + 0.1 * Vector3d(normal(random), normal(random), normal(random));
      rows.push_back(Measurement{"s", t, view, "o", Gaussian3::from_covariance(z, r), std::nullopt});
    }
    const Gaussian3 reference = step(clean, t, rows)[0];
    if (k == 8) {
      rows[1].position = Gaussian3::from_covariance(rows[1].position.mean() + Vector3d(10.0, 0.0, 0.0), r);  // b
    }
    const Gaussian3 a = step(with, t, rows)[0];
    const Gaussian3 b = step(without, t, rows)[0];
    if (k == 8) {
      EXPECT_LT((a.mean() - truth).norm(), 0.3);
      EXPECT_GT((b.mean() - truth).norm(), 0.5);
    }
    if (k > 8) {
      with_shift += (a.mean() - reference.mean()).norm();
      without_shift += (b.mean() - reference.mean()).norm();
    }
  }
  const double clean_offset = clean.registration_offset("b")(0);
  EXPECT_LT(std::abs(with.registration_offset("b")(0) - clean_offset), 0.02);
  EXPECT_GT(std::abs(without.registration_offset("b")(0) - clean_offset), 0.1);
  // Soft, not a cut: the scaled measurement still counts as one at the threshold (d² = γ), a pull that
  // falls as 1/error, so the estimates after it are not the clean run's exactly.
  EXPECT_LT(with_shift, 0.5 * without_shift);
  const auto reports = with.view_noise_scales().reports();
  EXPECT_EQ(reports.at("b").down_weighted, 1u);
  EXPECT_EQ(reports.count("a") + reports.count("c"), 0u);
  EXPECT_TRUE(clean.view_noise_scales().reports().empty());
  EXPECT_TRUE(without.view_noise_scales().reports().empty());
}

FilterOptions gate_on() {
  FilterOptions options;
  options.gate.enabled = true;
  return options;
}

// An object walks a straight line at 1 m/s. At its first time view "b" reports it 10 m off, so the two
// measurements conflict and nothing tells which is right. With the gate the start says so (its
// covariance covers both), and it is no start for a velocity: the next times, where the views agree,
// are on the object. Before, the conflicting start passed as an agreeing one, the next estimate was
// pulled back towards it and the velocity between the two sent the track metres off.
TEST(SpatiotemporalGraphFilter, AStartFromConflictingMeasurementsIsWideAndNoStartForAVelocity) {
  const ConstantVelocityPredictor predictor(0.01, 1.0);
  SpatiotemporalGraphFilter filter(predictor, gate_on());
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  for (int k = 0; k < 5; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(1.0 * t, 0.0, 0.0);
    std::vector<Measurement> rows;
    for (const char* view : {"a", "b"}) {
      const Vector3d z = truth + Vector3d(k == 0 && std::string(view) == "b" ? 10.0 : 0.0, 0.02 * k, 0.0);
      rows.push_back(Measurement{"s", t, view, "o", Gaussian3::from_covariance(z, r), std::nullopt, std::nullopt});
    }
    const Gaussian3 estimate = step(filter, t, rows)[0];
    if (k == 0) {
      EXPECT_LT(estimate.mahalanobis_squared(truth), kChiSquare3Upper95) << "the start's covariance does not cover the truth";
    } else {
      EXPECT_LT((estimate.mean() - truth).norm(), 0.2) << "at step " << k;
    }
  }
}

// Constant velocity, recording every object of every motion graph it is asked to forecast.
class RecordingPredictor final : public testing::ForwardingPredictor {
 public:
  RecordingPredictor() : ForwardingPredictor(0.01, 1.0, std::numeric_limits<double>::infinity()) {}
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override {
    for (const MotionGraph& graph : graphs) {
      for (const ObjectHistory& object : graph.objects) seen.emplace_back(graph.target_time, object.object);
    }
    return ForwardingPredictor::forecast(graphs);
  }
  mutable std::vector<std::pair<double, std::string>> seen;  // (graph time, object)
};

// A track started from conflicting measurements starts again at its object's next time, before the
// forecasts of that time are asked for: its one position, a mixture of the views, is no neighbour for
// the other objects' forecasts either.
TEST(SpatiotemporalGraphFilter, AConflictingStartIsNoNeighbourInTheNextForecast) {
  const RecordingPredictor predictor;
  SpatiotemporalGraphFilter filter(predictor, gate_on());
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) {
    const double t = 0.1 * k;
    std::vector<Measurement> rows;
    for (const char* object : {"o", "p"}) {
      const Vector3d truth(1.0 * t, object == std::string("p") ? 5.0 : 0.0, 0.0);
      for (const char* view : {"a", "b"}) {
        const bool off = k == 0 && object == std::string("p") && view == std::string("b");
        const Vector3d z = truth + Vector3d(off ? 10.0 : 0.0, 0.0, 0.0);
        rows.push_back(Measurement{"s", t, view, object, Gaussian3::from_covariance(z, r), std::nullopt, std::nullopt});
      }
    }
    step(filter, t, rows);
  }
  bool o_at_first_forecast = false;
  for (const auto& [time, object] : predictor.seen) {
    if (std::abs(time - 0.1) < 1e-9) {
      EXPECT_NE(object, "p") << "the conflicting start of p was offered to Φ at 0.1 s";
      if (object == "o") o_at_first_forecast = true;
    }
  }
  EXPECT_TRUE(o_at_first_forecast);
}

// An object seen by one view, whose second measurement is 10 m off. With the gate, it is checked
// against the prediction from the one position before it (velocity unknown, a typical speed's spread),
// fails, and the track starts again from it at once; the next measurement, on the object again, fails
// against that and starts it again. So one estimate is off (the outlier's own), not the three and more
// that followed when only a prediction with a known velocity was checked against (the outlier went
// in, the velocity from it sent the track off, and it took three failures to start again).
TEST(SpatiotemporalGraphFilter, GatesAGrossErrorOfATrackWithOnePosition) {
  const ConstantVelocityPredictor predictor(0.01, 1.0);
  SpatiotemporalGraphFilter filter(predictor, gate_on());
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  int off = 0;
  for (int k = 0; k < 8; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(1.0 * t, 0.0, 0.0);
    const Vector3d z = truth + Vector3d(0.0, k == 1 ? 10.0 : 0.0, 0.0);
    const std::vector<Measurement> rows{Measurement{"s", t, "a", "o", Gaussian3::from_covariance(z, r), std::nullopt, std::nullopt}};
    const Gaussian3 estimate = step(filter, t, rows)[0];
    if ((estimate.mean() - truth).norm() > 0.5) ++off;
  }
  EXPECT_EQ(off, 1);
  EXPECT_EQ(filter.gate_restarts(), 2u);
}

// Four views with registration offsets watch three walkers; view "d" is faulty (`fault` changes
// its measurement at step k). Returns the mean error of the fused estimates from step `from` on.
struct FaultyViewRun {
  double error = 0.0;
  std::size_t refilters = 0;
  ViewNoiseScales::Report d;
};
template <typename Fault>
FaultyViewRun run_with_faulty_view(double lag_window, int from, Fault fault, const Matrix3d& stated_r_of_d) {
  const ConstantVelocityPredictor predictor(0.01, 1.0);
  FilterOptions options;
  options.gate.enabled = true;
  options.lag_window = lag_window;
  options.registration.translation_sigma = Vector3d(0.1, 0.1, 0.0);
  options.registration.noise_ratio = Vector3d::Constant(0.0);
  SpatiotemporalGraphFilter filter(predictor, options);
  std::mt19937_64 random(11);
  std::normal_distribution<double> normal;
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  std::map<std::string, Vector3d> offsets;
  for (const char* view : {"a", "b", "c", "d"}) offsets[view] = Vector3d(0.1 * normal(random), 0.1 * normal(random), 0.0);
  FaultyViewRun run;
  int scored = 0;
  for (int k = 0; k < 40; ++k) {
    const double t = 0.1 * k;
    std::vector<Measurement> rows;
    std::vector<Vector3d> truths;
    for (int object = 0; object < 3; ++object) {
      const Vector3d truth(object + 1.0 * t, 0.5 * object * t, 0.0);
      for (const char* view : {"a", "b", "c", "d"}) {
        Vector3d z = truth + offsets[view] + 0.1 * Vector3d(normal(random), normal(random), normal(random));
        const bool faulty = std::string(view) == "d";
        if (faulty) z = fault(k, z);
        rows.push_back(Measurement{"s", t, view, std::string(1, static_cast<char>('p' + object)),
                                   Gaussian3::from_covariance(z, faulty ? stated_r_of_d : r), std::nullopt});
        truths.push_back(truth);
      }
    }
    const std::vector<Gaussian3> estimates = step(filter, t, rows);
    if (k < from) continue;
    for (std::size_t i = 0; i < rows.size(); ++i) run.error += (estimates[i].mean() - truths[i]).norm();
    scored += static_cast<int>(rows.size());
  }
  run.error /= scored;
  run.refilters = filter.refilters();
  run.d = filter.view_noise_scales().reports().at("d");
  return run;
}

// View "d" states a hundredth of its noise. Once its noise scale is learnt, the filter goes back over
// its lag window and fuses everything since with it: from then on it is about as good as a filter
// told the truth, and better than one that cannot go back (lag window 0).
TEST(SpatiotemporalGraphFilter, GoesBackWhenAViewsNoiseWasUnderstated) {
  const auto honest = [](int, const Vector3d& z) { return z; };
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  const FaultyViewRun told = run_with_faulty_view(1.0, 2, honest, r);
  const FaultyViewRun back = run_with_faulty_view(1.0, 2, honest, 0.01 * r);
  const FaultyViewRun stays = run_with_faulty_view(0.0, 2, honest, 0.01 * r);
  EXPECT_EQ(told.refilters, 0u);
  EXPECT_GE(back.refilters, 1u);
  EXPECT_EQ(stays.refilters, 0u);
  EXPECT_GT(back.d.largest_scale, 30.0);
  EXPECT_LT(back.error, 1.15 * told.error) << back.error << " against " << told.error;
  EXPECT_LT(back.error, stays.error) << back.error << " against " << stays.error;
}

// View "d" moves 1 m at step 20. The gate finds the jump a few measurements later, releases the
// view's offset from the first of them, and goes back to fuse them again with it.
TEST(SpatiotemporalGraphFilter, ReleasesAJumpFromWhenItBegan) {
  const auto jump = [](int k, const Vector3d& z) { return k >= 20 ? Vector3d(z + Vector3d(0.6, 0.8, 0.0)) : z; };
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  const FaultyViewRun back = run_with_faulty_view(1.0, 20, jump, r);
  const FaultyViewRun stays = run_with_faulty_view(0.0, 20, jump, r);
  EXPECT_GE(back.d.offset_releases, 1u);
  EXPECT_GE(stays.d.offset_releases, 1u);
  EXPECT_GE(back.refilters, 1u);
  EXPECT_LT(back.error, stays.error) << back.error << " against " << stays.error;
}

// A motion model that is wrong for the data: constant velocity plus an acceleration that is not there.
class WrongAccelerationPredictor final : public testing::ForwardingPredictor {
 public:
  WrongAccelerationPredictor() : ForwardingPredictor(0.05, 1.0, std::numeric_limits<double>::infinity()) {}
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override {
    std::vector<std::vector<MotionForecast>> forecasts = ForwardingPredictor::forecast(graphs);
    for (auto& graph : forecasts) {
      for (MotionForecast& forecast : graph) forecast.acceleration = Vector3d(20.0, 0.0, 0.0);
    }
    return forecasts;
  }
};

TEST(SpatiotemporalGraphFilter, FollowsConstantVelocityWhereTheModelPredictsWorse) {
  const WrongAccelerationPredictor predictor;
  const Matrix3d r = 0.01 * 0.01 * Matrix3d::Identity();
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<std::vector<Measurement>> steps;
  std::vector<Vector3d> truth;
  for (int k = 0; k < 60; ++k) {
    const double t = 0.1 * k;
    truth.push_back(Vector3d(1.0 * t, 0.5 * t, 0.0));
    std::vector<Measurement> rows;
    for (const char* view : {"a", "b"}) {
      rows.push_back(measurement(t, view, "o", truth.back() + Vector3d(noise(random), noise(random), noise(random)), r));
    }
    steps.push_back(rows);
  }
  // Mean error over the last 30 steps of the estimates and of the predictions before them.
  std::map<MotionFallback, double> late_error, late_prediction_error;
  for (const MotionFallback policy : {MotionFallback::kOff, MotionFallback::kAuto, MotionFallback::kAlways}) {
    FilterOptions options;
    options.motion_fallback = policy;
    SpatiotemporalGraphFilter filter(predictor, options);
    for (int k = 0; k < 60; ++k) {
      const std::vector<Gaussian3> estimates = step(filter, 0.1 * k, steps[k]);
      if (k < 30) continue;
      late_error[policy] += (estimates[0].mean() - truth[k]).norm() / 30.0;
      late_prediction_error[policy] += (filter.last_predictions()[0]->prior.mean() - truth[k]).norm() / 30.0;
    }
    const MotionChoice& choice = filter.motion_choice();
    EXPECT_EQ(choice.constant_velocity(), policy != MotionFallback::kOff);
    EXPECT_EQ(choice.switches(), policy == MotionFallback::kAuto ? 1u : 0u);
    EXPECT_EQ(choice.samples() > 0, policy == MotionFallback::kAuto);
  }
  // The wrong model's predictions are off by ½ a Δt² = 0.1 m a step; constant velocity's are not.
  EXPECT_GT(late_prediction_error[MotionFallback::kOff], 0.05);
  EXPECT_LT(late_prediction_error[MotionFallback::kAuto], 0.3 * late_prediction_error[MotionFallback::kOff]);
  EXPECT_NEAR(late_prediction_error[MotionFallback::kAuto], late_prediction_error[MotionFallback::kAlways], 1e-3);
  EXPECT_LE(late_error[MotionFallback::kAuto], late_error[MotionFallback::kOff]);
}

// The choice can switch part-way through an event's samples (one per object). The event's
// predictions followed the motion chosen before it, and so must the labels of all its samples: up to
// and including the event that switches, `auto` learns Φ's λ from exactly the innovations `off` does.
TEST(SpatiotemporalGraphFilter, LabelsAnEventsSamplesByTheMotionItsPredictionsFollowed) {
  const WrongAccelerationPredictor predictor;
  const Matrix3d r = 0.01 * 0.01 * Matrix3d::Identity();
  std::mt19937_64 random(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  FilterOptions automatic;
  automatic.motion_fallback = MotionFallback::kAuto;
  FilterOptions off;
  off.motion_fallback = MotionFallback::kOff;
  SpatiotemporalGraphFilter chooses(predictor, automatic);
  SpatiotemporalGraphFilter stays(predictor, off);
  bool switched = false;
  for (int k = 0; k < 60 && !switched; ++k) {
    const double t = 0.1 * k;
    std::vector<Measurement> rows;
    for (int object = 0; object < 8; ++object) {
      const Vector3d position(1.0 * t + object, 0.5 * t - 0.3 * object * t, 0.0);
      for (const char* view : {"a", "b"}) {
        rows.push_back(measurement(t, view, "o" + std::to_string(object),
                                   position + Vector3d(noise(random), noise(random), noise(random)), r));
      }
    }
    step(chooses, t, rows);
    step(stays, t, rows);
    switched = chooses.motion_choice().constant_velocity();
    ASSERT_EQ(chooses.process_noise_scales(), stays.process_noise_scales()) << "step " << k;
  }
  ASSERT_TRUE(switched);
}

}  // namespace
}  // namespace stgf
