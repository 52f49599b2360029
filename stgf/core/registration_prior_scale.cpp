// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_prior_scale.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace stgf {
namespace {

double grid_log2_scale(int index) { return 0.25 * index - 10.0; }

// ½ gᵀ (I/κ + T)⁻¹ g − ½ log det(I + κ T) for the symmetric tridiagonal T (diagonal, subdiagonal e),
// at every κ of the grid at once, by the LDLᵀ of I/κ + T:
//     D_i = 1/κ + T_ii − e²_{i−1} / D_{i−1},   w_i = g_i − e_{i−1} w_{i−1} / D_{i−1},
//     gᵀ(I/κ + T)⁻¹g = Σ w_i² / D_i,            det(I + κT) = Π κ D_i.
// The grid is the inner loop (independent recurrences, one division each, vectorisable), and the
// determinant's product takes a logarithm every few rows only (κ D_i ≥ 1 for T ⪰ 0, and each factor
// is far below 10³⁰). −∞ where I/κ + T is not positive definite (T not quite ⪰ 0 in rounding).
std::array<double, RegistrationPriorScale::kGridPoints> log_marginal_likelihoods(const Eigen::VectorXd& diagonal,
                                                                                 const Eigen::VectorXd& subdiagonal,
                                                                                 const Eigen::VectorXd& g) {
  constexpr int n = RegistrationPriorScale::kGridPoints;
  std::array<double, n> scale{}, inverse_scale{}, inverse_pivot{}, solved{}, quadratic{}, log_determinant{}, product{};
  std::array<double, n> smallest_pivot{};
  for (int k = 0; k < n; ++k) {
    scale[k] = std::exp2(grid_log2_scale(k));
    inverse_scale[k] = 1.0 / scale[k];
    product[k] = 1.0;
    smallest_pivot[k] = std::numeric_limits<double>::infinity();
  }
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) {
    const double e = i > 0 ? subdiagonal(i - 1) : 0.0;
    const double e2 = e * e;
    for (int k = 0; k < n; ++k) {
      const double d = inverse_scale[k] + diagonal(i) - e2 * inverse_pivot[k];
      const double w = g(i) - e * solved[k] * inverse_pivot[k];
      smallest_pivot[k] = std::min(smallest_pivot[k], d);
      inverse_pivot[k] = 1.0 / d;
      solved[k] = w;
      quadratic[k] += w * w * inverse_pivot[k];
      product[k] *= scale[k] * d;
    }
    if (i % 8 == 7) {
      for (int k = 0; k < n; ++k) {
        log_determinant[k] += std::log(product[k]);
        product[k] = 1.0;
      }
    }
  }
  std::array<double, n> result{};
  for (int k = 0; k < n; ++k) result[k] = 0.5 * quadratic[k] - 0.5 * (log_determinant[k] + std::log(product[k]));
  for (int k = 0; k < n; ++k) {
    if (!(smallest_pivot[k] > 0.0)) result[k] = -std::numeric_limits<double>::infinity();
  }
  return result;
}

}  // namespace

void RegistrationPriorScale::add_coordinate(double prior_information, bool scaled) {
  if (!(prior_information > 0.0) || !std::isfinite(prior_information)) {
    throw std::invalid_argument("RegistrationPriorScale: a coordinate's prior information must be positive and finite");
  }
  prior_information_.push_back(prior_information);
  scaled_.push_back(scaled);
  const auto size = static_cast<Eigen::Index>(prior_information_.size());
  if (size > information_.rows()) {  // room for twice as many: views keep coming in a long scene
    const Eigen::Index capacity = std::max<Eigen::Index>(2 * size, 16);
    Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(capacity, capacity);
    grown.topLeftCorner(size - 1, size - 1) = information_.topLeftCorner(size - 1, size - 1);
    information_ = std::move(grown);
    Eigen::VectorXd grown_vector = Eigen::VectorXd::Zero(capacity);
    grown_vector.head(size - 1) = vector_.head(size - 1);
    vector_ = std::move(grown_vector);
  }
}

void RegistrationPriorScale::add_information(Eigen::Index row, Eigen::Index column,
                                             const Eigen::Ref<const Eigen::MatrixXd>& block) {
  const auto size = static_cast<Eigen::Index>(prior_information_.size());
  if (row < column || row + block.rows() > size || column + block.cols() > size) {
    throw std::invalid_argument("RegistrationPriorScale::add_information: the block is not in A's lower triangle");
  }
  information_.block(row, column, block.rows(), block.cols()) += block;
}

void RegistrationPriorScale::add_vector(Eigen::Index row, const Eigen::Ref<const Eigen::VectorXd>& segment) {
  if (row < 0 || row + segment.size() > static_cast<Eigen::Index>(prior_information_.size())) throw std::invalid_argument("RegistrationPriorScale::add_vector: outside b");
  vector_.segment(row, segment.size()) += segment;
}

std::vector<double> RegistrationPriorScale::log_posterior() const {
  // Split β into the scaled coordinates s and the fixed ones f; integrate f out under its prior.
  const auto size = static_cast<Eigen::Index>(prior_information_.size());
  const Eigen::MatrixXd information = information_.topLeftCorner(size, size).selfadjointView<Eigen::Lower>();
  std::vector<Eigen::Index> scaled, fixed;
  for (std::size_t j = 0; j < scaled_.size(); ++j) (scaled_[j] ? scaled : fixed).push_back(static_cast<Eigen::Index>(j));
  Eigen::MatrixXd a = information(scaled, scaled);
  Eigen::VectorXd b = vector_(scaled);
  if (!fixed.empty()) {
    Eigen::MatrixXd fixed_information = information(fixed, fixed);
    for (std::size_t k = 0; k < fixed.size(); ++k) {
      fixed_information(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)) += prior_information_[static_cast<std::size_t>(fixed[k])];
    }
    const Eigen::LLT<Eigen::MatrixXd> factor(fixed_information);
    const Eigen::MatrixXd coupling = information(scaled, fixed);
    a -= coupling * factor.solve(coupling.transpose());
    b -= coupling * factor.solve(vector_(fixed).eval());
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
  std::array<double, kGridPoints> likelihood{};
  if (whitening.size() > 0) likelihood = log_marginal_likelihoods(diagonal, subdiagonal, g);
  for (int k = 0; k < kGridPoints; ++k) {
    const double log_scale = grid_log2_scale(k) * std::log(2.0);
    const double prior = -0.5 * log_scale * log_scale / (kLogScaleSigma * kLogScaleSigma);
    result[static_cast<std::size_t>(k)] = prior + likelihood[static_cast<std::size_t>(k)];
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
