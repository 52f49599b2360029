// SPDX-License-Identifier: Apache-2.0
#pragma once
// The motion graphs of a measurement list (DESIGN §1.1, §2): what Φ trains and runs on, built from a
// benchmark split without LibTorch.
//
// ── Steps and times ──────────────────────────────────────────────────────────────────────────────
// Rows are grouped into scenes and steps by group_into_scenes (core/steps.hpp): scenes in order of
// first appearance, steps in increasing time, a step's time τ_s = the earliest time of its rows.
// Every time in a graph is a step time: the target time of a graph at step s is τ_s, and a history
// entry from step s' < s has time τ_{s'}. Steps are more than kSameStepTolerance apart, so history
// times strictly increase and all precede the target time. Gaps are kept: an object missed at some
// steps has history entries only at the steps where it was seen, with those steps' real times.
//
// ── Sources ──────────────────────────────────────────────────────────────────────────────────────
// kRawView (`sttp`): one graph per (scene, view v, step s ≥ 1 of the scene) holding every object o
//   that v measured at s and at some earlier step. The history of o is v's own measurements of o at
//   the last min(H, n) of the n earlier steps where v measured it: positions z, times τ, and (where
//   covariances are reported) R.
// kFused (`ours-l`, training `ours`): at every step s where any view measured object o, o's fused
//   position is the information-weighted mean (the `wls` estimate, information_weighted_mean in
//   core/multi_view_update.hpp) of all of that step's measurements of o:
//       P_s = (Σ_u R_u⁻¹)⁻¹,   x_s = P_s Σ_u R_u⁻¹ z_u.
//   One graph per (scene, step s ≥ 1), view "", holding every object measured by any view at s and
//   at some earlier step; its history is (x, τ) at the last min(H, n) of its n earlier fused steps,
//   with covariance P.
// H = history_length ≥ 1. A step with no such object gets no graph.
// Long gaps (make_motion_graph_set's `max_gap`): a track whose last entry is more than max_gap before
// the step starts again there, empty, as if the object were new (a predictor's horizon, see
// motion_predictor.hpp); the default, infinity, keeps every track whole.
//
// ── Order (deterministic: a function of the row order only) ──────────────────────────────────────
// Graphs by scene (first appearance), then step time, then view (for kRawView: in the order in which
// the views first appear among the step's rows). Objects within a graph in the order in which they
// first appear among the step's rows. Histories oldest first.
//
// ── Rows and graphs ──────────────────────────────────────────────────────────────────────────────
// MotionGraphSet::predictor_of_row maps every measurement row k to the graph object whose prediction
// is compared with (kRawView) or fused into (kFused) that row: for row k of view v, object o at step s,
// the object o of the graph of (scene, v, s) for kRawView or of (scene, s) for kFused. It is nullopt
// when o has no history there yet (v's first sighting of o for kRawView; the first step any view saw
// o for kFused). Under kFused all of a step's rows of one object map to the same graph object.
//
// ── Input errors ─────────────────────────────────────────────────────────────────────────────────
// std::invalid_argument when history_length < 1, or when one view has two rows of one object in one
// step (the measurement reader already rejects these; in-memory lists may not), naming the scene,
// the time, the view and the object.
//
// ── Cost ─────────────────────────────────────────────────────────────────────────────────────────
// O(N·H) time and memory for N rows: scene, view and object names are hashed once per row, the rest
// works on dense indices. Truth is looked up once per (scene, step, object) that a graph needs.

#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/io/truth_file.hpp"
#include "stgf/core/motion_graph.hpp"

namespace stgf {

// A graph with where its objects were at the target time, for training and validation: the truth,
// or (without truth) what was measured there.
struct TrainingGraph {
  MotionGraph graph;
  std::vector<Vector3d> targets;  // position at target_time, per object
  // The targets' covariances when they were measured (per object); empty for the truth (exact).
  std::vector<Matrix3d> target_covariances;
  // True positions at the history times (per object); empty without truth.
  std::vector<std::vector<Vector3d>> true_histories;
  std::vector<std::vector<Matrix3d>> history_covariances;  // covariance of each history position
};


enum class HistorySource {
  kRawView,  // one view's own measurements (sttp)
  kFused,    // the information-weighted mean of all views' measurements at each step (ours-l, ours)
};

// Where a graph object sits: graphs[graph].objects[object].
struct GraphObjectIndex {
  std::size_t graph = 0;
  std::size_t object = 0;
  friend bool operator==(const GraphObjectIndex&, const GraphObjectIndex&) = default;
};

// The graphs of a measurement list, for running Φ on it.
struct MotionGraphSet {
  std::vector<MotionGraph> graphs;
  // latest_covariances[g][i]: the covariance of the latest history position of graphs[g].objects[i]
  // (R of that measurement for kRawView, the fused P for kFused) — the P̂_prev from which the
  // prediction's covariance P = P̂_prev + Q starts (DESIGN §1.2).
  std::vector<std::vector<Matrix3d>> latest_covariances;
  // One entry per measurement row, in list order (see "Rows and graphs" above).
  std::vector<std::optional<GraphObjectIndex>> predictor_of_row;
  std::size_t restarted_tracks = 0;  // tracks that started again after a gap longer than max_gap
};

MotionGraphSet make_motion_graph_set(std::span<const Measurement> measurements, HistorySource source,
                                     int history_length,
                                     double max_gap = std::numeric_limits<double>::infinity());

// The graphs alone (make_motion_graph_set(...).graphs).
std::vector<MotionGraph> make_motion_graphs(std::span<const Measurement> measurements, HistorySource source,
                                            int history_length);

// The same graphs, in the same order, with what the objects truly did: for object i of a graph,
// targets[i] = truth at the graph's target time, true_histories[i][k] = truth at the history's k-th
// time, history_covariances[i][k] = the covariance of the k-th history position (R or the fused P).
// Truth is found with TruthIndex::find (± kSameStepTolerance). Throws std::invalid_argument naming the
// scene, time and object of a truth that a graph needs and `truth` lacks (objects in no graph
// need none), besides the input errors above.
std::vector<TrainingGraph> make_training_graphs(std::span<const Measurement> measurements,
                                                const TruthIndex& truth, HistorySource source,
                                                int history_length);

// The same graphs without truth: each object's target is what was measured of it at the target time —
// its fused position x_s (kFused) or the view's own measurement (kRawView) — with that position's
// covariance in target_covariances (P_s or R); true_histories stay empty. Φ learns to predict the
// next measurement: its noise is independent of the history's and has zero mean, so the prediction
// that minimises the expected error is the same as against the truth (for noise symmetric about
// zero, which a Gaussian is), at the price of noisier gradients.
std::vector<TrainingGraph> make_measured_training_graphs(std::span<const Measurement> measurements,
                                                         HistorySource source, int history_length);

}  // namespace stgf
