// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_scale_pool.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace stgf {

RegistrationPriorScales RegistrationScalePool::Point::scales() const {
  const double translation = std::exp2(0.25 * scale - 10.0);
  return {translation, translation * std::exp2(ratio - kUnitRatio), std::exp2(0.25 * vertical - 10.0)};
}

RegistrationScalePool::Point RegistrationScalePool::Point::lowered_to_unit() const {
  const int lowered_scale = std::min(scale, kUnitScale);
  // log2 κ_n = (scale / 4 − 10) + (ratio − 8); the ratio that takes it to min(κ_n, 1) from κ_t'.
  const double log2_noise_ratio = std::min(0.0, 0.25 * scale - 10.0 + (ratio - kUnitRatio));
  const double log2_ratio = log2_noise_ratio - (0.25 * lowered_scale - 10.0);
  // Rounded down: at most 1 (κ_t' = 1 at a scale not a multiple of 4 leaves a fraction).
  const int lowered_ratio =
      std::clamp(static_cast<int>(std::floor(log2_ratio + 1e-9)) + kUnitRatio, 0, kRatioIndices - 1);
  return {lowered_scale, lowered_ratio, std::min(vertical, kUnitScale)};
}

void RegistrationScalePool::add(std::size_t scene_index, std::span<const double> grid, Point applied) {
  if (grid.size() != static_cast<std::size_t>(kGridSize)) {
    throw std::invalid_argument("RegistrationScalePool::add: a grid of 17 × 81 and 81 log likelihoods");
  }
  Evidence& pending = sums_.add_scene(scene_index);
  // κ_v's row, shifted as κ_t's: k + k_v* − 40.
  for (int k = 0; k < kScaleIndices; ++k) {
    const auto j = static_cast<std::size_t>(k + applied.vertical);
    pending.vertical[j] += grid[static_cast<std::size_t>(kRatioIndices * kScaleIndices + k)];
    ++pending.vertical_covered[j];
  }
  // Shifted to the calibration's scales: k + k* − 40, r + r* − 8, each offset by its span's margin.
  for (int r = 0; r < kRatioIndices; ++r) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const int row = r + applied.ratio;  // (r + r* − 8) + 8
      const int column = k + applied.scale;  // (k + k* − 40) + 40
      const auto j = static_cast<std::size_t>(row * kScaleSpan + column);
      pending.log_likelihood[j] += grid[static_cast<std::size_t>(r * kScaleIndices + k)];
      ++pending.covered[j];
    }
  }
}

void RegistrationScalePool::Evidence::add(const Evidence& other) {
  for (std::size_t j = 0; j < log_likelihood.size(); ++j) {
    log_likelihood[j] += other.log_likelihood[j];
    covered[j] += other.covered[j];
  }
  for (std::size_t k = 0; k < vertical.size(); ++k) {
    vertical[k] += other.vertical[k];
    vertical_covered[k] += other.vertical_covered[k];
  }
}

std::optional<RegistrationScalePool::Point> RegistrationScalePool::estimate_for(std::size_t scene_index) const {
  const auto before = sums_.before(scene_index);
  if (before.scenes < kFewestScenes) return std::nullopt;
  std::optional<Point> best;
  double best_value = -std::numeric_limits<double>::infinity();
  // Within the grid's own range: κ_t in [2^-10, 2^10], ρ in [2^-8, 2^8].
  for (int r = 0; r < kRatioIndices; ++r) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const auto j = static_cast<std::size_t>((r + kUnitRatio) * kScaleSpan + k + kUnitScale);
      if (before.evidence.covered[j] != before.scenes) continue;
      const double value = before.evidence.log_likelihood[j];
      if (value > best_value) {
        best_value = value;
        best = Point{k, r};
      }
    }
  }
  // κ_v: its row's argmax; a flat row (no scene had vertical offsets to compare) says nothing, and
  // leaves it at the calibration's.
  if (best) {
    double highest = -std::numeric_limits<double>::infinity(), lowest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < kScaleIndices; ++k) {
      const auto j = static_cast<std::size_t>(k + kUnitScale);
      if (before.evidence.vertical_covered[j] != before.scenes) continue;
      const double value = before.evidence.vertical[j];
      lowest = std::min(lowest, value);
      if (value > highest) {
        highest = value;
        best->vertical = k;
      }
    }
    if (!(highest > lowest)) best->vertical = kUnitScale;
  }
  if (best && use_ == Use::kLowerOnly) best = best->lowered_to_unit();
  return best;
}

std::optional<std::vector<double>> RegistrationScalePool::evidence_for(std::size_t scene_index) const {
  const auto before = sums_.before(scene_index);
  if (before.scenes == 0) return std::nullopt;
  std::vector<double> grid;
  grid.reserve(static_cast<std::size_t>(kGridSize));
  for (int r = 0; r < kRatioIndices; ++r) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const auto j = static_cast<std::size_t>((r + kUnitRatio) * kScaleSpan + k + kUnitScale);
      if (before.evidence.covered[j] != before.scenes) {
        throw std::logic_error("RegistrationScalePool::evidence_for: a scene ran with the prior scaled");
      }
      grid.push_back(before.evidence.log_likelihood[j]);
    }
  }
  for (int k = 0; k < kScaleIndices; ++k) {
    const auto j = static_cast<std::size_t>(k + kUnitScale);
    if (before.evidence.vertical_covered[j] != before.scenes) {
      throw std::logic_error("RegistrationScalePool::evidence_for: a scene ran with the prior scaled");
    }
    grid.push_back(before.evidence.vertical[j]);
  }
  return grid;
}

}  // namespace stgf
