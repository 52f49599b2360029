#pragma once
// `ours` over a whole measurement list, fast: one SpatiotemporalGraphFilter per scene, and the
// scenes advanced together in blocks of a few hundred, step k of every scene of a block in one round, so that the predictor sees all of a
// round's graphs in a few batched passes instead of one small pass per scene and step. Scenes are
// independent, so the result is that of running each scene's filter alone (run_localizer), up to
// the floating-point effect of batch size on the predictor's matrix products (about 1e-7 m with
// Φ in single precision; exact for predictors that treat graphs one by one).

#include <optional>
#include <span>
#include <vector>

#include "stgf/learn/spatiotemporal_graph_filter.hpp"

namespace stgf {

struct FilterRun {
  std::vector<Gaussian3> estimates;  // one per measurement row, in order
  // What was predicted for each row before its update (when asked for; see
  // SpatiotemporalGraphFilter::last_predictions).
  std::vector<std::optional<SpatiotemporalGraphFilter::Prediction>> predictions;
  std::size_t restarted_tracks = 0;  // summed over the scenes
};

FilterRun run_spatiotemporal_graph_filter(const MotionPredictor& predictor,
                                          const SpatiotemporalGraphFilter::Options& options,
                                          std::span<const Measurement> measurements, bool keep_predictions = false);

}  // namespace stgf
