// SPDX-License-Identifier: Apache-2.0
// Registration offsets (core/view_registration.hpp): a zero prior is the plain weighted mean; one
// view alone learns nothing and carries its whole prior; two views learn their difference (to the
// posterior's accuracy, the hand-computed posterior variance) while the shared part stays at its prior;
// corrected fusion beats the plain mean when a precise view is biased; the fused covariance is honest
// (mean NEES 3 on data drawn from the model); the order of rows does not matter; bad priors throw.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "stgf/core/multi_view_update.hpp"
#include "stgf/core/view_registration.hpp"
#include "support/random_spd.hpp"
#include "support/registration_offset.hpp"

namespace stgf {
namespace {

using Matrix36 = OffsetJacobian;
using Vector6d = OffsetVector;  // (t, δ, ε)
using testing::random_spd;
using testing::relative_difference;

Measurement measurement(const std::string& view, const std::string& object, const Vector3d& z,
                        const Matrix3d& r, double time = 0.0) {
  return Measurement{"s", time, view, object, Gaussian3::from_covariance(z, r), std::nullopt, std::nullopt};
}

std::vector<const Measurement*> pointers(const std::vector<Measurement>& rows) {
  std::vector<const Measurement*> result;
  for (const Measurement& row : rows) result.push_back(&row);
  return result;
}

// H = [I  L  0], L Lᵀ = R: how an offset (t, δ, ε) moves a measurement with noise R (no sensor
// position: no range to scale).
Matrix36 offset_jacobian(const Matrix3d& r) {
  Matrix36 jacobian = Matrix36::Zero();
  jacobian.leftCols<3>().setIdentity();
  jacobian.middleCols<3>(3) = r.llt().matrixL();
  return jacobian;
}

// z = p + H β + e with e ~ N(0, R).
Vector3d measure(const Vector3d& truth, const Vector6d& offset, const Matrix3d& r, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  const Vector3d unit(normal(rng), normal(rng), normal(rng));
  const Matrix3d factor = r.llt().matrixL();
  return truth + offset_jacobian(r) * offset + factor * unit;
}

using testing::draw_offset;

Vector3d uniform_point(std::mt19937_64& rng, double half_width) {
  std::uniform_real_distribution<double> uniform(-half_width, half_width);
  return Vector3d(uniform(rng), uniform(rng), uniform(rng));
}

// H = [I₃ L] with L the Cholesky factor of R: written out, the bits of Eigen's LLT, over covariances
// of every scale and condition the readers accept.
TEST(ViewRegistration, OffsetJacobianHoldsEigensCholeskyFactorBitForBit) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, -6.0 + 12.0 * (trial % 100) / 99.0);
    const Matrix3d r = random_spd(rng, scale, trial % 2 == 0 ? 10.0 : 1e6);
    const OffsetJacobian h = offset_jacobian(r);
    const Matrix3d l = r.llt().matrixL();
    EXPECT_EQ(h.leftCols<3>(), Matrix3d::Identity());
    ASSERT_EQ(h.middleCols<3>(3), l) << "R =\n" << r;
    ASSERT_EQ(h.col(6), Vector3d::Zero());  // no sensor: no range to scale
  }
}

// With the sensor's position, H = [I₃ G L(Gᵀ R G)]: it turns with the world frame (turn the object,
// the sensor and R about the vertical, and H's factor turns with them), its first column runs along
// the ray in the ray's own sense whatever the heading, and without a sensor it is the plain factor.
TEST(ViewRegistration, OffsetJacobianAlongTheRayTurnsWithTheWorldFrame) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int trial = 0; trial < 200; ++trial) {
    const double heading = angle(rng);
    const Vector3d ray(std::cos(heading), std::sin(heading), 0.0);
    // Long along the ray (depth), short across it, as a camera's back-projected foot point is.
    const Vector3d across(-ray.y(), ray.x(), 0.0);
    const Matrix3d r = 0.09 * ray * ray.transpose() + 0.004 * across * across.transpose() +
                       0.0025 * Vector3d::UnitZ() * Vector3d::UnitZ().transpose();
    Measurement row = measurement("v", "o", Vector3d(1.0, 2.0, 0.0) + 12.0 * ray, r);
    row.sensor_position = Vector3d(1.0, 2.0, 5.0);
    const Matrix36 h = offset_jacobian(row);
    EXPECT_EQ(h.leftCols<3>(), Matrix3d::Identity());
    EXPECT_LT((h.col(3) - 0.3 * ray).norm(), 1e-12) << "heading " << heading;  // √0.09 along the ray
    EXPECT_LT((h.middleCols<3>(3) * h.middleCols<3>(3).transpose() - r).norm(), 1e-12);
    EXPECT_LT((h.col(6) - 12.0 * ray).norm(), 1e-12) << "heading " << heading;  // ε's: the horizontal range
    const Matrix3d turn = Eigen::AngleAxisd(angle(rng), Vector3d::UnitZ()).toRotationMatrix();
    Measurement turned = measurement("v", "o", turn * row.position.mean(), turn * r * turn.transpose());
    turned.sensor_position = turn * *row.sensor_position;
    EXPECT_LT((offset_jacobian(turned).rightCols<4>() - turn * h.rightCols<4>()).norm(), 1e-11);
    row.sensor_position.reset();
    EXPECT_EQ(offset_jacobian(row), offset_jacobian(row.position.covariance()));
  }
}

