// SPDX-License-Identifier: Apache-2.0
// Calibrating the registration prior (core/registration_calibration.hpp) by marginal likelihood:
// on data drawn from the model it recovers σ_t and α (including an axis with no offset), against the
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

namespace stgf {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

struct Simulated {
  std::vector<Measurement> measurements;
  std::vector<Vector3d> truth;
};

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
      Vector6d offset;
      for (int axis = 0; axis < 3; ++axis) offset[axis] = prior.translation_sigma[axis] * normal(rng);
      for (int axis = 3; axis < 6; ++axis) offset[axis] = prior.noise_ratio * normal(rng);
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
  prior.noise_ratio = 0.5;
  const Simulated data = simulate(prior, 125, 4, 20, 7);
  const RegistrationCalibration calibration = calibrate_registration_prior(data.measurements, data.truth);
  EXPECT_EQ(calibration.groups, 500u);
  const Vector3d& sigma = calibration.prior.translation_sigma;
  EXPECT_NEAR(sigma.x(), 0.3, 0.2 * 0.3) << sigma.transpose();
  EXPECT_NEAR(sigma.y(), 0.2, 0.2 * 0.2) << sigma.transpose();
  EXPECT_LT(sigma.z(), 0.02) << sigma.transpose();
  EXPECT_NEAR(calibration.prior.noise_ratio, 0.5, 0.25 * 0.5);
  EXPECT_GT(calibration.log_likelihood_gain, 1.0);  // nats per group over "no offsets"
}

TEST(RegistrationCalibration, FindsNoOffsetWhereThereIsNone) {
  const Simulated data = simulate(RegistrationPrior{}, 125, 4, 20, 8);
  const RegistrationCalibration calibration = calibrate_registration_prior(data.measurements, data.truth);
  EXPECT_EQ(calibration.groups, 500u);
  const Vector3d& sigma = calibration.prior.translation_sigma;
  EXPECT_LT(sigma.maxCoeff(), 0.02) << sigma.transpose();
  EXPECT_GE(sigma.minCoeff(), 0.0);
  EXPECT_LT(calibration.prior.noise_ratio, 0.1);
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
      for (int axis = 0; axis < 3; ++axis) offset[axis] = prior.translation_sigma[axis] * normal(rng);
      for (int axis = 3; axis < 6; ++axis) offset[axis] = prior.noise_ratio * normal(rng);
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
  prior.noise_ratio = 0.5;
  const std::vector<Measurement> measurements = simulate_shared(prior, 125, 4, 2, 10, 17);
  const RegistrationCalibration calibration = calibrate_registration_prior_from_disagreements(measurements);
  EXPECT_EQ(calibration.groups, 125u);  // one per scene
  const Vector3d& sigma = calibration.prior.translation_sigma;
  // 4 views show 3 relative offsets each: a quarter less evidence than against the truth.
  EXPECT_NEAR(sigma.x(), 0.3, 0.25 * 0.3) << sigma.transpose();
  EXPECT_NEAR(sigma.y(), 0.2, 0.25 * 0.2) << sigma.transpose();
  EXPECT_LT(sigma.z(), 0.02) << sigma.transpose();
  EXPECT_NEAR(calibration.prior.noise_ratio, 0.5, 0.3 * 0.5);
  EXPECT_GT(calibration.log_likelihood_gain, 1.0);
}

TEST(RegistrationCalibration, FindsNoOffsetInDisagreementsWhereThereIsNone) {
  const std::vector<Measurement> measurements = simulate_shared(RegistrationPrior{}, 125, 4, 2, 10, 18);
  const RegistrationCalibration calibration = calibrate_registration_prior_from_disagreements(measurements);
  EXPECT_LT(calibration.prior.translation_sigma.maxCoeff(), 0.02) << calibration.prior.translation_sigma.transpose();
  EXPECT_LT(calibration.prior.noise_ratio, 0.1);
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
