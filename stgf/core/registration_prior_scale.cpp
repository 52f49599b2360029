// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_prior_scale.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace stgf {
namespace {

double grid_log2_scale(int index) { return 0.25 * index - 10.0; }

// ½ gᵀ (I/κ + T)⁻¹ g − ½ log det(I + κ T) for the symmetric tridiagonal T (diagonal, subdiagonal),
// by the LDLᵀ of I/κ + T; −∞ if I/κ + T is not positive definite.
double log_marginal_likelihood(double scale, const Eigen::VectorXd& diagonal, const Eigen::VectorXd& subdiagonal,
                               const Eigen::VectorXd& g) {
  const double inverse = 1.0 / scale;
  double pivot = 0.0, solved = 0.0;  // D_{i−1} and (L⁻¹g)_{i−1}
  double quadratic = 0.0, log_determinant = 0.0;
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) {
    double d = inverse + diagonal(i);
    double w = g(i);
    if (i > 0) {
      const double l = subdiagonal(i - 1) / pivot;
      d -= l * subdiagonal(i - 1);
      w -= l * solved;
    }
    if (!(d > 0.0)) return -std::numeric_limits<double>::infinity();
    quadratic += w * w / d;
    log_determinant += std::log(scale * d);  // det(I + κT) = Π κ D_i
    pivot = d;
    solved = w;
  }
  return 0.5 * quadratic - 0.5 * log_determinant;
}

}  // namespace

void RegistrationPriorScale::add_coordinate(double prior_information, bool scaled) {
  if (!(prior_information > 0.0) || !std::isfinite(prior_information)) {
    throw std::invalid_argument("RegistrationPriorScale: a coordinate's prior information must be positive and finite");
  }
  prior_information_.push_back(prior_information);
  scaled_.push_back(scaled);
  const auto size = static_cast<Eigen::Index>(prior_information_.size());
  information_.conservativeResize(size, size);
  information_.rightCols(1).setZero();
  information_.bottomRows(1).setZero();
  vector_.conservativeResize(size);
  vector_(size - 1) = 0.0;
}

void RegistrationPriorScale::add(std::span<const Eigen::Index> coordinates, const Eigen::MatrixXd& information,
                                 const Eigen::VectorXd& vector, double dimensions) {
  const auto n = static_cast<Eigen::Index>(coordinates.size());
  if (information.rows() != n || information.cols() != n || vector.size() != n) {
    throw std::invalid_argument("RegistrationPriorScale::add: sizes do not match the coordinates");
  }
  for (Eigen::Index j = 0; j < n; ++j) {
    vector_(coordinates[j]) += vector(j);
    for (Eigen::Index i = 0; i < n; ++i) information_(coordinates[i], coordinates[j]) += information(i, j);
  }
  dimensions_ += dimensions;
}

std::vector<double> RegistrationPriorScale::log_posterior() const {
  // Split β into the scaled coordinates s and the fixed ones f; integrate f out under its prior.
  std::vector<Eigen::Index> scaled, fixed;
  for (std::size_t j = 0; j < scaled_.size(); ++j) (scaled_[j] ? scaled : fixed).push_back(static_cast<Eigen::Index>(j));
  Eigen::MatrixXd a = information_(scaled, scaled);
  Eigen::VectorXd b = vector_(scaled);
  if (!fixed.empty()) {
    Eigen::MatrixXd fixed_information = information_(fixed, fixed);
    for (std::size_t k = 0; k < fixed.size(); ++k) {
      fixed_information(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)) += prior_information_[static_cast<std::size_t>(fixed[k])];
    }
    const Eigen::LLT<Eigen::MatrixXd> factor(fixed_information);
    const Eigen::MatrixXd coupling = information_(scaled, fixed);
    a -= coupling * factor.solve(coupling.transpose());
    b -= coupling * factor.solve(vector_(fixed));
  }
  // Whiten by the prior: Λ₀^{-½} A Λ₀^{-½} = Q T Qᵀ, g = Qᵀ Λ₀^{-½} b.
  Eigen::VectorXd whitening(static_cast<Eigen::Index>(scaled.size()));
  for (std::size_t k = 0; k < scaled.size(); ++k) {
    whitening(static_cast<Eigen::Index>(k)) = 1.0 / std::sqrt(prior_information_[static_cast<std::size_t>(scaled[k])]);
  }
  std::vector<double> result(kGridPoints);
  Eigen::VectorXd diagonal, subdiagonal, g;
  if (whitening.size() > 0) {
    const Eigen::MatrixXd whitened = whitening.asDiagonal() * a * whitening.asDiagonal();
    const Eigen::Tridiagonalization<Eigen::MatrixXd> tridiagonal(whitened);
    diagonal = tridiagonal.diagonal();
    subdiagonal = tridiagonal.subDiagonal();
    g = tridiagonal.matrixQ().transpose() * whitening.cwiseProduct(b);
  }
  for (int k = 0; k < kGridPoints; ++k) {
    const double log2_scale = grid_log2_scale(k);
    const double log_scale = log2_scale * std::log(2.0);
    const double prior = -0.5 * log_scale * log_scale / (kLogScaleSigma * kLogScaleSigma);
    result[static_cast<std::size_t>(k)] =
        prior + (whitening.size() > 0 ? log_marginal_likelihood(std::exp2(log2_scale), diagonal, subdiagonal, g) : 0.0);
  }
  return result;
}

bool RegistrationPriorScale::update() {
  if (dimensions_ < kFirstEstimateDimensions || dimensions_ < 2.0 * estimated_at_) return false;
  estimated_at_ = dimensions_;
  // κ̂ = E[κ | data] over the grid.
  const std::vector<double> posterior = log_posterior();
  const double peak = *std::max_element(posterior.begin(), posterior.end());
  double total = 0.0, weighted = 0.0;
  for (int k = 0; k < kGridPoints; ++k) {
    const double weight = std::exp(posterior[static_cast<std::size_t>(k)] - peak);
    total += weight;
    weighted += weight * std::exp2(grid_log2_scale(k));
  }
  const double scale = weighted / total;
  const bool changed = scale != scale_;
  scale_ = scale;
  return changed;
}

}  // namespace stgf
