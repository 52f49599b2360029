// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/view_noise_scales.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "stgf/core/measurement_gate.hpp"

namespace stgf {

ViewNoiseScales::View& ViewNoiseScales::view_of(std::string_view name) {
  auto found = views_.find(name);
  if (found == views_.end()) found = views_.emplace(std::string(name), View{}).first;
  return found->second;
}

double ViewNoiseScales::scale(std::string_view view) const {
  const auto found = views_.find(view);
  return found == views_.end() ? 1.0 : found->second.scale;
}

double ViewNoiseScales::median_distance_squared(const View& view, double scale, const Vector3d& centre,
                                                std::size_t count) const {
  std::array<double, kWindow> values{};
  for (std::size_t i = 0; i < count; ++i) {
    const Sample& sample = view.recent(i);
    values[i] = scale == 1.0 && centre.isZero()
                    ? sample.distance_squared
                    : distance_squared(sample.innovation - centre, sample.prediction_covariance + scale * sample.noise);
  }
  auto middle = values.begin() + static_cast<std::ptrdiff_t>(count / 2);
  std::nth_element(values.begin(), middle, values.begin() + static_cast<std::ptrdiff_t>(count));
  return *middle;
}

ViewNoiseScales::Typical ViewNoiseScales::typical_innovation(const View& view, std::size_t count,
                                                               double scale) const {
  Typical typical{Vector3d::Zero(), Matrix3d::Zero()};
  for (int axis = 0; axis < 3; ++axis) {
    std::array<double, kWindow> values{};
    for (std::size_t i = 0; i < count; ++i) values[i] = view.recent(i).innovation(axis);
    auto middle = values.begin() + static_cast<std::ptrdiff_t>(count / 2);
    std::nth_element(values.begin(), middle, values.begin() + static_cast<std::ptrdiff_t>(count));
    typical.median(axis) = *middle;
  }
  const double n = static_cast<double>(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Sample& sample = view.recent(i);
    const Matrix3d independent = scale * sample.noise + sample.prediction_covariance - sample.recurring;
    typical.variance += (std::numbers::pi / 2.0 * independent / n + sample.recurring) / n;
  }
  return typical;
}

double ViewNoiseScales::solve_scale(const View& view, const Vector3d& centre, std::size_t count) const {
  // The smallest grid point 2^(j/2) whose median falls to m₃: bisection over j (m decreases in μ).
  int low = -1;   // below the grid: μ = 1
  int high = 40;  // the largest scale on the grid, taken when even it leaves the median above m₃
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    (median_distance_squared(view, std::exp2(0.5 * std::max(middle, 0)), centre, count) > kChiSquare3Median ? low
                                                                                                              : high) =
        middle;
  }
  return std::exp2(0.5 * std::max(high, 0));
}

bool ViewNoiseScales::shows_bias(const View& view, std::size_t count, double threshold) const {
  const Typical typical = typical_innovation(view, count, 1.0);
  if (!(distance_squared(typical.median, typical.variance) > threshold)) return false;
  // A median away from zero by more than the stated noise allows may only say that the noise is
  // larger than stated: judge it again with the noise scale that the samples' spread about their
  // median asks for.
  const double spread_scale = solve_scale(view, typical.median, count);
  return spread_scale == 1.0 ||
         distance_squared(typical.median, typical_innovation(view, count, spread_scale).variance) > threshold;
}

std::optional<ViewNoiseScales::Release> ViewNoiseScales::add(std::string_view name, double time, const Vector3d& innovation,
                                                             const Matrix3d& prediction_covariance,
                                                             const Matrix3d& recurring, const Matrix3d& noise,
                                                             bool separate_bias) {
  View& view = view_of(name);
  view.window[view.samples % kWindow] = Sample{time, innovation, prediction_covariance, recurring, noise,
                                               distance_squared(innovation, prediction_covariance + noise)};
  ++view.samples;
  if (view.samples < kJump) return std::nullopt;
  static const double kWindowThreshold = chi_square_3_quantile(0.999);
  static const double kJumpThreshold = chi_square_3_quantile(0.9999);
  const std::size_t available = std::min(view.samples, kWindow);
  const bool jump = shows_bias(view, kJump, kJumpThreshold);
  const bool judged = view.samples >= kRecent;  // enough samples for the window's tests
  const double median = judged ? median_distance_squared(view, 1.0, Vector3d::Zero(), available) : 0.0;
  const bool window_bias = judged && !jump && shows_bias(view, available, kWindowThreshold);
  const bool too_spread = median > kTrigger * kChiSquare3Median;
  if (!jump && !window_bias && !too_spread) {
    // None of the tests holds: a view found disagreeing before keeps its μ estimated from its
    // disagreements (back to 1 once it behaves); the others stay at 1.
    if (judged) view.scale = view.scale > 1.0 ? solve_scale(view, Vector3d::Zero(), available) : 1.0;
    return std::nullopt;
  }
  if (std::isnan(view.report.first_flagged_time)) {
    view.report.first_flagged_time = time;
    view.report.flagging_median = median;
  }
  if (!(separate_bias && (jump || window_bias))) {
    // No offset to move: the disagreements are all noise.
    view.scale = solve_scale(view, Vector3d::Zero(), available);
    view.report.largest_scale = std::max(view.report.largest_scale, view.scale);
    return std::nullopt;
  }
  // The offset moved: by the window's mean since now (a bias over the window; μ from the window
  // centred on it), or by the median of the last kJump since the first of them (a jump; μ stays,
  // what follows judges the noise).
  Vector3d centre = Vector3d::Zero();
  double since = time;
  if (window_bias) {
    for (std::size_t i = 0; i < available; ++i) centre += view.recent(i).innovation / static_cast<double>(available);
    view.scale = solve_scale(view, centre, available);
  } else {
    centre = typical_innovation(view, kJump, 1.0).median;
    since = view.recent(kJump - 1).time;
  }
  view.report.largest_scale = std::max(view.report.largest_scale, view.scale);
  restart_after_release(name, time);
  return Release{Matrix3d(centre * centre.transpose()), since};
}

void ViewNoiseScales::restart_after_release(std::string_view name, double time) {
  View& view = view_of(name);
  view.samples = 0;
  ++view.report.offset_releases;
  if (std::isnan(view.report.first_flagged_time)) view.report.first_flagged_time = time;
}

void ViewNoiseScales::presume(std::string_view name, double scale) {
  View& view = view_of(name);
  view.scale = std::max(view.scale, scale);
}

void ViewNoiseScales::count(std::string_view name, bool passed) {
  Report& report = view_of(name).report;
  ++report.checked;
  if (!passed) ++report.gated;
}

std::map<std::string, ViewNoiseScales::Report> ViewNoiseScales::reports() const {
  std::map<std::string, Report> result;
  for (const auto& [name, view] : views_) result.emplace(name, view.report);
  return result;
}

void GatingSummary::add(const std::string& scene, const ViewNoiseScales& scales) {
  for (const auto& [view, report] : scales.reports()) {
    checked += report.checked;
    gated += report.gated;
    down_weighted += report.down_weighted;
    if (report.gated > 0 || report.down_weighted > 0 || !std::isnan(report.first_flagged_time)) {
      views.push_back(View{scene, view, report});
    }
  }
}

void GatingSummary::add(const GatingSummary& later) {
  checked += later.checked;
  gated += later.gated;
  down_weighted += later.down_weighted;
  restarts += later.restarts;
  refilters += later.refilters;
  views.insert(views.end(), later.views.begin(), later.views.end());
}

}  // namespace stgf
