// SPDX-License-Identifier: Apache-2.0
// JointRegistration keeps the joint Gaussian over positions and offsets in factored form
// (p_i = a_i + B_i β, joint_registration.hpp). It must be exactly the dense joint Kalman filter over
// s = (p_1 … p_m, β_1 … β_n) written out below: the same positions, offsets, covariances and
// innovations after any sequence of starts, predictions, updates (noise scaled or not; one
// measurement at a time or all of an object's at once), views
// appearing late, offsets released (full rank and rank one) and objects removed — including a prior
// that is singular on z, whose zero direction the factored form leaves out.

#include "stgf/core/joint_registration.hpp"

#include <map>
#include <random>

#include <gtest/gtest.h>

namespace stgf {
namespace {

using Matrix36 = OffsetJacobian;

// The reference: one dense Gaussian over every position and offset, every operation exact.
class DenseJointRegistration {
 public:
  explicit DenseJointRegistration(const RegistrationPrior& prior) : prior_covariance_(prior.covariance()) {}

  void add_object(const Measurement& first, double noise_scale) {
    const Eigen::Index u = add_view(first.view);
    const Matrix36 h = offset_jacobian(first);
    const Eigen::Index i = grow(3);
    // p = z − H_u β_u − e, e independent of everything.
    mean_.segment<3>(i) = first.position.mean() - h * mean_.segment<kOffsetSize>(u);
    const Eigen::MatrixXd cross = -h * covariance_.middleRows<kOffsetSize>(u);
    covariance_.middleRows<3>(i) = cross;
    covariance_.middleCols<3>(i) = cross.transpose();
    covariance_.block<3, 3>(i, i) =
        noise_scale * first.position.covariance() + h * covariance_.block<kOffsetSize, kOffsetSize>(u, u) * h.transpose();
    objects_[first.object] = i;
  }
  void remove_object(const std::string& object) {
    const Eigen::Index i = objects_.at(object);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index k = 0; k < mean_.size(); ++k) {
      if (k < i || k >= i + 3) keep.push_back(k);
    }
    mean_ = mean_(keep).eval();
    covariance_ = covariance_(keep, keep).eval();
    objects_.erase(object);
    for (auto* blocks : {&objects_, &views_}) {
      for (auto& [name, start] : *blocks) {
        if (start > i) start -= 3;
      }
    }
  }
  void predict(const std::string& object, const Vector3d& d, const Matrix3d& q) {
    const Eigen::Index i = objects_.at(object);
    mean_.segment<3>(i) += d;
    covariance_.block<3, 3>(i, i) += q;
  }
  void release_offset(const std::string& view, const Matrix3d& w) { covariance_.block<3, 3>(views_.at(view), views_.at(view)) += w; }
  Eigen::MatrixXd observation(const Measurement& m, Eigen::Index u) const {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(3, mean_.size());
    h.middleCols<3>(objects_.at(m.object)).setIdentity();
    h.middleCols<kOffsetSize>(u) = offset_jacobian(m);
    return h;
  }
  JointRegistration::Innovation innovation(const Measurement& m, double noise_scale) {
    const Eigen::Index u = add_view(m.view);
    const Eigen::MatrixXd h = observation(m, u);
    return {m.position.mean() - h * mean_, h * covariance_ * h.transpose() + noise_scale * m.position.covariance()};
  }
  // Σ_k W_k ν_k and its covariance, the measurements' innovations stacked: W (H Σ Hᵀ + R) Wᵀ.
  JointRegistration::Innovation combined_innovation(const std::vector<const Measurement*>& measurements,
                                                    const std::vector<double>& noise_scales,
                                                    const std::vector<Matrix3d>& weights) {
    const auto k = static_cast<Eigen::Index>(measurements.size());
    for (const Measurement* m : measurements) add_view(m->view);
    Eigen::MatrixXd h(3 * k, mean_.size()), noise = Eigen::MatrixXd::Zero(3 * k, 3 * k), w(3, 3 * k);
    Eigen::VectorXd z(3 * k);
    for (Eigen::Index j = 0; j < k; ++j) {
      const Measurement& m = *measurements[static_cast<std::size_t>(j)];
      h.middleRows<3>(3 * j) = observation(m, views_.at(m.view));
      noise.block<3, 3>(3 * j, 3 * j) = noise_scales[static_cast<std::size_t>(j)] * m.position.covariance();
      w.middleCols<3>(3 * j) = weights[static_cast<std::size_t>(j)];
      z.segment<3>(3 * j) = m.position.mean();
    }
    return {w * (z - h * mean_), w * (h * covariance_ * h.transpose() + noise) * w.transpose()};
  }
  void update(const Measurement& m, double noise_scale) {
    const Eigen::Index u = add_view(m.view);
    const Eigen::MatrixXd h = observation(m, u);
    const Matrix3d s = h * covariance_ * h.transpose() + noise_scale * m.position.covariance();
    const Eigen::MatrixXd gain = covariance_ * h.transpose() * s.inverse();
    mean_ += gain * (m.position.mean() - h * mean_);
    covariance_ -= gain * h * covariance_;
    covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();
  }
  // Cov(Σ_k W_k H_k β_u(k)): every offset block's covariance and cross-covariance, written out.
  Matrix3d offsets_covariance(const std::vector<const Measurement*>& measurements, const std::vector<Matrix3d>& weights) {
    for (const Measurement* m : measurements) add_view(m->view);
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(3, mean_.size());
    for (std::size_t k = 0; k < measurements.size(); ++k) {
      g.middleCols<kOffsetSize>(views_.at(measurements[k]->view)) += weights[k] * offset_jacobian(*measurements[k]);
    }
    return g * covariance_ * g.transpose();
  }
  Vector3d position_mean(const std::string& object) const { return mean_.segment<3>(objects_.at(object)); }
  Matrix3d position_covariance(const std::string& object) const {
    const Eigen::Index i = objects_.at(object);
    return covariance_.block<3, 3>(i, i);
  }
  OffsetVector offset(const std::string& view) const { return mean_.segment<kOffsetSize>(views_.at(view)); }
  OffsetMatrix offset_covariance(const std::string& view) const {
    return covariance_.block<kOffsetSize, kOffsetSize>(views_.at(view), views_.at(view));
  }
  const std::map<std::string, Eigen::Index>& objects() const { return objects_; }
  const std::map<std::string, Eigen::Index>& views() const { return views_; }

