// SPDX-License-Identifier: Apache-2.0
#pragma once
// Localization metrics (DESIGN §4), over rows (scene, t, view, object) that pair an estimate
// N(x̂, P̂) with the truth y:
//
//   DE      = mean ‖x̂ − y‖₂                                   (metres)
//   REL-DE  = mean ‖x̂ − y‖₂ / ‖y − s_v‖₂, s_v = the position of the view's sensor
//   NEES    = mean (x̂ − y)ᵀ P̂⁻¹ (x̂ − y), and the share of rows whose NEES lies inside the two-sided
//             95% interval of χ²(3). A calibrated filter has mean NEES ≈ 3 and a share ≈ 0.95; a
//             larger mean means an overconfident covariance, a smaller one an overcautious one.
//   NEES by direction: the same of the horizontal marginal (x, y: e_hᵀ P̂_hh⁻¹ e_h, χ²(2), mean 2 when
//             calibrated) and of the vertical one (z: e_z² / P̂_zz, χ²(1), mean 1). The 3-D mean alone can
//             look calibrated while it is not: on ground-plane cameras an overcautious height (z,
//             mean 0.2) hides an overconfident ground position (x, y, mean 2.9, where 2 is calibrated).

#include <cstddef>
#include <limits>
#include <optional>

#include "stgf/core/gaussian.hpp"

namespace stgf {

// The 2.5% and 97.5% quantiles of χ² with 3 degrees of freedom.
inline constexpr double kChiSquare3Lower95 = 0.215795282623898;
inline constexpr double kChiSquare3Upper95 = 9.348403604496138;

struct ErrorSummary {
  static constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();
  std::size_t rows = 0;
  double displacement_error = kUndefined;           // DE
  double relative_displacement_error = kUndefined;  // REL-DE; undefined unless every row has a sensor
  double nees_mean = kUndefined;
  double nees_share_in_95 = kUndefined;
  double nees_horizontal_mean = kUndefined;  // x, y: 2 when calibrated
  double nees_vertical_mean = kUndefined;    // z: 1 when calibrated
};

class ErrorAccumulator {
 public:
  // Adds one row. `sensor_position` is where the view holding the estimate was; without it the
  // row has no range and REL-DE becomes undefined for the whole set.
  void add(const Gaussian3& estimate, const Vector3d& truth,
           const std::optional<Vector3d>& sensor_position);

  ErrorSummary summary() const;

 private:
  std::size_t rows_ = 0;
  std::size_t rows_with_range_ = 0;
  std::size_t nees_inside_ = 0;
  double displacement_sum_ = 0.0;
  double relative_displacement_sum_ = 0.0;
  double nees_sum_ = 0.0;
  double nees_horizontal_sum_ = 0.0;
  double nees_vertical_sum_ = 0.0;
};

}  // namespace stgf
