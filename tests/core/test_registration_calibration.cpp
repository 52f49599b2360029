// SPDX-License-Identifier: Apache-2.0
// Calibrating the registration prior (core/registration_calibration.hpp) by marginal likelihood:
// on data drawn from the model it recovers σ_t and α (including an axis with no offset, and α per axis
// of each measurement's ray), against the
// truth and without it (from the views' disagreements), on data without offsets it finds none, and
// mismatched inputs are rejected.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "stgf/core/registration_calibration.hpp"
#include "support/random_spd.hpp"
#include "support/registration_offset.hpp"

namespace stgf {
namespace {

using Vector6d = OffsetVector;  // (t, δ, ε)

struct Simulated {
  std::vector<Measurement> measurements;
  std::vector<Vector3d> truth;
};

using testing::draw_offset;

// `scenes` × `views` groups of `rows` measurements, z = y + [I L] β_g + e with β_g drawn from the
// prior once per (scene, view) and R varied per row (σ from 3 cm to 50 cm, anisotropic, rotated) so
// that t and L δ can be told apart.
Simulated simulate(const RegistrationPrior& prior, int scenes, int views, int rows, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Simulated data;
  for (int scene = 0; scene < scenes; ++scene) {
    for (int view = 0; view < views; ++view) {
      const Vector6d offset = draw_offset(prior, rng);
      for (int row = 0; row < rows; ++row) {
        const Vector3d truth(40.0 * unit(rng) - 20.0, 40.0 * unit(rng) - 20.0, 2.0 * unit(rng));
        const double scale = std::pow(10.0, -3.0 + 2.4 * unit(rng));
        const Matrix3d r = testing::random_spd(rng, scale, 10.0);
        const Matrix3d factor = r.llt().matrixL();
        const Vector3d noise(normal(rng), normal(rng), normal(rng));
        const Vector3d z = truth + offset.head<3>() + factor * offset.tail<3>() + factor * noise;
        data.measurements.push_back(Measurement{"scene" + std::to_string(scene), 0.1 * row,
                                                "view" + std::to_string(view), "o" + std::to_string(row),
                                                Gaussian3::from_covariance(z, r), std::nullopt});
        data.truth.push_back(truth);
      }
    }
  }
  return data;
}

TEST(RegistrationCalibration, RecoversThePriorTheDataWereDrawnFrom) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.0);
  prior.noise_ratio = Vector3d::Constant(0.5);
  const Simulated data = simulate(prior, 125, 4, 20, 7);
  const RegistrationCalibration calibration = calibrate_registration_prior(data.measurements, data.truth);
  EXPECT_EQ(calibration.groups, 500u);
  const Vector3d& sigma = calibration.prior.translation_sigma;
  EXPECT_NEAR(sigma.x(), 0.3, 0.2 * 0.3) << sigma.transpose();
  EXPECT_NEAR(sigma.y(), 0.2, 0.2 * 0.2) << sigma.transpose();
  EXPECT_LT(sigma.z(), 0.02) << sigma.transpose();
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(calibration.prior.noise_ratio[axis], 0.5, 0.4 * 0.5) << axis;
  EXPECT_GT(calibration.log_likelihood_gain, 1.0);  // nats per group over "no offsets"
}

// Sensors around the scene, each measurement's R long along its ray (depth) and short across it, as
// a camera's ground points or a vehicle's detections are, and the offset in noise units drawn with α
// per axis of the ray's frame (offset_jacobian: along the ray, across it, vertical).
// `ground_camera`: R along the ray grows with the square of the range (a camera's ground points), not
// linearly, so that an offset linear in range along the ray (the range scale's) is not one in noise units.
Simulated simulate_rays(const RegistrationPrior& prior, int scenes, int views, int rows, std::uint64_t seed,
                        bool ground_camera = false) {
  Simulated data;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  for (int group = 0; group < scenes * views; ++group) {
    const double bearing = 2.0 * M_PI * unit(rng);
    const Vector3d sensor(30.0 * std::cos(bearing), 30.0 * std::sin(bearing), 5.0);
    const Vector6d offset = draw_offset(prior, rng);
    for (int row = 0; row < rows; ++row) {
      const Vector3d truth(20.0 * unit(rng) - 10.0, 20.0 * unit(rng) - 10.0, 0.0);
      const Vector3d ray = truth - sensor;
      const double range = ray.head<2>().norm();
      Matrix3d turn;  // x along the ray's heading
      turn << ray.x() / range, -ray.y() / range, 0, ray.y() / range, ray.x() / range, 0, 0, 0, 1;
      const Vector3d sigma(ground_camera ? 4e-4 * range * range : 0.01 * range, 0.003 * range, 0.004 * range);
      const Matrix3d r = turn * sigma.cwiseProduct(sigma).asDiagonal() * turn.transpose();
      Measurement measurement{"scene" + std::to_string(group / views), 0.1 * row, "view" + std::to_string(group % views),
                              "o" + std::to_string(row), Gaussian3::from_covariance(truth, r), sensor, std::nullopt};
      const OffsetJacobian h = offset_jacobian(measurement);
      const Vector3d noise(normal(rng), normal(rng), normal(rng));
      measurement.position = Gaussian3::from_covariance(truth + h * offset + h.middleCols<3>(3) * noise, r);
      data.measurements.push_back(std::move(measurement));
      data.truth.push_back(truth);
    }
  }
  return data;
}

