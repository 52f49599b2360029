// SPDX-License-Identifier: Apache-2.0
#pragma once
// A view that keeps disagreeing with the other views — a camera knocked out of calibration, a detector
// whose covariance understates its error — would otherwise spoil every object it sees: the χ² gate
// (measurement_gate.hpp) keeps out its grossest errors, but what passes comes with an R that claims
// far too much. So each view of a scene gets a noise scale μ_u ≥ 1 (its noise is taken as μ_u R; 1 for
// a view that behaves), and, when the filter estimates the views' offsets, a way to say that the
// view's offset has changed.
//
// Disagreements. Each measurement of u at a time when other views measure the same object and pass
// the gate gives ν = z_u − (the others' information-weighted mean), each corrected for its view's
// offset: ν ~ N(0, A + μ_u R), A the rest of its covariance. Part of A recurs from one disagreement of
// u to the next — the offsets' errors (with offsets estimated jointly, exactly the covariance of the
// combination's offset errors: JointRegistration::offsets_covariance, in which the offset common to
// the views cancels) — and the rest (the others' noise) averages out like R; the caller gives both.
// The view's last kWindow disagreements are kept. With
//     d²_k(μ) = ν_kᵀ (A_k + μ R_k)⁻¹ ν_k,   m(μ) = median_k d²_k(μ),   m₃ = 2.366 the median of χ²(3),
// and, for a bias test over the last n, ν̃ their coordinate-wise median (gross outliers do not move
// it) and V(μ) = mean_k (π/2 (μR_k + A_k − A_k,recurring)/n + A_k,recurring) its variance, the view is
// found disagreeing when any of these holds:
//   - a jump: over its last kJump = 3 disagreements, ν̃ᵀ V(μ)⁻¹ ν̃ > the χ²(3) quantile 0.9999;
//   - from kRecent = 5 disagreements on, m(1) > kTrigger · m₃ = 5.9: its typical measurement lies
//     where an honest one lands 12 % of the time (for kWindow = 15 honest ones, probability about
//     10⁻⁴);
//   - from kRecent on, a bias over the window: the same test as a jump's over all kept disagreements,
//     at the quantile 0.999: a bias that is small against one measurement's noise but persists.
// The bias tests are judged twice: with μ = 1, and with the μ that the disagreements' spread about ν̃
// asks for, so that a view whose noise is understated (a wide spread) is not taken for one whose
// offset moved.
// Then
//   - with `separate_bias` (the filter estimates offsets, joint_registration.hpp), a jump or bias
//     returns a Release: ν̄ ν̄ᵀ (ν̄ = ν̃ of the jump's three, or the window's mean), by which the caller
//     widens the view's translation offset covariance (its calibration has changed: a jump becomes a
//     new offset that the other views teach, rather than noise that only down-weights the view), and
//     when the shift began (the first of the jump's three; now for a bias over the window); the kept
//     disagreements are dropped, so the next judgement sees only what came after. A bias over the
//     window also re-solves μ on its disagreements centred on ν̄; a jump leaves μ to what follows;
//   - otherwise (a spread too wide, or no offsets) μ_u is solved on the disagreements themselves.
// Once found disagreeing, a view keeps its μ re-solved from every new disagreement, back to 1 when it
// behaves; a view never found disagreeing keeps μ = 1.
// μ_u is the smallest grid point 2^(j/2), j = 0 … 40, whose median m(μ_u) of the (centred) samples is
// at most m₃ (m decreases in μ): what makes the view's typical disagreement an honest one.
// SceneFilter goes back over its lag window with a large μ or a jump (scene_filter.hpp).
//
// What the filter reports for each view: its largest μ, when it was first found disagreeing (with
// m(1) then), how often its offset was widened, and how many of its measurements the gate checked and
// left out.

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
  static constexpr std::size_t kJump = 3;
  static constexpr double kTrigger = 2.5;
  static constexpr double kChiSquare3Median = 2.365973884375338;

  // μ of the view (1 for an unknown one).
  double scale(std::string_view view) const;

  // Adds a disagreement of a measurement of `view` at `time` with the other views: ν, the others'
  // share A of its covariance and the part of A that recurs, and the stated R. Updates μ of the view.
  // With `separate_bias`, returns the release of the view's offset when it has shifted (above).
  struct Release {
    Matrix3d covariance;  // ν̄ ν̄ᵀ
    double since;         // when the shift began: the time of the earliest disagreement that shows it
  };
  std::optional<Release> add(std::string_view view, double time, const Vector3d& innovation,
                              const Matrix3d& prediction_covariance, const Matrix3d& recurring, const Matrix3d& noise,
                              bool separate_bias = false);
  // The view's offset was widened at `time` (a release that add() returned, applied again by a filter
  // that went back to before it): its window starts afresh, and the release is reported.
  void restart_after_release(std::string_view view, double time);
  // Takes μ of `view` as at least `scale` until its disagreements judge it again (a filter that goes
  // back in time with what it has learnt since).
  void presume(std::string_view view, double scale);
  // Counts a measurement of `view` checked by the gate, and whether it passed.
  void count(std::string_view view, bool passed);
  // Counts a measurement of `view` fused with its noise scaled up by the other views' disagreement
  // (cross_view_weights.hpp).
  void count_down_weighted(std::string_view view) { ++view_of(view).report.down_weighted; }

  struct Report {
    double largest_scale = 1.0;
    // When it was first found disagreeing (NaN: never), with m(1) then.
    double first_flagged_time = std::numeric_limits<double>::quiet_NaN();
    double flagging_median = 0.0;
    std::size_t offset_releases = 0;  // times its offset was widened (separate_bias)
    std::size_t checked = 0;      // measurements checked by the gate
    std::size_t gated = 0;        // of which failed it
    std::size_t down_weighted = 0;  // measurements the other views placed far off (cross_view_weights.hpp)
  };
  // Per view that has been added or counted, in name order.
  std::map<std::string, Report> reports() const;

 private:
  struct Sample {
    double time;
    Vector3d innovation;
    Matrix3d prediction_covariance;
    Matrix3d recurring;  // the part of it the view's disagreements share
    Matrix3d noise;
    double distance_squared;  // d²(1)
  };
  struct View {
    std::array<Sample, kWindow> window;
    std::size_t samples = 0;  // added so far (the window holds the last kWindow)
    double scale = 1.0;
    Report report;
    // The i-th latest sample (0: the latest; i < min(samples, kWindow)).
    const Sample& recent(std::size_t i) const { return window[(samples - 1 - i) % kWindow]; }
  };
  // Over the last `count` samples: the median of d²(μ) of ν − centre, and the coordinate-wise median
  // of ν with its variance V.
  View& view_of(std::string_view name);  // added if new
  double median_distance_squared(const View& view, double scale, const Vector3d& centre, std::size_t count) const;
  struct Typical {
    Vector3d median;
    Matrix3d variance;
  };
  // With the view's noise taken as `scale` R in V.
  Typical typical_innovation(const View& view, std::size_t count, double scale) const;
  // The smallest grid point μ whose median d²(μ) over the last `count` samples, less `centre`, is at
  // most m₃.
  double solve_scale(const View& view, const Vector3d& centre, std::size_t count) const;
  // Whether the last `count` samples' median lies away from zero beyond `threshold`, also with the
  // noise scale their spread about it asks for.
  bool shows_bias(const View& view, std::size_t count, double threshold) const;

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
  std::size_t down_weighted = 0;  // measurements fused with their noise scaled up by the other views
  std::size_t restarts = 0;  // tracks started again because every measurement failed the gate
  // times a scene's filter went back over its lag window: a view's noise found understated, or its
  // offset found shifted some events before (scene_filter.hpp)
  std::size_t refilters = 0;
  std::vector<View> views;

  // Adds a scene's views (those with a gated or down-weighted measurement or found disagreeing).
  void add(const std::string& scene, const ViewNoiseScales& scales);
  // Adds the summary of later scenes (a file run in parts): the counts, and its views after these.
  void add(const GatingSummary& later);
};

}  // namespace stgf