TEST(ViewRegistration, ZeroPriorIsTheInformationWeightedMeanAndLearnsNothing) {
  std::mt19937_64 rng(11);
  ViewRegistration registration(RegistrationPrior{});
  EXPECT_FALSE(registration.active());
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Measurement> rows;
    for (const char* view : {"a", "b", "c"}) {
      rows.push_back(measurement(view, "o", uniform_point(rng, 10.0), random_spd(rng, 0.05, 50.0)));
    }
    rows.push_back(measurement("a", "q", uniform_point(rng, 10.0), random_spd(rng, 0.05, 50.0)));
    rows.push_back(measurement("c", "q", uniform_point(rng, 10.0), random_spd(rng, 0.05, 50.0)));
    const std::vector<const Measurement*> of_o = {&rows[0], &rows[1], &rows[2]};
    const Gaussian3 before = registration.combine(of_o);
    const Gaussian3 reference = information_weighted_mean(
        std::vector<Gaussian3>{rows[0].position, rows[1].position, rows[2].position});
    EXPECT_LT(relative_difference(before.mean(), reference.mean()), 1e-12);
    EXPECT_LT(relative_difference(before.covariance(), reference.covariance()), 1e-12);

    registration.learn(pointers(rows));
    const Gaussian3 after = registration.combine(of_o);
    EXPECT_EQ(after.mean(), before.mean());
    EXPECT_EQ(after.covariance(), before.covariance());
    for (const char* view : {"a", "b", "c"}) {
      EXPECT_EQ(registration.offset(view), Vector6d::Zero());
      EXPECT_EQ(registration.offset_covariance(view), (OffsetMatrix::Zero()));
    }
  }
}

