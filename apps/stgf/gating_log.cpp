// SPDX-License-Identifier: Apache-2.0
#include "gating_log.hpp"

#include <cmath>
#include <map>

#include <spdlog/spdlog.h>

#include "stgf/core/cross_view_weights.hpp"

namespace stgf::cli {
namespace {

// The views' counts as "name count, name count, …", largest first.
std::string by_view(const std::map<std::string, std::size_t>& counts) {
  std::vector<std::pair<std::size_t, std::string>> order;
  for (const auto& [view, count] : counts) {
    if (count > 0) order.emplace_back(count, view);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string text;
  for (const auto& [count, view] : order) text += (text.empty() ? "" : ", ") + view + " " + std::to_string(count);
  return text;
}

}  // namespace

void log_gating(const std::string& method, const GateOptions& gate, const GatingSummary& summary) {
  std::map<std::string, std::size_t> gated;
  std::map<std::string, std::size_t> scaled;
  std::map<std::string, std::size_t> down_weighted;
  for (const GatingSummary::View& view : summary.views) {
    gated[view.view] += view.report.gated;
    down_weighted[view.view] += view.report.down_weighted;
    if (!std::isnan(view.report.first_flagged_time)) ++scaled[view.view];
  }
  if (summary.down_weighted > 0) {
    spdlog::info("{}: {} measurement(s) lay far from the other views' measurements of their object at their time "
                 "(d² > {:.2f}) and were fused with their noise scaled up to that distance; by view: {}",
                 method, summary.down_weighted, CrossViewWeights::threshold(), by_view(down_weighted));
  }
  if (!gate.enabled) return;
  const MeasurementGate measurement_gate(gate);
  if (summary.gated > 0) {
    spdlog::info("{}: {} of {} measurements checked ({:.3f} %) failed the χ² gate at {} (d² > {:.2f}) and were not "
                 "fused; by view: {}",
                 method, summary.gated, summary.checked, 100.0 * static_cast<double>(summary.gated) /
                                                            static_cast<double>(summary.checked),
                 gate.probability, measurement_gate.threshold(), by_view(gated));
  }
  constexpr std::size_t kShown = 5;
  std::size_t shown = 0;
  std::size_t scenes = 0;
  for (const GatingSummary::View& view : summary.views) {
    if (std::isnan(view.report.first_flagged_time)) continue;
    ++scenes;
    if (shown++ >= kShown) continue;
    spdlog::warn("{}: scene {}: view '{}' disagrees with the other views from t = {:.3f} s (median d² {:.1f} over "
                 "its last {} measurements, expected {:.2f}): its noise is taken as up to {:.0f} times what it states{}",
                 method, view.scene, view.view, view.report.first_flagged_time, view.report.flagging_median,
                 ViewNoiseScales::kWindow, ViewNoiseScales::kChiSquare3Median, view.report.largest_scale,
                 view.report.offset_releases > 0
                     ? ", and its offset was re-opened " + std::to_string(view.report.offset_releases) + " time(s)"
                     : std::string());
  }
  if (scenes > kShown) {
    spdlog::warn("{}: ... {} (scene, view) pairs in all were found disagreeing with the other views; by view: {}", method, scenes,
                 by_view(scaled));
  }
  if (summary.restarts > 0) {
    spdlog::info("{}: {} track(s) started again because the measurements of the object disagreed with the track's "
                 "prediction (more of them agreeing with each other than with it, or one view for several times)",
                 method, summary.restarts);
  }
  if (summary.refilters > 0) {
    spdlog::info("{}: went back over the lag window {} time(s) to fuse again what came since with what was learnt "
                 "of a view (its noise understated, or its offset shifted since then); rows already estimated keep "
                 "their estimates",
                 method, summary.refilters);
  }
}

}  // namespace stgf::cli
