#pragma once
// The learned methods of DESIGN §2 that predict without an update at t:
//   sttp    Φ on one view's own measurement history (single-view learned prediction, like STGAT);
//   ours-l  Φ on the fused history (the information-weighted mean of all views at each past step).
// Each measured row (scene, t, view, object) gets the prediction of its object at t made from the
// history before t, with covariance P = P_last + Q(Δt) (DESIGN §1.2), P_last the covariance of the
// latest history position (R for sttp, the fused P for ours-l). With a single history position Φ
// has no velocity to go on, so (s_v Δt)² I is added (s_v: the model's typical speed). With no
// history at all (the first sighting) there is nothing to predict from, and the row gets what the
// method would start from: its own measurement for sttp, the fused measurement of the step for ours-l.
// A track unseen for longer than the model's prediction horizon starts again the same way.

#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/learn/motion_graphs.hpp"
#include "stgf/learn/motion_model.hpp"

namespace stgf {

// sttp needs a model trained on raw histories, ours-l one trained on fused histories.
HistorySource history_source_of_method(const std::string& method);  // std::invalid_argument otherwise

// One estimate per measurement row, in order. `restarted_tracks` (if given) receives how many tracks
// started again after a gap longer than the model's horizon.
std::vector<Gaussian3> run_learned_method(const std::string& method, const MotionModel& model,
                                          std::span<const Measurement> measurements,
                                          std::size_t* restarted_tracks = nullptr);

}  // namespace stgf