TEST(ViewRegistration, SingleViewNeverLearnsAndCarriesItsWholePrior) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.1);
  prior.noise_ratio = Vector3d::Constant(0.5);
  OffsetMatrix prior_covariance = OffsetMatrix::Zero();
  prior_covariance.diagonal() << 0.3 * 0.3, 0.2 * 0.2, 0.1 * 0.1, 0.5 * 0.5, 0.5 * 0.5, 0.5 * 0.5, 0.0;  // no range scale

  Matrix3d r;
  r << 0.04, 0.01, 0.0, 0.01, 0.09, 0.002, 0.0, 0.002, 0.02;
  // R + H Σ₀ Hᵀ = R + diag(σ²) + α² L Lᵀ = 1.25 R + diag(0.09, 0.04, 0.01), by hand:
  Matrix3d expected;
  expected << 0.14, 0.0125, 0.0, 0.0125, 0.1525, 0.0025, 0.0, 0.0025, 0.035;

  ViewRegistration registration(prior);
  const Measurement single = measurement("a", "o", Vector3d(1.0, -2.0, 0.5), r);
  const std::vector<const Measurement*> alone = {&single};
  const Gaussian3 unknown_view = registration.combine(alone);  // a view not seen yet: its prior
  EXPECT_LT((unknown_view.mean() - single.position.mean()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((unknown_view.covariance() - expected).cwiseAbs().maxCoeff(), 1e-12);

  // Steps in which no object is seen by two views: "a" and "b" never see the same object.
  std::mt19937_64 rng(5);
  for (int step = 0; step < 10; ++step) {
    std::vector<Measurement> rows;
    for (int object = 0; object < 3; ++object) {
      rows.push_back(
          measurement("a", "a" + std::to_string(object), uniform_point(rng, 5.0), random_spd(rng, 0.02)));
      rows.push_back(
          measurement("b", "b" + std::to_string(object), uniform_point(rng, 5.0), random_spd(rng, 0.02)));
    }
    registration.learn(pointers(rows));
  }
  EXPECT_EQ(registration.view_count(), 2u);
  for (const char* view : {"a", "b"}) {
    EXPECT_EQ(registration.offset(view), Vector6d::Zero()) << view;
    EXPECT_EQ(registration.offset_covariance(view), prior_covariance) << view;
  }
  const Gaussian3 known_view = registration.combine(alone);
  EXPECT_LT((known_view.mean() - single.position.mean()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((known_view.covariance() - expected).cwiseAbs().maxCoeff(), 1e-12);
}

// Two views with the same R = r² I (so both offsets reach the measurements through the same H):
// the differences z_b − z_a measure D = H β_b − H β_a with noise 2R, so after N of them
//     Var D = (1/(2h) + N/(2r²))⁻¹ I,   h = σ² + α² r²   (the prior variance of each H β_u),
// while the sum H β_a + H β_b, uncorrelated with D under the prior, keeps mean 0 and variance 2h:
// each H β_u ends with variance (2h + Var D) / 4.
TEST(ViewRegistration, TwoViewsLearnTheirDifferenceAndKeepTheCommonModeAtThePrior) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d::Constant(0.5);
  prior.noise_ratio = Vector3d::Constant(1.0);
  const double noise_sigma = 0.05;
  const Matrix3d r = noise_sigma * noise_sigma * Matrix3d::Identity();
  const Matrix36 h = offset_jacobian(r);
  Vector6d offset_a = Vector6d::Zero();
  Vector6d offset_b = Vector6d::Zero();
  offset_b.head<3>() = Vector3d(0.5, -0.3, 0.0);
  const Vector3d true_difference = h * offset_b - h * offset_a;

  std::mt19937_64 rng(7);
  ViewRegistration registration(prior);
  const int steps = 40, objects = 5;
  for (int step = 0; step < steps; ++step) {
    std::vector<Measurement> rows;
    for (int object = 0; object < objects; ++object) {
      const Vector3d truth = uniform_point(rng, 20.0);
      const std::string id = "o" + std::to_string(object);
      rows.push_back(measurement("a", id, measure(truth, offset_a, r, rng), r, step));
      rows.push_back(measurement("b", id, measure(truth, offset_b, r, rng), r, step));
    }
    registration.learn(pointers(rows));
  }

  const double prior_variance = 0.25 + 1.0 * noise_sigma * noise_sigma;  // h
  const double observations = steps * objects;
  const double difference_variance =
      1.0 / (1.0 / (2.0 * prior_variance) + observations / (2.0 * noise_sigma * noise_sigma));
  const Vector3d estimated_difference = h * registration.offset("b") - h * registration.offset("a");
  const Vector3d error = estimated_difference - true_difference;
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LT(std::abs(error[axis]), 4.0 * std::sqrt(difference_variance))
        << "axis " << axis << ": " << error.transpose();
  }
  EXPECT_LT(error.norm(), 0.02);
  // Shrunk: from 2h = 0.5 m² per axis to about 2r²/N.
  EXPECT_LT(difference_variance, 1e-4 * 2.0 * prior_variance);
  // The common mode stays exactly where the prior put it.
  const Vector3d common_mode = h * registration.offset("a") + h * registration.offset("b");
  EXPECT_LT(common_mode.norm(), 1e-9);
  const double marginal_variance = (2.0 * prior_variance + difference_variance) / 4.0;
  for (const char* view : {"a", "b"}) {
    const Matrix3d projected = h * registration.offset_covariance(view) * h.transpose();
    EXPECT_LT(relative_difference(projected, marginal_variance * Matrix3d::Identity()), 1e-9) << view << "\n"
                                                                                              << projected;
  }
  // The fused measurement of a fresh object keeps the common mode's variance: about h per axis
  // ((2h)/4 for the mean of the two offsets, plus r²/2 for the noise).
  const Vector3d truth(1.0, 2.0, 3.0);
  const std::vector<Measurement> probe = {measurement("a", "p", measure(truth, offset_a, r, rng), r),
                                          measurement("b", "p", measure(truth, offset_b, r, rng), r)};
  const Gaussian3 fused = registration.combine(pointers(probe));
  const double expected_variance = 2.0 * prior_variance / 4.0 + noise_sigma * noise_sigma / 2.0;
  EXPECT_LT(relative_difference(fused.covariance(), expected_variance * Matrix3d::Identity()), 1e-6)
      << fused.covariance();
}

// Four views, one (c) precise and biased by b_c. The plain weighted mean follows c most of the
// way (its weight is 0.89); with the offsets learned the views agree, and the fused mean is off only by what
// no view can see, the common mode: with equal translation priors its estimate is the mean offset, so the
// fused error is b_c / 4.
TEST(ViewRegistration, CombineCorrectsAPreciseBiasedView) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d::Constant(2.0);
  prior.noise_ratio = Vector3d::Constant(0.0);
  const Vector3d bias(1.5, -1.0, 0.3);
  const std::vector<std::string> views = {"a", "b", "c", "d"};
  const Matrix3d coarse = 0.1 * 0.1 * Matrix3d::Identity();
  const Matrix3d precise = 0.02 * 0.02 * Matrix3d::Identity();
  auto offset_of = [&](const std::string& view) {
    Vector6d offset = Vector6d::Zero();
    if (view == "c") offset.head<3>() = bias;
    return offset;
  };
  auto noise_of = [&](const std::string& view) { return view == "c" ? precise : coarse; };

  std::mt19937_64 rng(7);
  ViewRegistration registration(prior);
  auto make_step = [&](int step, int objects, std::vector<Vector3d>& truths) {
    std::vector<Measurement> rows;
    truths.clear();
    for (int object = 0; object < objects; ++object) {
      truths.push_back(uniform_point(rng, 20.0));
      for (const std::string& view : views) {
        rows.push_back(measurement(view, "o" + std::to_string(object),
                                   measure(truths.back(), offset_of(view), noise_of(view), rng),
                                   noise_of(view), step));
      }
    }
    return rows;
  };
  std::vector<Vector3d> truths;
  for (int step = 0; step < 30; ++step) registration.learn(pointers(make_step(step, 4, truths)));

  const int objects = 20;
  const std::vector<Measurement> rows = make_step(30, objects, truths);
  Vector3d corrected_error = Vector3d::Zero();
  Vector3d plain_error = Vector3d::Zero();
  for (int object = 0; object < objects; ++object) {
    const std::size_t first = views.size() * static_cast<std::size_t>(object);
    std::vector<const Measurement*> of_object;
    std::vector<Gaussian3> gaussians;
    for (std::size_t v = 0; v < views.size(); ++v) {
      of_object.push_back(&rows[first + v]);
      gaussians.push_back(rows[first + v].position);
    }
    corrected_error += (registration.combine(of_object).mean() - truths[object]) / objects;
    plain_error += (information_weighted_mean(gaussians).mean() - truths[object]) / objects;
  }
  // The plain mean weighs c by R_c⁻¹ / Σ R_u⁻¹ = 2500 / (2500 + 3 · 100).
  const double weight_of_c = 2500.0 / 2800.0;
  EXPECT_LT((plain_error - weight_of_c * bias).norm(), 0.03) << plain_error.transpose();
  EXPECT_LT((corrected_error - bias / 4.0).norm(), 0.03) << corrected_error.transpose();
  EXPECT_LT(corrected_error.norm(), 0.35 * plain_error.norm());
}