 private:
  Eigen::Index grow(Eigen::Index size) {
    const Eigen::Index start = mean_.size();
    mean_.conservativeResize(start + size);
    mean_.tail(size).setZero();
    covariance_.conservativeResize(start + size, start + size);
    covariance_.rightCols(size).setZero();
    covariance_.bottomRows(size).setZero();
    return start;
  }
  Eigen::Index add_view(const std::string& view) {
    if (const auto found = views_.find(view); found != views_.end()) return found->second;
    const Eigen::Index u = grow(kOffsetSize);
    covariance_.block<kOffsetSize, kOffsetSize>(u, u) = prior_covariance_;
    views_[view] = u;
    return u;
  }

  OffsetMatrix prior_covariance_;
  std::map<std::string, Eigen::Index> objects_, views_;
  Eigen::VectorXd mean_;
  Eigen::MatrixXd covariance_;
};

Matrix3d random_covariance(std::mt19937_64& random, double scale) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Matrix3d a;
  for (int k = 0; k < 9; ++k) a(k / 3, k % 3) = normal(random);
  return scale * (a * a.transpose() + 0.5 * Matrix3d::Identity());
}

void expect_same_state(const JointRegistration& factored, const DenseJointRegistration& dense, const std::string& when) {
  SCOPED_TRACE(when);
  // All positions at once (one blocked solve from 8 objects on), on a copy: the original below reads
  // each alone.
  const JointRegistration copy = factored;
  std::vector<std::string_view> names;
  for (const auto& [object, index] : dense.objects()) names.push_back(object);
  const std::vector<Gaussian3> together = copy.positions(names);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string object(names[i]);
    EXPECT_LE((together[i].mean() - dense.position_mean(object)).norm(), 1e-9) << object << " (all at once)";
    EXPECT_LE((together[i].covariance() - dense.position_covariance(object)).norm(), 1e-9) << object << " (all at once)";
  }
  for (const auto& [object, index] : dense.objects()) {
    const Gaussian3 p = factored.position(object);
    EXPECT_LE((p.mean() - dense.position_mean(object)).norm(), 1e-9) << object;
    EXPECT_LE((p.covariance() - dense.position_covariance(object)).norm(), 1e-9) << object;
  }
  for (const auto& [view, index] : dense.views()) {
    EXPECT_LE((factored.offset(view) - dense.offset(view)).norm(), 1e-9) << view;
    EXPECT_LE((factored.offset_covariance(view) - dense.offset_covariance(view)).norm(), 1e-9) << view;
  }
}

