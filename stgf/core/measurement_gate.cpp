// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/measurement_gate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace stgf {

double chi_square_3_quantile(double probability) {
  if (!(probability > 0.0 && probability < 1.0)) throw std::invalid_argument("a χ² quantile needs a probability in (0, 1)");
  const auto cdf = [](double x) {
    return std::erf(std::sqrt(x / 2.0)) - std::sqrt(2.0 * x / std::numbers::pi) * std::exp(-x / 2.0);
  };
  double low = 0.0;
  double high = 1.0;
  while (cdf(high) < probability) high *= 2.0;
  for (int i = 0; i < 200 && high - low > 1e-12 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (cdf(middle) < probability ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

double distance_squared(const Vector3d& innovation, const Matrix3d& covariance) {
  const Eigen::LLT<Matrix3d> factor(covariance);
  if (factor.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return factor.matrixL().solve(innovation).squaredNorm();
}

MeasurementGate::MeasurementGate(const GateOptions& options)
    : enabled_(options.enabled),
      probability_(options.probability),
      threshold_(chi_square_3_quantile(options.probability)) {}

MeasurementGate::Consensus MeasurementGate::consensus(std::span<const Gaussian3> measurements) const {
  if (measurements.empty()) throw std::invalid_argument("MeasurementGate::consensus needs a measurement");
  const std::size_t n = measurements.size();
  Consensus result{0, std::vector<bool>(n, true)};
  if (!enabled_ || n < 2) return result;
  std::vector<std::vector<bool>> agree(n, std::vector<bool>(n, true));
  std::vector<std::size_t> support(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const double d2 = distance_squared(measurements[i].mean() - measurements[j].mean(),
                                         measurements[i].covariance() + measurements[j].covariance());
      agree[i][j] = agree[j][i] = d2 <= threshold_;
      if (agree[i][j]) {
        ++support[i];
        ++support[j];
      }
    }
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (support[i] > support[result.anchor]) result.anchor = i;
  }
  if (support[result.anchor] == 0) return result;  // no two agree: nothing to go by
  result.agreement = true;
  for (std::size_t i = 0; i < n; ++i) result.passes[i] = agree[result.anchor][i];
  return result;
}

MeasurementGate::Decision MeasurementGate::decide(std::span<const double> prediction_distances,
                                                 std::span<const Gaussian3> alone, int gated_events,
                                                 int restart_after) const {
  const std::size_t n = alone.size();
  Decision decision = pass_all(n);
  if (!enabled_) return decision;
  if (!prediction_distances.empty()) {
    decision.checked = true;
    bool any = false;
    for (std::size_t k = 0; k < n; ++k) {
      decision.passes[k] = passes(prediction_distances[k]);
      any = any || decision.passes[k];
    }
    // The prediction may be what is wrong: when more measurements agree with each other than pass
    // against it, and they do not include what passed, the track starts again from them.
    const std::size_t passing = static_cast<std::size_t>(std::count(decision.passes.begin(), decision.passes.end(), true));
    if (passing == n) return decision;
    const Consensus consensus = this->consensus(alone);
    const std::size_t agreeing = static_cast<std::size_t>(std::count(consensus.passes.begin(), consensus.passes.end(), true));
    const bool wrong_prediction = consensus.agreement && !decision.passes[consensus.anchor] && agreeing > passing;
    if (wrong_prediction || (passing == 0 && gated_events + 1 >= restart_after)) {
      decision.restart = true;
      decision.anchor = consensus.anchor;
      decision.passes = consensus.passes;
    }
    return decision;
  }
  const Consensus consensus = this->consensus(alone);
  decision.checked = n > 1;
  decision.conflicting = n > 1 && !consensus.agreement;
  decision.anchor = consensus.anchor;
  decision.passes = consensus.passes;
  return decision;
}

}  // namespace stgf