// The key property: on data drawn from the model (offsets from the prior, noise from R), the fused
// measurement's covariance is honest — its NEES against the truth averages 3 — while the plain
// weighted mean, which trusts R alone, is overconfident.
TEST(ViewRegistration, CombinedCovarianceIsConsistent) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.1);
  prior.noise_ratio = Vector3d::Constant(0.5);
  const std::vector<std::string> views = {"a", "b", "c"};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double nees = 0.0, plain_nees = 0.0;
  int count = 0;
  for (int scene = 0; scene < 200; ++scene) {
    ViewRegistration registration(prior);
    std::vector<Vector6d> offsets;
    for (std::size_t v = 0; v < views.size(); ++v) offsets.push_back(draw_offset(prior, rng));
    for (int step = 0; step < 10; ++step) {
      std::vector<Measurement> rows;
      std::vector<Vector3d> truths;
      std::vector<std::vector<std::size_t>> rows_of_object;
      for (int object = 0; object < 3; ++object) {
        truths.push_back(uniform_point(rng, 30.0));
        rows_of_object.emplace_back();
        for (std::size_t v = 0; v < views.size(); ++v) {
          // Each view sees each object with probability 0.8 (the last view when none would).
          if (unit(rng) > 0.8 && !(v + 1 == views.size() && rows_of_object.back().empty())) continue;
          // Noise from 3 cm to 30 cm, anisotropic: different ranges, so t and L δ are separable.
          const double scale = std::pow(10.0, -3.0 + 2.0 * unit(rng));
          const Matrix3d r = random_spd(rng, scale, 10.0);
          rows_of_object.back().push_back(rows.size());
          rows.push_back(measurement(views[v], "o" + std::to_string(object),
                                     measure(truths.back(), offsets[v], r, rng), r, step));
        }
      }
      for (std::size_t object = 0; object < truths.size(); ++object) {
        std::vector<const Measurement*> of_object;
        std::vector<Gaussian3> gaussians;
        for (std::size_t row : rows_of_object[object]) {
          of_object.push_back(&rows[row]);
          gaussians.push_back(rows[row].position);
        }
        nees += registration.combine(of_object).mahalanobis_squared(truths[object]);
        plain_nees += information_weighted_mean(gaussians).mahalanobis_squared(truths[object]);
        ++count;
      }
      registration.learn(pointers(rows));
    }
  }
  nees /= count;
  plain_nees /= count;
  EXPECT_GE(nees, 2.7);
  EXPECT_LE(nees, 3.3);
  EXPECT_GT(plain_nees, 6.0);  // what ignoring the offsets costs on the same data
}