// `sensors`: every view's rows carry its sensor's position (drawn when the view is first seen), so
// that H has its ray-frame factor and its range scale column.
void run_scenario(const RegistrationPrior& prior, std::uint64_t seed, int object_count = 4, bool sensors = false) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  JointRegistration factored(prior);
  DenseJointRegistration dense(prior);
  std::map<std::string, Vector3d> sensor_of_view;
  const auto measurement = [&](const std::string& object, const std::string& view) {
    const Vector3d z(3.0 * normal(random), 3.0 * normal(random), normal(random));
    Measurement row{"s", 0.0, view, object, Gaussian3::from_covariance(z, random_covariance(random, 0.01)), std::nullopt};
    if (sensors) {
      const auto [at, added] = sensor_of_view.try_emplace(view, Vector3d::Zero());
      if (added) at->second = Vector3d(20.0 * normal(random), 20.0 * normal(random), 5.0);
      row.sensor_position = at->second;
    }
    return row;
  };
  std::vector<std::string> objects;
  for (int i = 0; i < object_count; ++i) objects.push_back(std::string(1, static_cast<char>('a' + i)));
  std::vector<std::string> views = {"v0", "v1"};
  for (int step = 0; step < 30; ++step) {
    if (step == 8) views.push_back("v2");   // a view that appears late
    if (step == 15) views.push_back("v3");
    for (const std::string& object : objects) {
      if (uniform(random) < 0.2) continue;  // not seen this step
      std::vector<std::string> seen;
      for (const std::string& view : views) {
        if (uniform(random) < 0.7) seen.push_back(view);
      }
      if (seen.empty()) continue;
      if (!factored.has_object(object)) {
        const Measurement first = measurement(object, seen.front());
        factored.add_object(first, 1.0);
        dense.add_object(first, 1.0);
        seen.erase(seen.begin());
      } else {
        const Vector3d d(0.1 * normal(random), 0.1 * normal(random), 0.0);
        const Matrix3d q = random_covariance(random, 0.001);
        factored.predict(object, d, q);
        dense.predict(object, d, q);
      }
      // Half the time all of the object's measurements in one update, else one by one.
      const bool together = uniform(random) < 0.5;
      std::vector<Measurement> batch;
      std::vector<double> scales;
      batch.reserve(seen.size());
      for (const std::string& view : seen) {
        const Measurement& m = batch.emplace_back(measurement(object, view));
        const double scale = scales.emplace_back(uniform(random) < 0.3 ? 4.0 : 1.0);
        if (together) continue;
        const JointRegistration::Innovation expected = dense.innovation(m, scale);
        const JointRegistration::Innovation actual = factored.innovation(m, scale);
        EXPECT_LE((actual.value - expected.value).norm(), 1e-9);
        EXPECT_LE((actual.covariance - expected.covariance).norm(), 1e-9);
        factored.update(m, scale);
        dense.update(m, scale);
      }
      if (together) {
        if (batch.size() >= 2) {
          // The combined innovation, with the information weights W_k = (Σ_j R_j⁻¹)⁻¹ R_k⁻¹ (and, from
          // step 20, with a view never seen among them).
          std::vector<const Measurement*> combined;
          std::vector<double> combined_scales = scales;
          for (const Measurement& m : batch) combined.push_back(&m);
          const Measurement unseen = measurement(object, "never-seen-" + std::to_string(step));
          if (step >= 20) {
            combined.push_back(&unseen);
            combined_scales.push_back(2.0);
          }
          Matrix3d information = Matrix3d::Zero();
          for (std::size_t k = 0; k < combined.size(); ++k) {
            information += (combined_scales[k] * combined[k]->position.covariance()).inverse();
          }
          std::vector<Matrix3d> weights;
          for (std::size_t k = 0; k < combined.size(); ++k) {
            weights.push_back(information.inverse() * (combined_scales[k] * combined[k]->position.covariance()).inverse());
          }
          const JointRegistration::Innovation actual = factored.innovation(combined, combined_scales);
          const JointRegistration::Innovation expected = dense.combined_innovation(combined, combined_scales, weights);
          EXPECT_LE((actual.value - expected.value).norm(), 1e-9) << "combined innovation at step " << step;
          EXPECT_LE((actual.covariance - expected.covariance).norm(), 1e-9) << "combined innovation at step " << step;
        }
        std::vector<const Measurement*> pointers;
        for (std::size_t k = 0; k < batch.size(); ++k) {
          pointers.push_back(&batch[k]);
          dense.update(batch[k], scales[k]);
        }
        factored.update(pointers, scales);
      }
      if (batch.size() >= 2) {
        // One measurement against a weighted mean of the others (and, from step 20, one of a view
        // never seen, whose offset is its prior, independent of the rest).
        std::vector<const Measurement*> combined;
        std::vector<Matrix3d> weights;
        for (std::size_t k = 0; k < batch.size(); ++k) {
          combined.push_back(&batch[k]);
          weights.push_back(k == 0 ? Matrix3d::Identity() : Matrix3d(-random_covariance(random, 1.0)));
        }
        const Measurement unseen = measurement(object, "never-seen");
        if (step >= 20) {
          combined.push_back(&unseen);
          weights.push_back(-Matrix3d::Identity());
        }
        const Matrix3d actual = factored.offsets_covariance(combined, weights);
        EXPECT_LE((actual - dense.offsets_covariance(combined, weights)).norm(), 1e-9) << "offsets_covariance at step " << step;
        // The offset common to the views cancels in a difference: less than the two offsets' own spread.
        const Matrix3d apart = factored.offsets_covariance(std::vector<const Measurement*>{combined[0], combined[1]},
                                                           std::vector<Matrix3d>{Matrix3d::Identity(), -Matrix3d::Identity()});
        const Matrix3d alone = factored.offsets_covariance(std::vector<const Measurement*>{combined[0]},
                                                           std::vector<Matrix3d>{Matrix3d::Identity()}) +
                               factored.offsets_covariance(std::vector<const Measurement*>{combined[1]},
                                                           std::vector<Matrix3d>{Matrix3d::Identity()});
        EXPECT_LT(apart.trace(), alone.trace()) << "at step " << step;
      }
    }
    expect_same_state(factored, dense, "after step " + std::to_string(step));
    if (step == 12 || step == 22) {
      // Full rank, then rank one (the gate releases ν̄ ν̄ᵀ: one direction only).
      const Vector3d direction(normal(random), normal(random), normal(random));
      const Matrix3d w = step == 12 ? random_covariance(random, 0.05) : Matrix3d(0.05 * direction * direction.transpose());
      factored.release_offset("v1", w);
      dense.release_offset("v1", w);
      expect_same_state(factored, dense, "after releasing v1's offset at step " + std::to_string(step));
    }
    if (step == 18 && factored.has_object("b")) {
      factored.remove_object("b");
      dense.remove_object("b");
      expect_same_state(factored, dense, "after removing b");
    }
  }
}

