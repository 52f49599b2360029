// SPDX-License-Identifier: Apache-2.0
#pragma once
// `sttp` (DESIGN §2): Φ on one view's own measurement history (single-view learned prediction, like
// STGAT), prediction only. Each measured row (scene, t, view, object) gets the prediction of its
// object at t made from that view's measurements before t, with covariance P = R_last + Q(Δt)
// (DESIGN §1.2), R_last the covariance of the latest history position. With a single history position
// Φ has no velocity to go on, so (s_v Δt)² I is added (s_v: the model's typical speed). With no history
// at all (the view's first sighting) there is nothing to predict from, and the row gets its own
// measurement. A track unseen for longer than the model's prediction horizon starts again the same way.
// (`ours-l`, the fused-history prediction, is the spatiotemporal graph filter's own prediction before
// each update: methods/filter_runner.hpp with predictions kept.)

#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/learn/motion_graphs.hpp"
#include "stgf/learn/motion_model.hpp"

namespace stgf {

// One estimate per measurement row, in order. `restarted_tracks` (if given) receives how many tracks
// started again after a gap longer than the model's horizon.
std::vector<Gaussian3> run_single_view_prediction(const MotionModel& model,
                                          std::span<const Measurement> measurements,
                                          std::size_t* restarted_tracks = nullptr);

}  // namespace stgf