// Objects within a step are independent measurements of the offsets, so their order (and the order
// of views within an object, i.e. which view the differences are taken against) does not matter.
TEST(ViewRegistration, OrderOfRowsWithinAStepDoesNotMatter) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.1);
  prior.noise_ratio = Vector3d::Constant(0.5);
  std::mt19937_64 rng(3);
  ViewRegistration forward(prior), shuffled(prior);
  const std::vector<std::string> views = {"a", "b", "c"};
  std::vector<Vector6d> offsets;
  for (std::size_t v = 0; v < views.size(); ++v) offsets.push_back(draw_offset(prior, rng));
  for (int step = 0; step < 5; ++step) {
    std::vector<Measurement> rows;
    for (int object = 0; object < 4; ++object) {
      const Vector3d truth = uniform_point(rng, 10.0);
      for (std::size_t v = 0; v < views.size(); ++v) {
        const Matrix3d r = random_spd(rng, 0.01, 10.0);
        rows.push_back(
            measurement(views[v], "o" + std::to_string(object), measure(truth, offsets[v], r, rng), r, step));
      }
    }
    std::vector<const Measurement*> in_order = pointers(rows);
    // Objects in reverse order, the views of each object rotated.
    std::vector<const Measurement*> reordered;
    for (int object = 3; object >= 0; --object) {
      for (int v = 0; v < 3; ++v)
        reordered.push_back(in_order[static_cast<std::size_t>(3 * object + (v + object) % 3)]);
    }
    forward.learn(in_order);
    shuffled.learn(reordered);
  }
  for (const std::string& view : views) {
    EXPECT_LT((forward.offset(view) - shuffled.offset(view)).cwiseAbs().maxCoeff(), 1e-9) << view;
    EXPECT_LT((forward.offset_covariance(view) - shuffled.offset_covariance(view)).cwiseAbs().maxCoeff(),
              1e-9)
        << view;
  }
  EXPECT_GT(forward.offset("a").norm(), 0.0);  // something was learned
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  const std::vector<Measurement> probe = {measurement("a", "p", Vector3d(1, 2, 3), r),
                                          measurement("b", "p", Vector3d(1.1, 2, 3), r),
                                          measurement("c", "p", Vector3d(1, 2.1, 3), r)};
  const Gaussian3 a = forward.combine(pointers(probe));
  std::vector<const Measurement*> reversed = pointers(probe);
  std::reverse(reversed.begin(), reversed.end());
  const Gaussian3 b = shuffled.combine(reversed);
  EXPECT_LT((a.mean() - b.mean()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((a.covariance() - b.covariance()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(ViewRegistration, InvalidPriorThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Vector3d& sigma : {Vector3d(-0.1, 0.2, 0.3), Vector3d(0.1, nan, 0.3), Vector3d(0.1, 0.2, inf)}) {
    RegistrationPrior prior;
    prior.translation_sigma = sigma;
    EXPECT_THROW(ViewRegistration{prior}, std::invalid_argument) << sigma.transpose();
  }
  for (const double ratio : {-0.5, nan, inf}) {
    RegistrationPrior prior;
    prior.noise_ratio = Vector3d::Constant(ratio);
    EXPECT_THROW(ViewRegistration{prior}, std::invalid_argument) << ratio;
  }
  RegistrationPrior valid;
  valid.translation_sigma = Vector3d(0.0, 0.2, 0.3);
  EXPECT_NO_THROW(ViewRegistration{valid});
  EXPECT_THROW(ViewRegistration(valid).combine({}), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
