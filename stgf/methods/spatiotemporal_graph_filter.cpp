// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/spatiotemporal_graph_filter.hpp"

#include <numeric>
#include <optional>

namespace stgf {

std::vector<Gaussian3> SpatiotemporalGraphFilter::fuse(std::span<const Measurement> measurements) {
  std::vector<std::size_t> ids(measurements.size());
  std::iota(ids.begin(), ids.end(), std::size_t{0});
  std::vector<const Measurement*> pointers;
  pointers.reserve(measurements.size());
  for (const Measurement& measurement : measurements) pointers.push_back(&measurement);
  filter_.receive(pointers, ids);
  while (!filter_.advance()) filter_.provide_forecasts(predictor_.forecast(filter_.forecast_request()));
  std::vector<std::optional<Gaussian3>> estimates(measurements.size());
  last_predictions_.assign(measurements.size(), std::nullopt);
  filter_.take_results(results_);
  for (SceneFilter::Result& result : results_) {
    estimates[result.id] = result.estimate;
    last_predictions_[result.id] = result.prediction ? std::optional(*result.prediction) : std::nullopt;
  }
  std::vector<Gaussian3> ordered;
  ordered.reserve(estimates.size());
  for (const auto& estimate : estimates) {
    if (!estimate) throw std::logic_error("SpatiotemporalGraphFilter: a measurement got no estimate");
    ordered.push_back(*estimate);
  }
  return ordered;
}

std::vector<Gaussian3> SpatiotemporalGraphFilter::step(double time, std::span<const Measurement* const> measurements) {
  std::vector<Measurement> copies;
  copies.reserve(measurements.size());
  for (const Measurement* measurement : measurements) {
    copies.push_back(*measurement);
    copies.back().time = time;
  }
  return fuse(copies);
}

}  // namespace stgf
