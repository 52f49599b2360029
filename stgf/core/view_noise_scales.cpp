// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/view_noise_scales.hpp"

#include <algorithm>
#include <cmath>

#include "stgf/core/measurement_gate.hpp"

namespace stgf {

double ViewNoiseScales::scale(std::string_view view) const {
  const auto found = views_.find(view);
  return found == views_.end() ? 1.0 : found->second.scale;
}

double ViewNoiseScales::median_distance_squared(const View& view, double scale) const {
  std::array<double, kWindow> values;
  for (std::size_t k = 0; k < kWindow; ++k) {
    const Sample& sample = view.window[k];
    values[k] = scale == 1.0 ? sample.distance_squared
                             : distance_squared(sample.innovation, sample.prediction_covariance + scale * sample.noise);
  }
  auto middle = values.begin() + kWindow / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

void ViewNoiseScales::add(std::string_view name, double time, const Vector3d& innovation,
                          const Matrix3d& prediction_covariance, const Matrix3d& noise) {
  auto found = views_.find(name);
  if (found == views_.end()) found = views_.emplace(std::string(name), View{}).first;
  View& view = found->second;
  view.window[view.samples % kWindow] =
      Sample{innovation, prediction_covariance, noise, distance_squared(innovation, prediction_covariance + noise)};
  ++view.samples;
  if (view.samples < kWindow) return;
  const double median = median_distance_squared(view, 1.0);
  if (!(median > kTrigger * kChiSquare3Median)) {
    view.scale = 1.0;
    return;
  }
  // The smallest grid point 2^(j/2) whose median falls to m₃: bisection over j (m decreases in μ).
  int low = 0;    // m(2^(low/2)) > m₃
  int high = 40;  // the largest scale on the grid, taken when even it leaves the median above m₃
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    (median_distance_squared(view, std::exp2(0.5 * middle)) > kChiSquare3Median ? low : high) = middle;
  }
  view.scale = std::exp2(0.5 * high);
  if (std::isnan(view.report.first_raised_time)) {
    view.report.first_raised_time = time;
    view.report.raising_median = median;
  }
  view.report.largest_scale = std::max(view.report.largest_scale, view.scale);
}

void ViewNoiseScales::count(std::string_view name, bool passed) {
  auto found = views_.find(name);
  if (found == views_.end()) found = views_.emplace(std::string(name), View{}).first;
  ++found->second.report.checked;
  if (!passed) ++found->second.report.gated;
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
    if (report.gated > 0 || report.largest_scale > 1.0) views.push_back(View{scene, view, report});
  }
}

}  // namespace stgf
