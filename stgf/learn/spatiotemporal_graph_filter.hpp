#pragma once
// `ours`: the spatiotemporal graph filter (DESIGN §1, paper Algorithm 1), as a streaming
// Localizer: feed it the measurements of one step at a time, get one estimate per measurement.
//
// Every view v keeps its own track of each object it has measured: the fused estimates
// (x̂, P̂) of its past steps (the paper's decentralised form). At a step with measurement set M_t:
//   1. Predict. For each view v and each object i that v measures at t and has tracked before, Φ
//      predicts x from v's track of i (and v's other tracked objects, the graph of view v); all
//      views' graphs go through Φ in one batched pass.
//      P = P̂_last + D Q(Δt) D  (+ (s Δt)² I when the track holds a single position: no velocity yet).
//      D = diag(√λ) (identity unless adapted) scales Q to the data at hand, per world axis: on data
//      unlike the training data (another frame rate, other motion) Φ can predict far worse than its
//      Q says, and the innovations show it; λ is estimated per scene from the innovations of earlier
//      steps (process_noise_scale.hpp), one per object and step (the views' innovations of an object
//      share its measurements).
//      An object v has not tracked before starts diffuse: P⁻¹ = 0, so its estimate is the step's
//      combined measurement (the information-weighted mean, or the registration-corrected one).
//      DESIGN §1.5's x = 0, P = 10⁴ I approximates this limit, but not in a world frame far from
//      its origin: at UTM-sized coordinates (4·10⁶ m) it pulls the first estimate metres towards 0.
//   2. Update. The multi-view update with the measurements of i by every view at t (shared):
//      S = P⁻¹ + Σ_u R_u⁻¹, P̂ = S⁻¹, x̂ = P̂ (P⁻¹ x + Σ_u R_u⁻¹ z_u).
//      With a registration prior (view_registration.hpp), the measurements are first corrected by
//      each view's estimated offset and combined into one measurement whose covariance keeps what is
//      left of the offsets' uncertainty; the update then takes that one. After the step, the offsets
//      learn from what the views disagreed on. With a zero prior this is exactly the plain update.
//   3. Feedback. (t, x̂, P̂) is appended to v's track of i (the last line of Algorithm 1), so the
//      next prediction runs on fused positions.
// A step with no measurement changes nothing; views may join or leave at any step; an object a
// view misses for a while keeps its older track, and Φ predicts across the gap from real times —
// up to the predictor's horizon (motion_predictor.hpp): an object a view has not seen for longer
// starts again in that view, diffuse, as if new (counted by restarted_tracks()).
// The estimate of row (v, i) is view v's fused estimate of i.

#include <deque>
#include <map>
#include <optional>
#include <string>

#include "stgf/core/process_noise_scale.hpp"
#include "stgf/core/view_registration.hpp"
#include "stgf/learn/motion_predictor.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

class SpatiotemporalGraphFilter final : public Localizer {
 public:
  struct Options {
    RegistrationPrior registration;   // the views' unstated offsets (zero: none)
    bool adapt_process_noise = true;  // scale Q online from the innovations (false: λ = 1)
  };

  // `predictor` must outlive the filter.
  explicit SpatiotemporalGraphFilter(const MotionPredictor& predictor) : SpatiotemporalGraphFilter(predictor, Options{}) {}
  SpatiotemporalGraphFilter(const MotionPredictor& predictor, const Options& options)
      : predictor_(predictor), registration_(options.registration), adapt_process_noise_(options.adapt_process_noise) {}

  // The current scales λ of Q, per world axis.
  const Vector3d& process_noise_scales() const { return process_noise_scale_.scales(); }
  // How many tracks started again after a gap longer than the predictor's horizon.
  std::size_t restarted_tracks() const { return restarted_tracks_; }

  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;

  // step() in two halves, so that the filters of many scenes can share one batched pass of the
  // predictor (filter_runner.hpp): prepare_step returns the graphs to predict (it may restart
  // tracks); complete_step takes the predictions of exactly those graphs and finishes the step.
  // step(t, M) = complete_step(predictor.predict(prepare_step(t, M))). The measurements must
  // outlive complete_step.
  std::vector<MotionGraph> prepare_step(double time, std::span<const Measurement* const> measurements);
  std::vector<Gaussian3> complete_step(const std::vector<std::vector<Vector3d>>& predicted);

  // What the last step predicted for each of its rows, before the update: nullopt for a row whose
  // view had no track of the object (diffuse start). For calibrating Q in the filter's own regime.
  struct Prediction {
    Vector3d mean;              // Φ's x
    Matrix3d last_covariance;   // P̂_last of the track
    double dt = 0.0;            // prediction interval
    std::size_t track_positions = 0;
  };
  const std::vector<std::optional<Prediction>>& last_predictions() const { return last_predictions_; }

 private:
  struct TrackPoint {
    double time;
    Gaussian3 estimate;
  };
  using Track = std::deque<TrackPoint>;  // oldest first, at most predictor_.history_positions()

  // What prepare_step leaves for complete_step.
  struct Pending {
    double time;
    std::vector<const Measurement*> rows;
    std::vector<std::optional<std::pair<std::size_t, std::size_t>>> prediction_of_row;  // (graph, object)
    std::vector<std::size_t> graph_sizes;
  };

  const MotionPredictor& predictor_;
  std::optional<Pending> pending_;
  ViewRegistration registration_;
  bool adapt_process_noise_;
  ProcessNoiseScale process_noise_scale_;
  std::vector<std::optional<Prediction>> last_predictions_;
  std::size_t restarted_tracks_ = 0;
  // view → object → track
  std::map<std::string, std::map<std::string, Track, std::less<>>, std::less<>> tracks_;
};

}  // namespace stgf
