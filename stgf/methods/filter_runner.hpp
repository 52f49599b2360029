// SPDX-License-Identifier: Apache-2.0
#pragma once
// `ours` over a whole measurement list, fast: one SceneFilter per scene (core/scene_filter.hpp), and
// the scenes of a block of a few hundred advanced together: each runs until it needs forecasts, and
// the forecasts of every waiting scene come from a few batched passes of the predictor, instead of one
// small pass per scene and time. Scenes are independent, and Φ computes each object from its own
// graph alone (model/motion_inference.hpp), so the result is bitwise that of running each scene's
// filter alone.
//
// Delivery. Without arrival times (no row has one), each scene's rows are given step by step in time
// order (core/steps.hpp), and nothing can be late: the lag window plays no part. With arrival times
// (every row has one), each scene's rows are given in arrival order (ties: time, then list order),
// rows with the same arrival together; a row's estimate is what the filter knew of its object at its
// time when the row was first processed (the answer a live user would have had), and rows later than
// the lag window are counted and left out or stop the run (FilterOptions::late, LateMeasurementError
// with the row's index as id).
//
// In parts. The scenes of a list are advanced kScenesPerFilterBlock at a time. Φ computes each object
// from its own graph alone (model/motion_inference.hpp), so a long list given in parts of whole
// scenes, of any sizes, gets the estimates of one call over the whole list, bit for bit: `stgf run`
// reads its file in parts of kScenesPerFilterBlock scenes (DESIGN §3.8).

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "stgf/core/common_translation_scale.hpp"
#include "stgf/core/process_noise_pool.hpp"
#include "stgf/core/registration_scale_pool.hpp"
#include "stgf/core/scene_filter.hpp"
#include "stgf/core/sensor_motion.hpp"

namespace stgf {

// Scenes advanced together: their forecasts are asked for together (a predictor that batches would
// amortise its passes over them; Φ's Eigen pass costs the same either way), few enough that their
// filters' state and the rows of a file read in parts stay small (`stgf run` on the mpl test split:
// 16 scenes hold about 6,000 rows).
inline constexpr std::size_t kScenesPerFilterBlock = 16;

struct FilterRun {
  std::vector<Gaussian3> estimates;  // one per measurement row, in order
  // What was predicted for each row before its update (when asked for).
  std::vector<std::optional<TrackPrediction>> predictions;
  std::size_t restarted_tracks = 0;    // summed over the scenes
  std::size_t coasting_predictions = 0;  // by constant velocity beyond the model's horizon (ObjectTrack::coasts_to)
  std::size_t late_measurements = 0;   // too late for the lag window
  std::size_t late_rows = 0;           // late rows fused in their place in time
  std::size_t rewinds = 0;             // times a scene went back for them
  GatingSummary gating;                // what the gate did (its restarts are in restarted_tracks too)
  // The registration prior's learned scales of the scenes of fixed sensors and of moving ones; empty
  // without a registration prior or with adaptation off.
  PerSensorMotion<LearnedRegistrationScales> registration_prior_scales;
  MotionChoiceSummary motion_choice;   // which motion the scenes followed (motion_choice.hpp)
  std::size_t scenes = 0;              // in the list
};

// What the scenes of a run learn together, in list order (`first_scene` of run_spatiotemporal_graph_filter
// is the place of the list's first scene in the whole run); null: each scene learns alone.
struct ScenePools {
  // The registration prior's scales (registration_scale_pool.hpp), one pool for the scenes of fixed
  // sensors and one for those whose sensors move (sensor_motion.hpp): each scene starts from its
  // pool's evidence for its place in the list (or, the translations lowered only, from its estimate) and adds
  // its own.
  PerSensorMotion<RegistrationScalePool*> registration;
  // Q's scales (process_noise_pool.hpp): each scene starts them from the pool's evidence for its place
  // in the list (below 1 too, or held at 1 and above: ProcessNoisePool::below_one), learns on from its
  // own innovations, and adds what they said.
  ProcessNoisePool* process_noise = nullptr;
  // The size of the offset common to a scene's views, from the scenes before it (one for fixed sensors,
  // one for moving ones: common_translation_scale.hpp): where a scene's own is lower, the covariances it
  // reports carry the difference. With the registration's scales learned (`adapt_registration_prior`).
  PerSensorMotion<CommonTranslationScale*> common_translation;
};

// Throws std::invalid_argument when some rows have an arrival time and others not.
FilterRun run_spatiotemporal_graph_filter(const MotionPredictor& predictor, const FilterOptions& options,
                                          std::span<const Measurement> measurements, bool keep_predictions = false,
                                          ScenePools pools = {}, std::size_t first_scene = 0);

}  // namespace stgf
