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
double grid_log2_ratio(int index) {
  return RegistrationPriorScale::kRatioStep * (index - RegistrationPriorScale::kEqualRatio);
}

// ½ gᵀ (I/κ + T)⁻¹ g − ½ log det(I + κ T) for the symmetric tridiagonal T (diagonal, subdiagonal e),
// at every κ of the grid at once, by the LDLᵀ of I/κ + T:
//     D_i = 1/κ + T_ii − e²_{i−1} / D_{i−1},   w_i = g_i − e_{i−1} w_{i−1} / D_{i−1},
//     gᵀ(I/κ + T)⁻¹g = Σ w_i² / D_i,            det(I + κT) = Π κ D_i.
// The grid is the inner loop (independent recurrences, one division each, vectorisable), and the
// determinant's product is renormalised every few rows by its binary exponent (κ D_i ≥ 1 for T ⪰ 0,
// and each factor is far below 10³⁰), one logarithm at the end. −∞ where I/κ + T is not positive
// definite (T not quite ⪰ 0 in rounding).
std::array<double, RegistrationPriorScale::kGridPoints> log_marginal_likelihoods(const Eigen::VectorXd& diagonal,
                                                                                 const Eigen::VectorXd& subdiagonal,
                                                                                 const Eigen::VectorXd& g) {
  constexpr int n = RegistrationPriorScale::kGridPoints;
  std::array<double, n> scale{}, inverse_scale{}, inverse_pivot{}, solved{}, quadratic{}, product{};
  std::array<int, n> binary_exponent{};  // det(I + κT) = product · 2^binary_exponent
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
        int exponent = 0;
        product[k] = std::frexp(product[k], &exponent);
        binary_exponent[k] += exponent;
      }
    }
  }
  std::array<double, n> result{};
  for (int k = 0; k < n; ++k) {
    const double log_determinant = std::log(product[k]) + binary_exponent[k] * std::log(2.0);
    result[k] = 0.5 * quadratic[k] - 0.5 * log_determinant;
  }
  for (int k = 0; k < n; ++k) {
    if (!(smallest_pivot[k] > 0.0)) result[k] = -std::numeric_limits<double>::infinity();
  }
  return result;
}

}  // namespace

void RegistrationPriorScale::add_coordinate(double prior_information, Group group) {
  if (!(prior_information > 0.0) || !std::isfinite(prior_information)) {
    throw std::invalid_argument("RegistrationPriorScale: a coordinate's prior information must be positive and finite");
  }
  prior_information_.push_back(prior_information);
  groups_.push_back(group);
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

RegistrationPriorScale::ScaledEvidence RegistrationPriorScale::scaled_evidence(std::optional<Group> axis) const {
  // Split β into the coordinates whose scale is estimated, s, and the rest, f (the fixed ones, and the
  // other scales' at their present estimates); integrate f out under its prior.
  const auto size = static_cast<Eigen::Index>(prior_information_.size());
  const Eigen::MatrixXd information = information_.topLeftCorner(size, size).selfadjointView<Eigen::Lower>();
  std::vector<Eigen::Index> scaled, fixed;
  for (std::size_t j = 0; j < groups_.size(); ++j) {
    const bool estimated = axis ? groups_[j] == *axis : groups_[j] != Group::kFixed && groups_[j] != Group::kVertical;
    (estimated ? scaled : fixed).push_back(static_cast<Eigen::Index>(j));
  }
  ScaledEvidence evidence{information(scaled, scaled), vector_(scaled), Eigen::VectorXd(static_cast<Eigen::Index>(scaled.size())), {}};
  if (!fixed.empty()) {
    Eigen::MatrixXd fixed_information = information(fixed, fixed);
    for (std::size_t k = 0; k < fixed.size(); ++k) {
      const auto j = static_cast<std::size_t>(fixed[k]);
      fixed_information(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)) += prior_information_[j] / scale(groups_[j]);
    }
    const Eigen::LLT<Eigen::MatrixXd> factor(fixed_information);
    const Eigen::MatrixXd coupling = information(scaled, fixed);
    evidence.information -= coupling * factor.solve(coupling.transpose());
    evidence.vector -= coupling * factor.solve(vector_(fixed).eval());
  }
  for (std::size_t k = 0; k < scaled.size(); ++k) {
    const auto j = static_cast<std::size_t>(scaled[k]);
    evidence.prior_information(static_cast<Eigen::Index>(k)) = prior_information_[j];
    // Scaled by κ itself, not by ρ κ: translations in the joint estimate, and a group on its own.
    evidence.translation.push_back(axis.has_value() || groups_[j] == Group::kTranslation);
  }
  return evidence;
}

