// SPDX-License-Identifier: Apache-2.0
#pragma once
// `ours` as a streaming filter for one scene: the spatiotemporal graph filter (core/scene_filter.hpp)
// with its motion predictor answering forecast requests at once. Use it in a robot's loop, a ROS
// callback or a V2X receiver; stgf run uses the batched filter_runner.hpp over files.
//
// Rules (core/scene_filter.hpp has the details):
//   - fuse() takes measurements in any grouping — one at a time, one message per view, a whole step,
//     several times at once — in the order they arrived. Measurements of one time given in separate
//     calls are fused as one multi-view update; one older than the latest time fused (a late message)
//     is fused in its place in time, if within options.lag_window (default 1 s), by going back and
//     re-filtering; one older than that is counted and left out (its estimate is its own
//     measurement, corrected for its view's offset) or, with LatePolicy::kStop, throws
//     LateMeasurementError and changes nothing.
//   - It returns one estimate per measurement, in the given order: what the filter knows of the
//     measurement's object at the measurement's time once it is fused (kPerObject: the object's one
//     fused track; kPerView: the track of the measurement's view).
//   - Whether the scene's sensors stand still or move is taken from the measurements so far (standing
//     still until a view's sensor position has moved 0.5 m: sensor_motion.hpp), unless options.sensors
//     says; the registration prior's shape is expected to hold on sensors of the kind it was
//     calibrated on (registration_prior_scale.hpp). stgf run knows each scene's from all its rows.
//   - It is one scene: Q's scales λ and the registration prior's scales are learned from its own
//     measurements (FilterOptions' process_noise_start and registration_scale_start take what other
//     scenes said). stgf run pools them over a file's scenes (`process_noise_scale`,
//     `registration_prior_scale`), so its estimates of a file's later scenes can differ from this
//     filter's fed each scene alone.
//   - Times are seconds on one clock shared by the views (stamp each message with its measurement
//     time, not its arrival time); they need not be regular.
//   - Bad input throws std::invalid_argument and changes nothing: a non-finite time, a (view, object)
//     twice at one time. A Measurement's Gaussian3 was checked when it was made. The filter never
//     produces a NaN: every covariance it builds is a sum of validated ones and positive
//     semi-definite process noise, inverted by Cholesky.

#include <optional>
#include <span>
#include <vector>

#include "stgf/core/scene_filter.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

class SpatiotemporalGraphFilter final : public Localizer {
 public:
  using Options = FilterOptions;

  // `predictor` must outlive the filter.
  explicit SpatiotemporalGraphFilter(const MotionPredictor& predictor, const Options& options = Options{})
      : predictor_(predictor), filter_(predictor, options) {}

  // Fuses measurements that arrived together; one estimate each, in order.
  std::vector<Gaussian3> fuse(std::span<const Measurement> measurements);

  // Localizer: the measurements of one time (a step).
  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;

  // What the last fuse() or step() predicted for each of its measurements before the update: none for
  // a diffuse start (a new track) or a measurement left out as too late.
  const std::vector<std::optional<TrackPrediction>>& last_predictions() const { return last_predictions_; }
  std::size_t restarted_tracks() const { return filter_.restarted_tracks(); }
  std::size_t late_measurements() const { return filter_.late_measurements(); }
  std::size_t rewinds() const { return filter_.rewinds(); }  // went back in time for a late measurement
  std::size_t late_rows() const { return filter_.late_rows(); }  // SceneFilter::late_rows
  std::size_t refilters() const { return filter_.refilters(); }  // went back for what the gate learnt of a view
  const Vector3d& process_noise_scales() const { return filter_.process_noise_scales(); }
  const Vector3d& coasting_noise_scales() const { return filter_.coasting_noise_scales(); }
  // Which motion the tracks follow (core/motion_choice.hpp).
  const MotionChoice& motion_choice() const { return filter_.motion_choice(); }
  // What the χ² gate did (core/measurement_gate.hpp, core/view_noise_scales.hpp).
  const ViewNoiseScales& view_noise_scales() const { return filter_.view_noise_scales(); }
  std::size_t gate_restarts() const { return filter_.gate_restarts(); }
  // The estimated registration offset (t, δ, ε) of a view (view_registration.hpp).
  OffsetVector registration_offset(std::string_view view) const { return filter_.registration_offset(view); }
  // κ̂_t and κ̂_n, the registration prior's scales learned from the views' disagreements (1 until learned).
  RegistrationPriorScales registration_prior_scales() const { return filter_.registration_prior_scales(); }

 private:
  const MotionPredictor& predictor_;
  SceneFilter filter_;
  std::vector<std::optional<TrackPrediction>> last_predictions_;
  std::vector<SceneFilter::Result> results_;  // scratch for SceneFilter::take_results
};

}  // namespace stgf
