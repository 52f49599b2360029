// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_scale_pool.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "stgf/core/scene_epochs.hpp"

namespace stgf {

RegistrationPriorScales RegistrationScalePool::Point::scales() const {
  const double translation = std::exp2(0.25 * scale - 10.0);
  return {translation, translation * std::exp2(ratio - kUnitRatio)};
}

void RegistrationScalePool::add(std::size_t scene_index, std::span<const double> grid, Point applied) {
  if (grid.size() != static_cast<std::size_t>(kRatioIndices * kScaleIndices)) {
    throw std::invalid_argument("RegistrationScalePool::add: a grid of 17 × 81 log likelihoods");
  }
  const std::size_t epoch = scene_epoch(scene_index);
  if (epoch < pending_epoch_) throw std::logic_error("RegistrationScalePool::add: scenes out of list order");
  if (epoch > pending_epoch_) {
    for (std::size_t j = 0; j < pending_.log_likelihood.size(); ++j) {
      committed_.log_likelihood[j] += pending_.log_likelihood[j];
      committed_.covered[j] += pending_.covered[j];
    }
    committed_.scenes += pending_.scenes;
    pending_ = Sum{};
    pending_epoch_ = epoch;
  }
  // Shifted to the calibration's scales: k + k* − 40, r + r* − 8, each offset by its span's margin.
  for (int r = 0; r < kRatioIndices; ++r) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const int row = r + applied.ratio;  // (r + r* − 8) + 8
      const int column = k + applied.scale;  // (k + k* − 40) + 40
      const auto j = static_cast<std::size_t>(row * kScaleSpan + column);
      pending_.log_likelihood[j] += grid[static_cast<std::size_t>(r * kScaleIndices + k)];
      ++pending_.covered[j];
    }
  }
  ++pending_.scenes;
}

std::optional<RegistrationScalePool::Point> RegistrationScalePool::estimate_for(std::size_t scene_index) const {
  const std::size_t epoch = scene_epoch(scene_index);
  const bool with_pending = pending_epoch_ < epoch;  // the pending epoch is complete once a later one runs
  const std::size_t scenes = committed_.scenes + (with_pending ? pending_.scenes : 0);
  if (scenes < kFewestScenes) return std::nullopt;
  std::optional<Point> best;
  double best_value = -std::numeric_limits<double>::infinity();
  // Within the grid's own range: κ_t in [2^-10, 2^10], ρ in [2^-8, 2^8].
  for (int r = 0; r < kRatioIndices; ++r) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const auto j = static_cast<std::size_t>((r + kUnitRatio) * kScaleSpan + k + kUnitScale);
      const std::size_t covered = committed_.covered[j] + (with_pending ? pending_.covered[j] : 0);
      if (covered != scenes) continue;
      const double value = committed_.log_likelihood[j] + (with_pending ? pending_.log_likelihood[j] : 0.0);
      if (value > best_value) {
        best_value = value;
        best = Point{k, r};
      }
    }
  }
  return best;
}

}  // namespace stgf
