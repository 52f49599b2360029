// SPDX-License-Identifier: Apache-2.0
#pragma once
// A robust per-view scale on the stated noise, for a view whose measurements keep disagreeing with
// what the filter predicts from everything else — a camera knocked out of calibration, a detector
// whose covariance understates its error. One faulty view would otherwise spoil every object it sees:
// the χ² gate (measurement_gate.hpp) keeps out its grossest errors, but what passes comes with an R
// that claims far too much.
//
// Model: view u's measurements have noise μ_u R (R as stated, μ_u ≥ 1; 1 for a view that behaves).
// Each measurement of u that has a prediction gives the innovation ν ~ N(0, A + μ_u R), where A is
// the prediction's share of S (measurement_gate.hpp). For the view's last kWindow such innovations,
//     d²_k(μ) = ν_kᵀ (A_k + μ R_k)⁻¹ ν_k,     m(μ) = median_k d²_k(μ),
// and the median of χ²(3) is m₃ = 2.366. The view is taken as faulty when either
//   - m(1) > kTrigger · m₃: the typical measurement of the view lies where an honest one lands about
//     12 % of the time — with kWindow = 15, a view that behaves crosses it with probability about 10⁻⁴
//     per window; or
//   - its typical innovation ν̄ (the coordinate-wise median of the window, which gross outliers do not
//     move) is far from zero: ν̄ᵀ V⁻¹ ν̄ > the χ²(3) quantile 0.999, V = mean_k (π/2 (S_k − C_k)/kWindow + C_k),
//     where C_k is the part of S_k that successive measurements of the view share (its offset's
//     uncertainty, which does not average out) — a bias (a jump) that is small against the noise of
//     one measurement but persists; or
//   - the same holds for its last kRecent = 5 innovations at the χ²(3) quantile 0.9999: a jump shows
//     within five measurements instead of half a window. Then μ_u is the smallest grid point 2^(j/2), j = 1 … 40, with
// m(μ_u) ≤ m₃ (m decreases in μ), and 1 again as soon as m(1) falls back below the trigger. The
// median ignores gross outliers (up to half the window), which the gate handles on their own, and it
// reacts to a step change (a jump) within half a window.
//
// A bias (a jump) shows as a large μ just the same: its measurements stop counting for much, and
// the objects only that view sees get a covariance as large as the disagreement.
//
// What the filter reports for each view: its largest μ, when it was first found disagreeing (with the
// median that showed it), how often its offset was widened, and how many of its measurements the gate
// checked and left out.

#include <array>
#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

class ViewNoiseScales {
 public:
  static constexpr std::size_t kWindow = 15;
  static constexpr std::size_t kRecent = 5;
  static constexpr double kTrigger = 2.5;
  static constexpr double kChiSquare3Median = 2.365973884375338;

  // μ of the view (1 for an unknown one).
  double scale(std::string_view view) const;

  // Adds a disagreement of a measurement of `view` at `time` with the other views: ν, the others'
  // share A of its covariance, and the stated R. Updates μ of the view.
  //
  // With `separate_bias` (the filter estimates the view's offset, joint_registration.hpp), a view
  // found faulty is taken to have both a changed offset and a noise scale: with ν̄ the mean of the
  // window's innovations (the median of the last five when they showed it), μ is solved on the
  // centred ones ν_k − ν̄ (of those five), the window starts afresh, and the
  // call returns ν̄ ν̄ᵀ, by which the caller widens the view's translation offset covariance (the
  // view's calibration may have changed: a jump becomes a new offset that the other views teach,
  // instead of a noise that only down-weights it). Otherwise it returns nothing.
  // `shared_covariance`: C above (zero when none).
  std::optional<Matrix3d> add(std::string_view view, double time, const Vector3d& innovation,
                              const Matrix3d& prediction_covariance, const Matrix3d& noise,
                              const Matrix3d& shared_covariance, bool separate_bias = false);
  // Counts a measurement of `view` checked by the gate, and whether it passed.
  void count(std::string_view view, bool passed);

  struct Report {
    double largest_scale = 1.0;
    // When it was first found disagreeing (NaN: never), with m(1) then.
    double first_flagged_time = std::numeric_limits<double>::quiet_NaN();
    double flagging_median = 0.0;
    std::size_t offset_releases = 0;  // times its offset was widened (separate_bias)
    std::size_t checked = 0;      // measurements checked by the gate
    std::size_t gated = 0;        // of which failed it
  };
  // Per view that has been added or counted, in name order.
  std::map<std::string, Report> reports() const;

 private:
  struct Sample {
    Vector3d innovation;
    Matrix3d prediction_covariance;
    Matrix3d noise;
    Matrix3d shared;
    double distance_squared;  // d²(1)
  };
  struct View {
    std::array<Sample, kWindow> window;
    std::size_t samples = 0;  // added so far (the window holds the last kWindow)
    double scale = 1.0;
    Report report;
  };
  // Over the last `count` samples: the median of d²(μ) of ν − centre, and the coordinate-wise median
  // of ν with its variance V.
  double median_distance_squared(const View& view, double scale, const Vector3d& centre, std::size_t count) const;
  struct Typical {
    Vector3d median;
    Matrix3d variance;
  };
  Typical typical_innovation(const View& view, std::size_t count) const;

  std::map<std::string, View, std::less<>> views_;
};

// What gating did over a run: totals, and every view of a scene whose measurements failed the gate
// or whose noise scale was raised.
struct GatingSummary {
  struct View {
    std::string scene;
    std::string view;
    ViewNoiseScales::Report report;
  };
  std::size_t checked = 0;   // measurements checked by the gate (against a prediction or each other)
  std::size_t gated = 0;     // of which failed it
  std::size_t restarts = 0;  // tracks started again because every measurement failed the gate
  std::vector<View> views;

  // Adds a scene's views (those with a gated measurement or found disagreeing).
  void add(const std::string& scene, const ViewNoiseScales& scales);
};

}  // namespace stgf
