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
  std::array<double, kWindow> values;
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

ViewNoiseScales::Typical ViewNoiseScales::typical_innovation(const View& view, std::size_t count) const {
  Typical typical{Vector3d::Zero(), Matrix3d::Zero()};
  for (int axis = 0; axis < 3; ++axis) {
    std::array<double, kWindow> values;
    for (std::size_t i = 0; i < count; ++i) values[i] = view.recent(i).innovation(axis);
    auto middle = values.begin() + static_cast<std::ptrdiff_t>(count / 2);
    std::nth_element(values.begin(), middle, values.begin() + static_cast<std::ptrdiff_t>(count));
    typical.median(axis) = *middle;
  }
  const double n = static_cast<double>(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Sample& sample = view.recent(i);
    typical.variance += (std::numbers::pi / 2.0 * sample.noise / n + sample.prediction_covariance) / n;
  }
  return typical;
}

std::optional<Matrix3d> ViewNoiseScales::add(std::string_view name, double time, const Vector3d& innovation,
                                             const Matrix3d& prediction_covariance, const Matrix3d& noise,
                                             bool separate_bias) {
  View& view = view_of(name);
  view.window[view.samples % kWindow] =
      Sample{innovation, prediction_covariance, noise, distance_squared(innovation, prediction_covariance + noise)};
  ++view.samples;
  if (view.samples < kRecent) return std::nullopt;
  const std::size_t available = std::min(view.samples, kWindow);
  static const double kWindowThreshold = chi_square_3_quantile(0.999);
  static const double kRecentThreshold = chi_square_3_quantile(0.9999);
  const double median = median_distance_squared(view, 1.0, Vector3d::Zero(), available);
  const Typical recent = typical_innovation(view, kRecent);
  const Typical whole = typical_innovation(view, available);
  const bool recent_bias = distance_squared(recent.median, recent.variance) > kRecentThreshold;
  if (!recent_bias && !(median > kTrigger * kChiSquare3Median) &&
      !(distance_squared(whole.median, whole.variance) > kWindowThreshold)) {
    view.scale = 1.0;
    return std::nullopt;
  }
  // The samples μ is solved on, and the bias to centre them on and release: the recent ones and their
  // median when they show the bias (a jump), else the window and its mean.
  const std::size_t count = recent_bias ? kRecent : available;
  Vector3d centre = Vector3d::Zero();
  if (separate_bias && recent_bias) {
    centre = recent.median;
  } else if (separate_bias) {
    for (std::size_t i = 0; i < available; ++i) {
      centre += view.recent(i).innovation / static_cast<double>(available);
    }
  }
  // The smallest grid point 2^(j/2) whose median falls to m₃: bisection over j (m decreases in μ).
  int low = -1;   // below the grid: μ = 1
  int high = 40;  // the largest scale on the grid, taken when even it leaves the median above m₃
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    (median_distance_squared(view, std::exp2(0.5 * std::max(middle, 0)), centre, count) > kChiSquare3Median ? low
                                                                                                              : high) =
        middle;
  }
  view.scale = std::exp2(0.5 * std::max(high, 0));
  if (std::isnan(view.report.first_flagged_time)) {
    view.report.first_flagged_time = time;
    view.report.flagging_median = median;
  }
  view.report.largest_scale = std::max(view.report.largest_scale, view.scale);
  if (!separate_bias) return std::nullopt;
  view.samples = 0;
  ++view.report.offset_releases;
  return Matrix3d(centre * centre.transpose());
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
    if (report.gated > 0 || !std::isnan(report.first_flagged_time)) views.push_back(View{scene, view, report});
  }
}

void GatingSummary::add(const GatingSummary& later) {
  checked += later.checked;
  gated += later.gated;
  restarts += later.restarts;
  views.insert(views.end(), later.views.begin(), later.views.end());
}

}  // namespace stgf