TEST(JointRegistration, EqualsTheDenseJointKalmanFilter) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.2, 0.3, 0.1);
  prior.noise_ratio = Vector3d::Constant(0.5);
  for (std::uint64_t seed : {1u, 2u, 3u}) run_scenario(prior, seed);
}

TEST(JointRegistration, EqualsTheDenseJointKalmanFilterWithAPriorSingularOnZ) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.1, 0.1, 0.0);  // as the benchmarks' ground-plane views
  prior.noise_ratio = Vector3d::Constant(0.3);
  for (std::uint64_t seed : {4u, 5u}) run_scenario(prior, seed);
}

// Enough objects per step that an event's pending rank-3 terms are folded into M as blocked rank
// updates and positions() solves for many objects at once.
TEST(JointRegistration, EqualsTheDenseJointKalmanFilterWithManyObjects) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.2, 0.3, 0.1);
  prior.noise_ratio = Vector3d::Constant(0.5);
  for (std::uint64_t seed : {6u, 7u}) run_scenario(prior, seed, 14);
}

// With the sensors' positions: the offset factor along each ray, and a range scale ε per view.
TEST(JointRegistration, EqualsTheDenseJointKalmanFilterWithRangeScales) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.2, 0.3, 0.0);
  prior.noise_ratio = Vector3d::Constant(0.5);
  prior.range_scale_sigma = 0.02;
  for (std::uint64_t seed : {8u, 9u}) run_scenario(prior, seed, 4, /*sensors=*/true);
}

