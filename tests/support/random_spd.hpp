// SPDX-License-Identifier: Apache-2.0
#pragma once
// Generators of random symmetric positive definite matrices for property tests.
//
// A covariance is built as U diag(λ) Uᵀ with U a random rotation and eigenvalues λ drawn
// log-uniformly over [scale/√c, scale·√c], so tests control the condition number c and the scale.

#include <cmath>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <rapidcheck.h>

namespace stgf::testing {

inline Eigen::Matrix3d spd_from(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& eigenvalues) {
  const Eigen::Matrix3d u = rotation.normalized().toRotationMatrix();
  const Eigen::Matrix3d spd = u * eigenvalues.asDiagonal() * u.transpose();
  return 0.5 * (spd + spd.transpose());
}

// rapidcheck generator: SPD with eigenvalues in [scale/10, scale·10] and scale in [1e-2, 1e2].
inline rc::Gen<Eigen::Matrix3d> gen_spd() {
  return rc::gen::map(rc::gen::container<std::vector<int>>(8, rc::gen::inRange(-1000, 1001)),
                      [](const std::vector<int>& v) {
                        Eigen::Quaterniond q(v[0] + 0.5, v[1], v[2], v[3]);
                        const double scale = std::pow(10.0, v[4] / 500.0);  // 1e-2 … 1e2
                        const Eigen::Vector3d eigenvalues(scale * std::pow(10.0, v[5] / 1000.0),
                                                          scale * std::pow(10.0, v[6] / 1000.0),
                                                          scale * std::pow(10.0, v[7] / 1000.0));
                        return spd_from(q, eigenvalues);
                      });
}

inline rc::Gen<Eigen::Vector3d> gen_vector() {
  return rc::gen::map(rc::gen::container<std::vector<int>>(3, rc::gen::inRange(-100000, 100001)),
                      [](const std::vector<int>& v) {
                        return Eigen::Vector3d(v[0] / 1000.0, v[1] / 1000.0, v[2] / 1000.0);
                      });
}

// Seeded, for loops outside rapidcheck.
inline Eigen::Matrix3d random_spd(std::mt19937_64& rng, double scale = 1.0, double condition = 100.0) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-0.5, 0.5);
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  const double half_log = 0.5 * std::log(condition);
  const Eigen::Vector3d eigenvalues(scale * std::exp(2 * half_log * uniform(rng)),
                                    scale * std::exp(2 * half_log * uniform(rng)),
                                    scale * std::exp(2 * half_log * uniform(rng)));
  return spd_from(q, eigenvalues);
}

// Largest absolute entry difference relative to the larger of the two norms (≥ 1e-300).
inline double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double scale = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), 1e-300});
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

}  // namespace stgf::testing
