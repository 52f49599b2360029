// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_scale_pool.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace stgf {

RegistrationPriorScales RegistrationScalePool::Point::scales() const {
  const auto on_grid = [](int index) { return std::exp2(0.25 * index - 10.0); };  // κ_t's grid
  RegistrationPriorScales scales;
  scales.translation = on_grid(scale);
  scales.noise_ratio = scales.translation * std::exp2(ratio - kUnitRatio);
  scales.along = on_grid(axes[0]);
  scales.across = on_grid(axes[1]);
  scales.vertical = on_grid(axes[2]);
  return scales;
}

RegistrationScalePool::Point RegistrationScalePool::Point::lowered_to_unit() const {
  const int lowered_scale = std::min(scale, kUnitScale);
  // log2 κ_n = (scale / 4 − 10) + (ratio − 12); the ratio that takes it to min(κ_n, 1) from κ_t'.
  const double log2_noise_ratio = std::min(0.0, 0.25 * scale - 10.0 + (ratio - kUnitRatio));
  const double log2_ratio = log2_noise_ratio - (0.25 * lowered_scale - 10.0);
  // Rounded down: at most 1 (κ_t' = 1 at a scale not a multiple of 4 leaves a fraction).
  const int lowered_ratio =
      std::clamp(static_cast<int>(std::floor(log2_ratio + 1e-9)) + kUnitRatio, 0, kRatioIndices - 1);
  Point lowered{lowered_scale, lowered_ratio, axes};
  for (int& axis : lowered.axes) axis = std::min(axis, kUnitScale);
  return lowered;
}

RegistrationScalePool::Point RegistrationScalePool::Point::translation_lowered_to_unit() const {
  const int lowered_scale = std::min(scale, kUnitScale);
  // κ_n = κ_t ρ kept: ρ' = ρ κ_t / κ_t', in whole octaves rounded down (a κ_t above 1 by a fraction of
  // one leaves κ_n up to 2^¾ below the estimate), at most the ratios' grid's end.
  const int octaves_lowered = (scale - lowered_scale) / 4;
  return Point{lowered_scale, std::min(ratio + octaves_lowered, kRatioIndices - 1), axes};
}

void RegistrationScalePool::add(std::size_t scene_index, std::span<const double> grid, Point applied) {
  if (grid.size() != static_cast<std::size_t>(kGridSize)) {
    throw std::invalid_argument("RegistrationScalePool::add: a grid of 25 × 81 and 3 × 81 log likelihoods");
  }
  Evidence& pending = sums_.add_scene(scene_index);
  // The axis groups' rows, each shifted as κ_t's: k + k_a* − 40.
  for (std::size_t a = 0; a < kAxes; ++a) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const auto j = static_cast<std::size_t>(k + applied.axes[a]);
      pending.axes[a][j] += grid[static_cast<std::size_t>((kRatioIndices + static_cast<int>(a)) * kScaleIndices + k)];
      ++pending.axes_covered[a][j];
    }
  }
  // Shifted to the calibration's scales: k + k* − 40, r + r* − 12, each offset by its span's margin.
  for (int r = 0; r < kRatioIndices; ++r) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const int row = r + applied.ratio;     // (r + r* − 12) + 12
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
  for (std::size_t a = 0; a < kAxes; ++a) {
    for (std::size_t k = 0; k < axes[a].size(); ++k) {
      axes[a][k] += other.axes[a][k];
      axes_covered[a][k] += other.axes_covered[a][k];
    }
  }
}

std::optional<RegistrationScalePool::Point> RegistrationScalePool::estimate_for(std::size_t scene_index) const {
  const auto before = sums_.before(scene_index);
  if (before.scenes < kFewestScenes) return std::nullopt;
  std::optional<Point> best;
  double best_value = -std::numeric_limits<double>::infinity();
  // Within the grid's own range: κ_t in [2^-10, 2^10], ρ in [2^-12, 2^12].
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
  if (!best) return best;
  // κ_v: its row's argmax; a flat row (no scene had vertical offsets to compare) says nothing, and
  // leaves it at the calibration's.
  double highest = -std::numeric_limits<double>::infinity(), lowest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kScaleIndices; ++k) {
    const auto j = static_cast<std::size_t>(k + kUnitScale);
    if (before.evidence.axes_covered[kVerticalAxis][j] != before.scenes) continue;
    const double value = before.evidence.axes[kVerticalAxis][j];
    lowest = std::min(lowest, value);
    if (value > highest) {
      highest = value;
      best->axes[kVerticalAxis] = k;
    }
  }
  if (!(highest > lowest)) best->axes[kVerticalAxis] = kUnitScale;
  if (use_ == Use::kLowerOnly) best = best->lowered_to_unit();
  if (use_ == Use::kTranslationLoweredOnly) best = best->translation_lowered_to_unit();
  // δ along and across the rays follow κ_n here (RegistrationPriorScale: they are learned apart only from
  // other scenes' evidence, Use::kEvidence): κ_n's index on κ_t's grid, k + 4 (r − 12), at least 0.
  best->axes[0] = best->axes[1] = std::clamp(best->scale + 4 * (best->ratio - kUnitRatio), 0, kScaleIndices - 1);
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
  for (std::size_t a = 0; a < kAxes; ++a) {
    for (int k = 0; k < kScaleIndices; ++k) {
      const auto j = static_cast<std::size_t>(k + kUnitScale);
      if (before.evidence.axes_covered[a][j] != before.scenes) {
        throw std::logic_error("RegistrationScalePool::evidence_for: a scene ran with the prior scaled");
      }
      grid.push_back(before.evidence.axes[a][j]);
    }
  }
  return grid;
}

}  // namespace stgf