// Four cameras around a scene, 10 m from it (as ETH/UCY's), that agree up to their noise: one range
// scale ε for all of them with t_u = ε s_u moves every measurement by ε times its own position, which
// would shrink every disagreement if ε's column were taken from the noisy measurement itself — the
// views' noise passing for offsets (κ̂ ran to 2¹⁰). Taken from a position common to the
// views (their weighted mean), that mode cancels in their differences: κ̂ stays near 1 and ε̂ within
// its prior.
TEST(JointRegistration, NoiseDoesNotPassForACommonRangeScale) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.03, 0.03, 0.0);
  prior.range_scale_sigma = 0.01;
  JointRegistration registration(prior);
  std::mt19937_64 random(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  const std::vector<Vector3d> sensors = {{-10.0, 2.0, 6.0}, {-4.0, -12.0, 6.0}, {7.0, -10.0, 7.0}, {8.0, 8.0, 7.0}};
  const Matrix3d noise = Vector3d(0.02, 0.02, 0.01).asDiagonal();
  for (int step = 0; step < 40; ++step) {
    for (int i = 0; i < 8; ++i) {
      const std::string object = "o" + std::to_string(i);
      const Vector3d position(3.0 * std::cos(i + 0.05 * step), 3.0 * std::sin(i + 0.05 * step), 0.0);
      std::vector<Measurement> rows;
      for (std::size_t v = 0; v < sensors.size(); ++v) {
        const Vector3d error(std::sqrt(noise(0, 0)) * normal(random), std::sqrt(noise(1, 1)) * normal(random),
                             std::sqrt(noise(2, 2)) * normal(random));
        rows.push_back(Measurement{"s", 0.1 * step, "v" + std::to_string(v), object,
                                   Gaussian3::from_covariance(position + error, noise), sensors[v], std::nullopt});
      }
      std::vector<const Measurement*> pointers;
      for (const Measurement& row : rows) pointers.push_back(&row);
      const std::vector<double> scales(rows.size(), 1.0);
      if (!registration.has_object(object)) {
        registration.add_object(rows.front(), 1.0);
        pointers.erase(pointers.begin());
      } else {
        registration.predict(object, Vector3d(0.0, 0.0, 0.0), Matrix3d::Identity() * 0.01);
      }
      registration.update(pointers, std::span(scales).first(pointers.size()));
      std::vector<const Measurement*> all;
      for (const Measurement& row : rows) all.push_back(&row);
      registration.observe_differences(all, scales);
    }
    registration.adapt_prior_scale();
  }
  EXPECT_TRUE(registration.prior_scale_estimated());
  EXPECT_LT(registration.prior_scales().translation, 4.0);
  EXPECT_LT(registration.prior_scales().noise_ratio, 4.0);
  for (int v = 0; v < 4; ++v) {
    EXPECT_LT(std::abs(registration.offset("v" + std::to_string(v))[6]), 3.0 * prior.range_scale_sigma) << v;
  }
}

TEST(JointRegistration, UnknownObjectsAreLogicErrors) {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.1, 0.1, 0.1);
  JointRegistration registration(prior);
  const Measurement m{"s", 0.0, "v", "o", Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity()), std::nullopt};
  EXPECT_THROW(registration.update(m), std::logic_error);
  EXPECT_THROW(registration.position("o"), std::logic_error);
  registration.add_object(m);
  EXPECT_THROW(registration.add_object(m), std::logic_error);
  const Measurement other{"s", 0.0, "v", "p", m.position, std::nullopt};
  const std::vector<const Measurement*> two_objects = {&m, &other};
  EXPECT_THROW(registration.update(two_objects, std::vector<double>{1.0, 1.0}), std::logic_error);
}

}  // namespace
}  // namespace stgf