std::vector<double> RegistrationPriorScale::log_likelihood(double log2_ratio) const {
  const std::array<double, kGridPoints> values = log_likelihood(scaled_evidence(), log2_ratio);
  return {values.begin(), values.end()};
}

std::array<double, RegistrationPriorScale::kGridPoints> RegistrationPriorScale::log_likelihood(const ScaledEvidence& evidence,
                                                                                               double log2_ratio) {
  // Whiten by Λ_ρ: Λ_ρ^{-½} A Λ_ρ^{-½} = Q T Qᵀ, g = Qᵀ Λ_ρ^{-½} b.
  const double ratio = std::exp2(log2_ratio);
  const Eigen::Index size = evidence.prior_information.size();
  if (size == 0) return {};
  Eigen::VectorXd whitening(size);
  for (Eigen::Index k = 0; k < size; ++k) {
    const double prior_variance = 1.0 / evidence.prior_information(k);
    whitening(k) = std::sqrt(evidence.translation[static_cast<std::size_t>(k)] ? prior_variance : ratio * prior_variance);
  }
  const Eigen::MatrixXd whitened = whitening.asDiagonal() * evidence.information * whitening.asDiagonal();
  const Eigen::Tridiagonalization<Eigen::MatrixXd> tridiagonal(whitened);
  const Eigen::VectorXd g = tridiagonal.matrixQ().transpose() * whitening.cwiseProduct(evidence.vector);
  return log_marginal_likelihoods(tridiagonal.diagonal(), tridiagonal.subDiagonal(), g);
}

std::vector<double> RegistrationPriorScale::log_likelihood_grid() const {
  const ScaledEvidence evidence = scaled_evidence();
  std::vector<double> grid;
  grid.reserve(kPooledGridSize);
  for (int ratio = -(kPooledRatios - 1) / 2; ratio <= (kPooledRatios - 1) / 2; ++ratio) {
    const std::array<double, kGridPoints> values = log_likelihood(evidence, static_cast<double>(ratio));
    grid.insert(grid.end(), values.begin(), values.end());
  }
  for (const Group axis : kAxisGroups) {
    const std::array<double, kGridPoints> values = log_likelihood(scaled_evidence(axis), 0.0);
    grid.insert(grid.end(), values.begin(), values.end());
  }
  return grid;
}

double scale_of(const RegistrationPriorScales& scales, RegistrationPriorScale::Group group) {
  using Group = RegistrationPriorScale::Group;
  switch (group) {
    case Group::kTranslation: return scales.translation;
    case Group::kNoiseRatio: return scales.noise_ratio;
    case Group::kAlong: return scales.along;
    case Group::kAcross: return scales.across;
    case Group::kVertical: return scales.vertical;
    case Group::kFixed: break;
  }
  return 1.0;
}

double RegistrationPriorScale::scale(Group group) const { return scale_of(scales_, group); }

