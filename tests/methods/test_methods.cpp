// SPDX-License-Identifier: Apache-2.0
// The model-based methods behind the Localizer interface: aom, wls and mmt.

#include <gtest/gtest.h>

#include "stgf/core/multi_view_update.hpp"
#include "stgf/methods/registry.hpp"
#include "stgf/methods/run_method.hpp"

namespace stgf {
namespace {

Measurement measurement(double time, const std::string& view, const std::string& object, const Vector3d& z,
                        const Matrix3d& r, const std::string& scene = "s") {
  return Measurement{scene, time, view, object, Gaussian3::from_covariance(z, r), std::nullopt};
}

std::vector<const Measurement*> pointers(const std::vector<Measurement>& rows) {
  std::vector<const Measurement*> result;
  for (const Measurement& row : rows) result.push_back(&row);
  return result;
}

TEST(Methods, NamesAreKnown) {
  EXPECT_EQ(method_names(), (std::vector<std::string>{"aom", "wls", "mmt"}));
  EXPECT_THROW(make_localizer("ours", MethodConfig{}), std::invalid_argument);
}

// Two views of o1 (R = I and 4·I), one view of o2.
const std::vector<Measurement> kStep = {
    measurement(0.0, "v1", "o1", Vector3d(0, 0, 0), Matrix3d::Identity()),
    measurement(0.0, "v1", "o2", Vector3d(5, 5, 5), Matrix3d::Identity()),
    measurement(0.0, "v2", "o1", Vector3d(5, 0, 0), 4.0 * Matrix3d::Identity())};

TEST(Methods, AverageIsThePlainMeanWithItsCovariance) {
  const auto estimates = make_localizer("aom", MethodConfig{})->step(0.0, pointers(kStep));
  ASSERT_EQ(estimates.size(), 3u);
  EXPECT_EQ(estimates[0].mean(), Vector3d(2.5, 0, 0));
  EXPECT_EQ(estimates[0].covariance(), Matrix3d(1.25 * Matrix3d::Identity()));  // (1 + 4) / 2²
  EXPECT_EQ(estimates[2].mean(), estimates[0].mean());
  EXPECT_EQ(estimates[1].mean(), Vector3d(5, 5, 5));
}

TEST(Methods, WeightedLeastSquaresIsTheInformationWeightedMean) {
  const auto estimates = make_localizer("wls", MethodConfig{})->step(0.0, pointers(kStep));
  // weights 1 and 1/4: x = (0·1 + 5·¼) / 1.25 = 1, P = 1 / 1.25 = 0.8
  EXPECT_LT((estimates[0].mean() - Vector3d(1, 0, 0)).norm(), 1e-14);
  EXPECT_LT((estimates[0].covariance() - 0.8 * Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_EQ(estimates[2].mean(), estimates[0].mean());
}

TEST(Methods, EmptyStepGivesNoEstimate) {
  for (const std::string& name : method_names()) {
    EXPECT_TRUE(make_localizer(name, MethodConfig{})->step(0.0, {}).empty()) << name;
  }
}

// mmt starts at the fused measurement, then follows a target moving at constant velocity: after a
// few steps its estimate beats the single-step wls on the same data.
TEST(Methods, MultiViewKalmanTrackerFollowsConstantVelocity) {
  std::vector<Measurement> rows;
  const Matrix3d r = 0.25 * Matrix3d::Identity();
  // Deterministic "noise" pattern, alternating in sign, so the test does not depend on a generator.
  const double offsets[4] = {0.4, -0.3, 0.2, -0.5};
  ConstantVelocityModel model;
  model.position_noise_density = 0.01;
  model.velocity_noise_density = 0.01;
  MethodConfig config;
  config.mmt = model;
  for (int k = 0; k < 40; ++k) {
    const double t = 0.1 * k;
    const Vector3d truth(1.0 * t, 0.5 * t, 0.0);
    rows.push_back(measurement(t, "v1", "o", truth + Vector3d::Constant(offsets[k % 4]), r));
    rows.push_back(measurement(t, "v2", "o", truth - Vector3d::Constant(offsets[(k + 1) % 4]), r));
  }
  const std::vector<Gaussian3> mmt = run_method("mmt", config, rows);
  const std::vector<Gaussian3> wls = run_method("wls", config, rows);
  ASSERT_EQ(mmt.size(), rows.size());
  EXPECT_LT((mmt[0].mean() - wls[0].mean()).norm(), 1e-12);  // starts at the fused measurement
  double mmt_error = 0.0, wls_error = 0.0;
  for (std::size_t k = 40; k < rows.size(); ++k) {
    const double t = rows[k].time;
    const Vector3d truth(1.0 * t, 0.5 * t, 0.0);
    mmt_error += (mmt[k].mean() - truth).norm();
    wls_error += (wls[k].mean() - truth).norm();
  }
  EXPECT_LT(mmt_error, 0.5 * wls_error);
  EXPECT_EQ(mmt[78].mean(), mmt[79].mean());  // both views of a step get the same estimate
}

TEST(Methods, MultiViewKalmanTrackerPredictsAcrossMissedSteps) {
  MethodConfig config;
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  std::vector<Measurement> rows;
  for (int k = 0; k < 10; ++k) rows.push_back(measurement(0.1 * k, "v", "o", Vector3d(0.1 * k, 0, 0), r));
  rows.push_back(measurement(2.0, "v", "o", Vector3d(2.0, 0, 0), r));  // seen again after 1 s
  const std::vector<Gaussian3> estimates = run_method("mmt", config, rows);
  EXPECT_NEAR(estimates.back().mean().x(), 2.0, 0.05);
}

TEST(Methods, EachSceneStartsFresh) {
  const Matrix3d r = Matrix3d::Identity();
  const std::vector<Measurement> rows = {measurement(0.0, "v", "o", Vector3d(0, 0, 0), r, "a"),
                                         measurement(0.1, "v", "o", Vector3d(1, 0, 0), r, "a"),
                                         measurement(0.0, "v", "o", Vector3d(50, 0, 0), r, "b")};
  const std::vector<Gaussian3> estimates = run_method("mmt", MethodConfig{}, rows);
  EXPECT_EQ(estimates[2].mean(), Vector3d(50, 0, 0));
}

}  // namespace
}  // namespace stgf
