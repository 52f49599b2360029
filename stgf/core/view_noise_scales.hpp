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
// and the median of χ²(3) is m₃ = 2.366. The view is taken as faulty when m(1) > kTrigger · m₃: the
// typical measurement of the view lies where an honest one lands less than 2.4 % of the time — with
// kWindow = 15, a view that behaves (even with a model that understates S by half) crosses it with
// probability below 10⁻⁴ per window. Then μ_u is the smallest grid point 2^(j/2), j = 1 … 40, with
// m(μ_u) ≤ m₃ (m decreases in μ), and 1 again as soon as m(1) falls back below the trigger. The
// median ignores gross outliers (up to half the window), which the gate handles on their own, and it
// reacts to a step change (a jump) within half a window.
//
// A bias (a jump) shows as a large μ just the same: its measurements stop counting for much, and
// the objects only that view sees get a covariance as large as the disagreement.
//
// What the filter reports for each view: its largest μ, when it was first raised (with the median
// that raised it), and how many of its measurements failed the gate.

#include <array>
#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

class ViewNoiseScales {
 public:
  static constexpr std::size_t kWindow = 15;
  static constexpr double kTrigger = 2.5;
  static constexpr double kChiSquare3Median = 2.365973884375338;

  // μ of the view (1 for an unknown one).
  double scale(std::string_view view) const;

  // Adds an innovation of a measurement of `view` at `time`: ν, the prediction's share A of its
  // covariance, and the stated R. Updates μ of the view.
  void add(std::string_view view, double time, const Vector3d& innovation, const Matrix3d& prediction_covariance,
           const Matrix3d& noise);
  // Counts a measurement of `view` checked by the gate, and whether it passed.
  void count(std::string_view view, bool passed);

  struct Report {
    double largest_scale = 1.0;
    double first_raised_time = std::numeric_limits<double>::quiet_NaN();  // NaN: never raised
    double raising_median = 0.0;  // m(1) when it was first raised
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
    double distance_squared;  // d²(1)
  };
  struct View {
    std::array<Sample, kWindow> window;
    std::size_t samples = 0;  // added so far (the window holds the last kWindow)
    double scale = 1.0;
    Report report;
  };
  double median_distance_squared(const View& view, double scale) const;

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

  // Adds a scene's views (those with a gated measurement or a raised scale).
  void add(const std::string& scene, const ViewNoiseScales& scales);
};

}  // namespace stgf