namespace {

// The grid's κ_t and ρ, and the hypotheses' log priors on it, each normalised over its own (update()):
// computed once.
struct GridPriors {
  std::array<double, RegistrationPriorScale::kGridPoints> scale{};
  std::array<double, RegistrationPriorScale::kRatioPoints> ratio{};
  std::array<double, RegistrationPriorScale::kGridPoints> one{};
  std::array<std::array<double, RegistrationPriorScale::kGridPoints>, RegistrationPriorScale::kRatioPoints> two{};
  GridPriors() {
    const auto log_prior = [](double log2_scale) {
      const double ln = log2_scale * std::log(2.0);
      return -0.5 * ln * ln / (RegistrationPriorScale::kLogScaleSigma * RegistrationPriorScale::kLogScaleSigma);
    };
    for (int r = 0; r < RegistrationPriorScale::kRatioPoints; ++r) ratio[static_cast<std::size_t>(r)] = std::exp2(grid_log2_ratio(r));
    double one_norm = 0.0, two_norm = 0.0;
    for (int k = 0; k < RegistrationPriorScale::kGridPoints; ++k) {
      scale[static_cast<std::size_t>(k)] = std::exp2(grid_log2_scale(k));
      one[static_cast<std::size_t>(k)] = log_prior(grid_log2_scale(k));
      one_norm += std::exp(one[static_cast<std::size_t>(k)]);
      for (int r = 0; r < RegistrationPriorScale::kRatioPoints; ++r) {
        double& value = two[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)];
        value = log_prior(grid_log2_scale(k)) + log_prior(grid_log2_scale(k) + grid_log2_ratio(r));
        two_norm += std::exp(value);
      }
    }
    for (double& value : one) value -= std::log(one_norm);
    for (auto& row : two) {
      for (double& value : row) value -= std::log(two_norm);
    }
  }
};

}  // namespace

void RegistrationPriorScale::set_two_scales_probability(double probability) {
  if (!(probability > 0.0 && probability < 1.0)) {
    throw std::invalid_argument("RegistrationPriorScale::set_two_scales_probability: a probability in (0, 1)");
  }
  two_scales_log_odds_ = std::log(probability / (1.0 - probability));
}

void RegistrationPriorScale::start_from(std::shared_ptr<const std::vector<double>> pooled) {
  if (pooled == nullptr || pooled->size() != static_cast<std::size_t>(kPooledGridSize)) {
    throw std::invalid_argument(
        "RegistrationPriorScale::start_from: a grid of 25 × 81 and 3 × 81 log likelihoods");
  }
  pooled_ = std::move(pooled);
  const RegistrationPriorScales joint = posterior_mean();
  scales_.translation = joint.translation;
  scales_.noise_ratio = joint.noise_ratio;
  set_axis_scales(/*first=*/true);
}

void RegistrationPriorScale::set_axis_scales(bool first) {
  // The first time, each axis group's partners start from the joint κ_n.
  if (first) scales_.along = scales_.across = scales_.vertical = scales_.noise_ratio;
  scales_.vertical = axis_posterior_mean(Group::kVertical);
  if (pooled_ == nullptr) {
    scales_.along = scales_.across = scales_.noise_ratio;
    return;
  }
  scales_.along = axis_posterior_mean(Group::kAlong);
  scales_.across = axis_posterior_mean(Group::kAcross);
}

double RegistrationPriorScale::axis_posterior_mean(Group axis) const {
  // One scale on the axis group's coordinates, the others at their estimates (integrated out under their
  // scaled priors): ln κ ~ N(0, s²) on the grid of κ_t, other scenes' evidence (start_from) added, and
  // the posterior mean.
  static const GridPriors priors;
  const bool own = dimensions_ > 0.0 && std::count(groups_.begin(), groups_.end(), axis) > 0;
  if (!own && pooled_ == nullptr) return 1.0;
  const std::array<double, kGridPoints> likelihood =
      own ? log_likelihood(scaled_evidence(axis), 0.0) : std::array<double, kGridPoints>{};
  const auto row = static_cast<std::size_t>(std::find(kAxisGroups.begin(), kAxisGroups.end(), axis) - kAxisGroups.begin());
  const std::size_t pooled_row = static_cast<std::size_t>(kPooledRatios * kGridPoints) + row * kGridPoints;
  std::array<double, kGridPoints> weights{};
  double peak = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < kGridPoints; ++k) {
    const double pooled = pooled_ == nullptr ? 0.0 : (*pooled_)[pooled_row + k];
    peak = std::max(peak, weights[k] = likelihood[k] + pooled + priors.one[k]);
  }
  double total = 0.0, mean = 0.0;
  for (std::size_t k = 0; k < kGridPoints; ++k) {
    const double weight = std::exp(weights[k] - peak);
    total += weight;
    mean += weight * priors.scale[k];
  }
  return mean / total;
}