TEST(RegistrationCalibration, RecoversAlphaPerAxisOfTheRays) {
  // Offsets across the rays only, as a vehicle's heading error gives, and some vertical: one α for
  // all three axes could only take their compromise.
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.2, 0.2, 0.0);
  prior.noise_ratio = Vector3d(0.0, 1.0, 0.4);
  const Simulated data = simulate_rays(prior, 125, 4, 20, 23);
  const RegistrationCalibration calibration =
      calibrate_registration_prior(data.measurements, data.truth, NoiseRatioAxes::kPerAxis);
  const Vector3d& alpha = calibration.prior.noise_ratio;
  EXPECT_LT(alpha.x(), 0.2) << alpha.transpose();
  EXPECT_NEAR(alpha.y(), 1.0, 0.25) << alpha.transpose();
  EXPECT_NEAR(alpha.z(), 0.4, 0.2) << alpha.transpose();
  EXPECT_NEAR(calibration.prior.translation_sigma.x(), 0.2, 0.06) << calibration.prior.translation_sigma.transpose();
  // By default one α for all three axes: their compromise, and a lower likelihood.
  const RegistrationCalibration one = calibrate_registration_prior(data.measurements, data.truth);
  EXPECT_TRUE(one.prior.noise_ratio.isConstant(one.prior.noise_ratio.x())) << one.prior.noise_ratio.transpose();
  EXPECT_GT(one.prior.noise_ratio.x(), 0.2);
  EXPECT_LT(one.prior.noise_ratio.x(), 1.0);
  EXPECT_GT(calibration.log_likelihood_gain, one.log_likelihood_gain + 0.1);
}

// Each sensor's horizontal range scaled by 1 + ε_u (σ_ε = 1 %), as a ground-plane camera's height
// error does: found with `range_scale`, and none where there is none; without it, σ_ε stays zero and
// the rest is calibrated exactly as before the range scale existed.
TEST(RegistrationCalibration, RecoversTheRangeScaleOfTheViews) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.1, 0.1, 0.0);
  prior.noise_ratio = Vector3d::Constant(0.3);
  prior.range_scale_sigma = 0.01;
  const Simulated data = simulate_rays(prior, 125, 4, 20, 31, /*ground_camera=*/true);
  const RegistrationCalibration scaled =
      calibrate_registration_prior(data.measurements, data.truth, NoiseRatioAxes::kOne, /*range_scale=*/true);
  EXPECT_NEAR(scaled.prior.range_scale_sigma, 0.01, 0.0025);
  EXPECT_NEAR(scaled.prior.noise_ratio.x(), 0.3, 0.1) << scaled.prior.noise_ratio.transpose();
  EXPECT_NEAR(scaled.prior.translation_sigma.x(), 0.1, 0.03) << scaled.prior.translation_sigma.transpose();
  EXPECT_EQ(calibrate_registration_prior(data.measurements, data.truth).prior.range_scale_sigma, 0.0);
  prior.range_scale_sigma = 0.0;
  const Simulated plain = simulate_rays(prior, 125, 4, 20, 37, /*ground_camera=*/true);
  EXPECT_LT(calibrate_registration_prior(plain.measurements, plain.truth, NoiseRatioAxes::kOne, true).prior.range_scale_sigma,
            0.003);
}

TEST(RegistrationCalibration, FindsNoOffsetWhereThereIsNone) {
  const Simulated data = simulate(RegistrationPrior{}, 125, 4, 20, 8);
  const RegistrationCalibration calibration = calibrate_registration_prior(data.measurements, data.truth);
  EXPECT_EQ(calibration.groups, 500u);
  const Vector3d& sigma = calibration.prior.translation_sigma;
  EXPECT_LT(sigma.maxCoeff(), 0.02) << sigma.transpose();
  EXPECT_GE(sigma.minCoeff(), 0.0);
  EXPECT_LT(calibration.prior.noise_ratio.maxCoeff(), 0.1) << calibration.prior.noise_ratio.transpose();
  EXPECT_GE(calibration.log_likelihood_gain, 0.0);
  EXPECT_LT(calibration.log_likelihood_gain, 0.05);
}

