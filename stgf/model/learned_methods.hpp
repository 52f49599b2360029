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

#include <deque>
#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/model/motion_graphs.hpp"
#include "stgf/model/trained_motion_model.hpp"

namespace stgf {

// One estimate per measurement row, in order. `restarted_tracks` (if given) receives how many tracks
// started again after a gap longer than the model's horizon.
std::vector<Gaussian3> run_single_view_prediction(const TrainedMotionModel& model,
                                          std::span<const Measurement> measurements,
                                          std::size_t* restarted_tracks = nullptr);

// `sttp` over a list given in parts, each part whole scenes, the parts in list order (a file read a
// block of scenes at a time: `stgf run`, DESIGN §3.8), with the estimates run_single_view_prediction
// gives for the whole list, bit for bit. Φ's forward passes see other graphs' rows in their matrix
// products, so the passes must hold the same graphs: they take the graphs of all parts in order, in
// chunks of kGraphsPerForwardPass across the parts' boundaries, and a part's estimates are complete
// only once the pass holding its last graph has run (with a later part, or in finish()).
class SingleViewPredictionStream {
 public:
  static constexpr std::size_t kGraphsPerForwardPass = 4096;

  explicit SingleViewPredictionStream(const TrainedMotionModel& model);  // `model` must outlive the stream

  // Takes the next part; returns the estimates now complete, one per row, in list order, following
  // those returned before.
  std::vector<Gaussian3> add(std::span<const Measurement> rows);
  // The estimates of every row not returned yet (the last pass runs here).
  std::vector<Gaussian3> finish();
  // Tracks started again after a gap longer than the model's horizon, over the parts so far.
  std::size_t restarted_tracks() const { return restarted_tracks_; }

 private:
  struct Part {
    MotionGraphSet set;
    std::vector<Gaussian3> first_sightings;          // the rows without a prediction: their own measurement
    std::vector<std::vector<Vector3d>> predictions;  // per graph, as the passes reach it
  };

  // Runs the passes that are full (`to_the_end`: and the last, partial one).
  void run_passes(bool to_the_end);
  // Moves the estimates of the complete parts at the front into `estimates`.
  void take_complete(std::vector<Gaussian3>& estimates);

  const TrainedMotionModel& model_;
  std::deque<Part> parts_;     // parts whose estimates are not all out, in order
  std::size_t waiting_ = 0;    // graphs of those parts not through Φ yet
  std::size_t restarted_tracks_ = 0;
};

}  // namespace stgf