bool RegistrationPriorScale::update() {
  if (dimensions_ < kFirstEstimateDimensions || dimensions_ < 2.0 * estimated_at_) return false;
  const bool first = !estimated();
  estimated_at_ = dimensions_;
  const RegistrationPriorScales before = scales_;
  // The joint scales with the vertical as it stands, then each axis group's with the others.
  const RegistrationPriorScales joint = posterior_mean();
  scales_.translation = joint.translation;
  scales_.noise_ratio = joint.noise_ratio;
  set_axis_scales(first);
  return before.translation != scales_.translation || before.noise_ratio != scales_.noise_ratio ||
         before.vertical != scales_.vertical || before.along != scales_.along || before.across != scales_.across;
}

RegistrationPriorScales RegistrationPriorScale::posterior_mean() const {
  // Two hypotheses (header): one scale (ρ = 1, ln κ ~ N(0, s²)), and two (ln κ_t, ln κ_n ~ N(0, s²)
  // independent, ρ on its grid) with prior odds two_scales_log_odds_, each prior normalised over its own grid;
  // (κ̂_t, κ̂_n) is the posterior mean over both. Views with coordinates of one kind only: one scale
  // (unless other scenes' evidence is pooled in, which may have had both).
  static const GridPriors priors;
  const bool own = dimensions_ > 0.0 && coordinates() > 0;
  const ScaledEvidence evidence = own ? scaled_evidence() : ScaledEvidence{};
  const auto translations = std::count(evidence.translation.begin(), evidence.translation.end(), true);
  const bool both =
      pooled_ != nullptr || (translations > 0 && translations < static_cast<std::ptrdiff_t>(evidence.translation.size()));
  // The pooled grid's row of log₂ ρ (its rows: log₂ ρ = −12, −11, …, 12).
  const auto pooled = [this](double log2_ratio, std::size_t k) {
    if (pooled_ == nullptr) return 0.0;
    const auto row = static_cast<std::size_t>(std::lround(log2_ratio) + (kPooledRatios - 1) / 2);
    return (*pooled_)[row * kGridPoints + k];
  };
  const auto likelihood_at = [&](double log2_ratio) {
    return own ? log_likelihood(evidence, log2_ratio) : std::array<double, kGridPoints>{};
  };
  // log weights: the one-scale hypothesis's, then the two-scale one's per ratio.
  std::array<std::array<double, kGridPoints>, kRatioPoints + 1> weights{};
  const std::array<double, kGridPoints> equal = likelihood_at(0.0);
  double peak = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < kGridPoints; ++k) {
    peak = std::max(peak, weights[0][k] = equal[k] + pooled(0.0, k) + priors.one[k]);
  }
  const int ratios = both ? kRatioPoints : 0;
  for (int r = 0; r < ratios; ++r) {
    const auto row = static_cast<std::size_t>(r);
    const double log2_ratio = grid_log2_ratio(r);
    const std::array<double, kGridPoints> likelihood = r == kEqualRatio ? equal : likelihood_at(log2_ratio);
    for (std::size_t k = 0; k < kGridPoints; ++k) {
      peak = std::max(peak, weights[row + 1][k] =
                                likelihood[k] + pooled(log2_ratio, k) + priors.two[row][k] + two_scales_log_odds_);
    }
  }
  double total = 0.0, translation = 0.0, noise_ratio = 0.0;
  for (int h = 0; h <= ratios; ++h) {
    const double ratio = h == 0 ? 1.0 : priors.ratio[static_cast<std::size_t>(h - 1)];
    for (std::size_t k = 0; k < kGridPoints; ++k) {
      const double weight = std::exp(weights[static_cast<std::size_t>(h)][k] - peak);
      const double scale = priors.scale[k];
      total += weight;
      translation += weight * scale;
      noise_ratio += weight * ratio * scale;
    }
  }
  return {translation / total, noise_ratio / total};
}

void LearnedRegistrationScales::add(const LearnedRegistrationScales& later) {
  scales.insert(scales.end(), later.scales.begin(), later.scales.end());
  scenes_without += later.scenes_without;
  common_translation_raised += later.common_translation_raised;
  if (later.common_translation_run_scale) common_translation_run_scale = later.common_translation_run_scale;
}

}  // namespace stgf