// `scenes` scenes in which `views` views measure the same `objects` objects at each of `times` times
// (one truth per object and time, seen by every view), z = y + [I L] β_u + e, β_u drawn once per
// (scene, view); R varied per row as above. `own_clocks`: each view measures at its own times (a
// phase of 0.03 s per view), so no two views ever measure an object at one time.
std::vector<Measurement> simulate_shared(const RegistrationPrior& prior, int scenes, int views, int objects, int times,
                                         std::uint64_t seed, bool own_clocks = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Measurement> measurements;
  for (int scene = 0; scene < scenes; ++scene) {
    std::vector<Vector6d> offsets(static_cast<std::size_t>(views));
    for (Vector6d& offset : offsets) {
      offset = draw_offset(prior, rng);
    }
    for (int time = 0; time < times; ++time) {
      for (int object = 0; object < objects; ++object) {
        const Vector3d truth(40.0 * unit(rng) - 20.0, 40.0 * unit(rng) - 20.0, 2.0 * unit(rng));
        for (int view = 0; view < views; ++view) {
          const Vector6d& offset = offsets[static_cast<std::size_t>(view)];
          const double scale = std::pow(10.0, -3.0 + 2.4 * unit(rng));
          const Matrix3d r = testing::random_spd(rng, scale, 10.0);
          const Matrix3d factor = r.llt().matrixL();
          const Vector3d noise(normal(rng), normal(rng), normal(rng));
          const Vector3d z = truth + offset.head<3>() + factor * offset.tail<3>() + factor * noise;
          const double t = 0.1 * time + (own_clocks ? 0.03 * view : 0.0);
          measurements.push_back(Measurement{"scene" + std::to_string(scene), t, "view" + std::to_string(view),
                                             "o" + std::to_string(object), Gaussian3::from_covariance(z, r),
                                             std::nullopt});
        }
      }
    }
  }
  return measurements;
}

TEST(RegistrationCalibration, RecoversThePriorFromTheViewsDisagreementsWithoutTruth) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.0);
  prior.noise_ratio = Vector3d::Constant(0.5);
  const std::vector<Measurement> measurements = simulate_shared(prior, 125, 4, 2, 10, 17);
  const RegistrationCalibration calibration = calibrate_registration_prior_from_disagreements(measurements);
  EXPECT_EQ(calibration.groups, 125u);  // one per scene
  const Vector3d& sigma = calibration.prior.translation_sigma;
  // 4 views show 3 relative offsets each: a quarter less evidence than against the truth.
  EXPECT_NEAR(sigma.x(), 0.3, 0.25 * 0.3) << sigma.transpose();
  EXPECT_NEAR(sigma.y(), 0.2, 0.25 * 0.2) << sigma.transpose();
  EXPECT_LT(sigma.z(), 0.02) << sigma.transpose();
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(calibration.prior.noise_ratio[axis], 0.5, 0.45 * 0.5) << axis;
  EXPECT_GT(calibration.log_likelihood_gain, 1.0);
}

TEST(RegistrationCalibration, FindsNoOffsetInDisagreementsWhereThereIsNone) {
  const std::vector<Measurement> measurements = simulate_shared(RegistrationPrior{}, 125, 4, 2, 10, 18);
  const RegistrationCalibration calibration = calibrate_registration_prior_from_disagreements(measurements);
  EXPECT_LT(calibration.prior.translation_sigma.maxCoeff(), 0.02) << calibration.prior.translation_sigma.transpose();
  EXPECT_LT(calibration.prior.noise_ratio.maxCoeff(), 0.1) << calibration.prior.noise_ratio.transpose();
  EXPECT_LT(calibration.log_likelihood_gain, 0.05);
}

TEST(RegistrationCalibration, ViewsOnTheirOwnClocksShowNoDisagreement) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.0);
  const std::vector<Measurement> measurements = simulate_shared(prior, 5, 3, 2, 10, 19, /*own_clocks=*/true);
  const RegistrationCalibration calibration = calibrate_registration_prior_from_disagreements(measurements);
  EXPECT_EQ(calibration.groups, 0u);
  EXPECT_TRUE(calibration.prior.is_zero());
}

TEST(RegistrationCalibration, NeedsOneTruthPerMeasurement) {
  const Simulated data = simulate(RegistrationPrior{}, 1, 1, 3, 9);
  const std::vector<Vector3d> short_truth(data.truth.begin(), data.truth.end() - 1);
  EXPECT_THROW(calibrate_registration_prior(data.measurements, short_truth), std::invalid_argument);
  std::vector<Vector3d> long_truth = data.truth;
  long_truth.push_back(Vector3d::Zero());
  EXPECT_THROW(calibrate_registration_prior(data.measurements, long_truth), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
