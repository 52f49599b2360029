// SPDX-License-Identifier: Apache-2.0
// The multi-view update (DESIGN §1.3): paper Theorems 1–2, the gain identity, order independence,
// monotone covariance, uninformative views, a hand-computed case, and property tests on random
// SPD matrices.

#include "stgf/core/multi_view_update.hpp"

#include <algorithm>
#include <random>

#include <Eigen/LU>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "support/random_spd.hpp"

namespace stgf {
namespace {

using testing::gen_spd;
using testing::gen_vector;
using testing::relative_difference;

// The textbook Kalman update with H = I (paper Eqs. 3–5), written with explicit inverses so that
// it shares no code with the information form under test.
struct KalmanUpdate {
  Matrix3d gain;
  Vector3d mean;
  Matrix3d covariance;
};
KalmanUpdate kalman_update(const Vector3d& x, const Matrix3d& p, const Vector3d& z, const Matrix3d& r) {
  KalmanUpdate update;
  update.gain = p * (p + r).inverse();
  update.mean = x + update.gain * (z - x);
  update.covariance = (Matrix3d::Identity() - update.gain) * p;
  return update;
}

std::vector<Gaussian3> random_views(rc::Gen<Matrix3d> covariance, int count) {
  std::vector<Gaussian3> views;
  for (int k = 0; k < count; ++k) {
    views.push_back(Gaussian3::from_covariance(*gen_vector(), *covariance));
  }
  return views;
}

// Theorem 1: with one view the measurement gain M equals the Kalman gain K.
RC_GTEST_PROP(MultiViewUpdate, Theorem1OneViewGainIsKalmanGain, ()) {
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const Gaussian3 view = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const MultiViewGains gains = multi_view_gains(prior, std::span(&view, 1));
  const KalmanUpdate kalman = kalman_update(prior.mean(), prior.covariance(), view.mean(), view.covariance());
  RC_ASSERT(relative_difference(gains.measurement_gains[0], kalman.gain) < 1e-12);
}

// Theorem 2: with one view P̂ = (I − K) P and x̂ = x + K (z − x).
RC_GTEST_PROP(MultiViewUpdate, Theorem2OneViewPosteriorIsKalmanPosterior, ()) {
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const Gaussian3 view = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const Gaussian3 fused = multi_view_update(prior, std::span(&view, 1));
  const KalmanUpdate kalman = kalman_update(prior.mean(), prior.covariance(), view.mean(), view.covariance());
  // 1e-10, not 1e-12: the reference's (I − K) P cancels when R ≪ P (rapidcheck found P eigenvalues
  // of 54 against R = 1e-3 I give 5e-12); a wrong update is off by far more (a 1e-6 change fails).
  RC_ASSERT(relative_difference(fused.covariance(), kalman.covariance) < 1e-10);
  const double spread = std::max({prior.mean().norm(), view.mean().norm(), 1.0});
  RC_ASSERT((fused.mean() - kalman.mean).cwiseAbs().maxCoeff() / spread < 1e-10);
}

RC_GTEST_PROP(MultiViewUpdate, GainsSumToIdentity, ()) {
  const int views = *rc::gen::inRange(1, 9);
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const std::vector<Gaussian3> measurements = random_views(gen_spd(), views);
  const MultiViewGains gains = multi_view_gains(prior, measurements);
  Matrix3d sum = gains.state_gain;
  for (const Matrix3d& gain : gains.measurement_gains) sum += gain;
  RC_ASSERT((sum - Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12);
}

// x̂ = E x + Σ M_u z_u (the paper's Eq. 12) agrees with the information-form mean.
RC_GTEST_PROP(MultiViewUpdate, GainFormMeanEqualsInformationForm, ()) {
  const int views = *rc::gen::inRange(1, 9);
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const std::vector<Gaussian3> measurements = random_views(gen_spd(), views);
  const MultiViewGains gains = multi_view_gains(prior, measurements);
  Vector3d gain_form = gains.state_gain * prior.mean();
  double spread = prior.mean().norm();
  for (int u = 0; u < views; ++u) {
    gain_form += gains.measurement_gains[u] * measurements[u].mean();
    spread = std::max(spread, measurements[u].mean().norm());
  }
  const Gaussian3 fused = multi_view_update(prior, measurements);
  RC_ASSERT((fused.mean() - gain_form).cwiseAbs().maxCoeff() / std::max(spread, 1.0) < 1e-11);
}

RC_GTEST_PROP(MultiViewUpdate, OrderOfViewsDoesNotMatter, ()) {
  const int views = *rc::gen::inRange(2, 9);
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  std::vector<Gaussian3> measurements = random_views(gen_spd(), views);
  const Gaussian3 fused = multi_view_update(prior, measurements);
  std::reverse(measurements.begin(), measurements.end());
  std::rotate(measurements.begin(), measurements.begin() + 1, measurements.end());
  const Gaussian3 permuted = multi_view_update(prior, measurements);
  RC_ASSERT(relative_difference(fused.covariance(), permuted.covariance()) < 1e-12);
  RC_ASSERT(relative_difference(fused.mean(), permuted.mean()) < 1e-10);
}

// The batch update equals applying the Kalman update one view at a time.
RC_GTEST_PROP(MultiViewUpdate, EqualsSequentialKalmanUpdates, ()) {
  const int views = *rc::gen::inRange(1, 9);
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  const std::vector<Gaussian3> measurements = random_views(gen_spd(), views);
  Vector3d x = prior.mean();
  Matrix3d p = prior.covariance();
  for (const Gaussian3& view : measurements) {
    const KalmanUpdate step = kalman_update(x, p, view.mean(), view.covariance());
    x = step.mean;
    p = step.covariance;
  }
  const Gaussian3 fused = multi_view_update(prior, measurements);
  RC_ASSERT(relative_difference(fused.covariance(), p) < 1e-10);
  RC_ASSERT(relative_difference(fused.mean(), x) < 1e-9);
}

RC_GTEST_PROP(MultiViewUpdate, AddingAViewNeverIncreasesTrace, ()) {
  const int views = *rc::gen::inRange(0, 8);
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  std::vector<Gaussian3> measurements = random_views(gen_spd(), views);
  const double before = multi_view_update(prior, measurements).covariance().trace();
  measurements.push_back(Gaussian3::from_covariance(*gen_vector(), *gen_spd()));
  const double after = multi_view_update(prior, measurements).covariance().trace();
  RC_ASSERT(after <= before * (1.0 + 1e-12));
  RC_ASSERT(after < before);  // an SPD R adds information strictly
}

RC_GTEST_PROP(MultiViewUpdate, ViewWithHugeCovarianceChangesNothing, ()) {
  const int views = *rc::gen::inRange(0, 6);
  const Gaussian3 prior = Gaussian3::from_covariance(*gen_vector(), *gen_spd());
  std::vector<Gaussian3> measurements = random_views(gen_spd(), views);
  const Gaussian3 without = multi_view_update(prior, measurements);
  measurements.push_back(Gaussian3::from_covariance(*gen_vector(), 1e14 * Matrix3d::Identity()));
  const Gaussian3 with = multi_view_update(prior, measurements);
  RC_ASSERT(relative_difference(with.covariance(), without.covariance()) < 1e-9);
  RC_ASSERT((with.mean() - without.mean()).norm() < 1e-9 * std::max(1.0, without.mean().norm()) + 1e-9);
}

TEST(MultiViewUpdate, NoViewKeepsThePrior) {
  const Gaussian3 prior = Gaussian3::from_covariance(Vector3d(1, 2, 3), 2.0 * Matrix3d::Identity());
  const Gaussian3 fused = multi_view_update(prior, {});
  EXPECT_EQ(fused.mean(), prior.mean());
  EXPECT_EQ(fused.covariance(), prior.covariance());
}

// Two views with correlated noise and no prior, worked by hand:
//   R₁ = [2 1 0; 1 2 0; 0 0 1], R₁⁻¹ = ⅓[2 −1 0; −1 2 0; 0 0 3], z₁ = (3, 0, 0)
//   R₂ = [2 −1 0; −1 2 0; 0 0 1], R₂⁻¹ = ⅓[2 1 0; 1 2 0; 0 0 3], z₂ = (0, 3, 0)
//   S = ⅓ diag(4, 4, 6) → P̂ = diag(¾, ¾, ½);  η = ⅓(6, −3, 0) + ⅓(3, 6, 0) = (3, 1, 0)
//   x̂ = P̂ η = (9/4, 3/4, 0)
TEST(MultiViewUpdate, HandComputedTwoViewsWithoutPrior) {
  Matrix3d r1, r2;
  r1 << 2, 1, 0, 1, 2, 0, 0, 0, 1;
  r2 << 2, -1, 0, -1, 2, 0, 0, 0, 1;
  const std::vector<Gaussian3> views = {Gaussian3::from_covariance(Vector3d(3, 0, 0), r1),
                                        Gaussian3::from_covariance(Vector3d(0, 3, 0), r2)};
  const Gaussian3 fused = information_weighted_mean(views);
  EXPECT_LT((fused.covariance() - Vector3d(0.75, 0.75, 0.5).asDiagonal().toDenseMatrix()).norm(), 1e-14);
  EXPECT_LT((fused.mean() - Vector3d(2.25, 0.75, 0.0)).norm(), 1e-14);
}

// The same two views with a prior N((0, 0, 4), 3·I): S = ⅓ diag(5, 5, 7),
//   η = (3, 1, 0) + ⅓(0, 0, 4) → P̂ = diag(3/5, 3/5, 3/7), x̂ = (9/5, 3/5, 4/7).
TEST(MultiViewUpdate, HandComputedTwoViewsWithPrior) {
  Matrix3d r1, r2;
  r1 << 2, 1, 0, 1, 2, 0, 0, 0, 1;
  r2 << 2, -1, 0, -1, 2, 0, 0, 0, 1;
  const std::vector<Gaussian3> views = {Gaussian3::from_covariance(Vector3d(3, 0, 0), r1),
                                        Gaussian3::from_covariance(Vector3d(0, 3, 0), r2)};
  const Gaussian3 prior = Gaussian3::from_covariance(Vector3d(0, 0, 4), 3.0 * Matrix3d::Identity());
  const Gaussian3 fused = multi_view_update(prior, views);
  EXPECT_LT((fused.covariance() - Vector3d(0.6, 0.6, 3.0 / 7.0).asDiagonal().toDenseMatrix()).norm(), 1e-14);
  EXPECT_LT((fused.mean() - Vector3d(1.8, 0.6, 4.0 / 7.0)).norm(), 1e-14);
}

TEST(MultiViewUpdate, ResultIsExactlySymmetric) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Gaussian3 prior = Gaussian3::from_covariance(Vector3d::Zero(), testing::random_spd(rng, 5.0));
    std::vector<Gaussian3> views;
    for (int u = 0; u < 5; ++u) {
      views.push_back(Gaussian3::from_covariance(Vector3d::Random(), testing::random_spd(rng, 0.3)));
    }
    const Gaussian3 fused = multi_view_update(prior, views);
    ASSERT_EQ(fused.covariance(), fused.covariance().transpose());
  }
}

TEST(MultiViewUpdate, WeightedMeanNeedsAMeasurement) {
  EXPECT_THROW(information_weighted_mean({}), std::invalid_argument);
}

// A diffuse prior x = 0, P = 10⁴·I (an earlier start; DESIGN §1.5 now uses the exact limit) makes the first update the
// information-weighted mean of the measurements, up to the prior's tiny weight.
TEST(MultiViewUpdate, DiffusePriorGivesTheWeightedMean) {
  std::mt19937_64 rng(3);
  std::vector<Gaussian3> views;
  for (int u = 0; u < 4; ++u) {
    views.push_back(Gaussian3::from_covariance(Vector3d::Random() * 10.0, testing::random_spd(rng, 0.1)));
  }
  const Gaussian3 diffuse = Gaussian3::from_covariance(Vector3d::Zero(), 1e4 * Matrix3d::Identity());
  const Gaussian3 fused = multi_view_update(diffuse, views);
  const Gaussian3 mean = information_weighted_mean(views);
  EXPECT_LT((fused.mean() - mean.mean()).norm(), 1e-3);
  EXPECT_LT(relative_difference(fused.covariance(), mean.covariance()), 1e-4);
}

}  // namespace
}  // namespace stgf
