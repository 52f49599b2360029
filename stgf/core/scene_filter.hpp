// SPDX-License-Identifier: Apache-2.0
#pragma once
// The spatiotemporal graph filter of one scene (DESIGN §1, paper Algorithm 1) in continuous time,
// for views on their own clocks whose measurements arrive late and out of order. LibTorch-free: the
// motion model plugs in behind MotionPredictor, and it is asked for forecasts through a request /
// provide protocol, so that a caller can batch the requests of many scenes into one pass of the
// model (filter_runner.hpp) or answer them at once (spatiotemporal_graph_filter.hpp).
//
// ── Tracks ───────────────────────────────────────────────────────────────────────────────────────
// kPerObject (default): one track per object (object_track.hpp). Every measurement of the object,
//   from any view, updates it, and each measurement's estimate is the object's fused estimate at the
//   measurement's time. Φ reads one graph per scene: every live track.
// kPerView (the paper's decentralised form): view v keeps its own track of each object it measures,
//   updated at the times v measures it with every view's measurements of the object at that time.
//   The estimate of a measurement is its view's track. Φ reads one graph per view.
//
// ── Events ───────────────────────────────────────────────────────────────────────────────────────
// Measurements are grouped by time (within kSameStepTolerance) into events, processed in time order.
// Each track's measurements fall into frames (object_track.hpp): a frame opens at the first event
// that measures the object after the previous one closed, and closes once the frame window has passed
// (kPerObject: the predictor's history_spacing(); kPerView: any later time). Processing the event at t:
//   1. tracks of its objects not updated for longer than the predictor's horizon start again
//      (counted); every open frame the window has passed closes: the track's state becomes a history
//      position;
//   2. tracks about to be predicted need a forecast if their history changed since the last one: the
//      filter stops and requests one graph per track group (the scene, or the view) holding every live
//      track (history not empty, state within the horizon of t), and continues once provided;
//   3. per object, in name order, each of its tracks is predicted to t and updated with the event's
//      measurements of the object (the diffuse start P⁻¹ = 0 for an empty track: its first estimate is
//      the measurements alone); the fused estimate is the track's new state and each measurement's
//      estimate. With a registration prior, kPerObject estimates every position and every view's
//      offset jointly (joint_registration.hpp): each measurement updates both, so offsets are learnt
//      from views that never measure at the same time. Since through the offsets one object's
//      measurements move every position, this is done in three passes over the event's objects:
//      each is predicted and its measurements checked against the state before the event; each is
//      updated with those that passed (one update of the joint Gaussian per object); each reports
//      its position given all of the event. kPerView corrects the measurements by the
//      offsets of view_registration.hpp, combines them into one, and learns the offsets from the
//      event's cross-view differences afterwards; without a prior, both are the multi-view update;
//   4. per object whose frame opens here with a prediction from two or more history positions, the
//      innovation of its (first) measurement teaches the scale of Q (process_noise_scale.hpp) and
//      weighs the motion model's prediction against constant velocity's (motion_choice.hpp); from
//      the next event on, the scene's tracks follow the one the evidence favours. A coasting track's
//      innovation teaches the scale of the coasting Q alone (a λ of its own).
// On synchronised views at the model's rate a frame is one event, and this is DESIGN §1's filter.
// Within an event, rows are taken in (object, view) order, so the result does not depend on the order
// in which they were given.
//
// ── Faulty views (FilterOptions::gate; design §1.12) ──────────────────────────────────────────────
// In step 3, each object's measurements at the event are first checked by the χ² gate
// (measurement_gate.hpp) against the track's prediction, or against each other for a track without
// a two-position history; those that fail are not fused (Result::gated, counted per view). A track
// that the measurements agree is wrong starts again from them. Each measurement's disagreement with
// the other views' measurements of the object at that time teaches its view's noise scale μ (its R is
// taken as μR from then on) and, jointly, may re-open the view's offset (view_noise_scales.hpp).
// What the view already taught the tracks and the offsets would otherwise stay: so, with a lag window,
// the filter goes back (refilters()) — to the start of the window when a view's μ reaches
// kRefilterNoiseScale and twice the μ it went back with before (the view is presumed to have it from
// there on, until its disagreements judge again), and to the first of the disagreements that showed a
// jump, whose release of the view's offset is applied from then on. The event being processed when
// it is found comes again too; rows already reported keep their estimates. Each release of a view
// begins after the one before and each μ is twice the last, so going back ends. With the gate on,
// stgf run keeps the lag window's checkpoints even for rows in time order.
//
// ── Late and repeated measurements ──────────────────────────────────────────────────────────────
// Let t* be the latest event time processed. A new measurement at t > t* is queued. One at t ≤ t* but
// within the lag window (t ≥ t* − lag_window) is incorporated as if it had come in order: the filter
// goes back to a checkpoint at or before t (kept every kCheckpointSpacing seconds of event time, and as
// far back as the window needs), and re-processes every later event with the new measurement in its
// place in time order — one at the same time as an event joins it, so measurements of one time given in
// separate calls are one multi-view update. The result is exactly that of in-order delivery. Re-processed
// measurements do not report again: a measurement's estimate is what the filter knew of its object at
// its time when it was first processed, the answer a live user had. A measurement older than the
// window is too late: counted, and either left out (its estimate is its own combined measurement,
// corrected by the offsets as last processed, and it changes nothing) or reported by
// LateMeasurementError (LatePolicy). A caller that advances only until every row has reported
// (Advance::kUntilReported) lets the re-processing wait until a later row needs it: a burst of late
// rows in time order then goes back once, not once per row. lag_window = 0 keeps no
// checkpoints and treats any time at or before t* as too late.
//
// ── Cost ─────────────────────────────────────────────────────────────────────────────────────────
// Φ runs once per new history position of a track (about once per history spacing), whatever the
// number of views and clocks. A checkpoint copies the scene's state (tracks, registration); a late
// measurement costs the re-processing of the events since the checkpoint before it.

#include <cstddef>
#include <deque>
#include <map>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "stgf/core/joint_registration.hpp"
#include "stgf/core/measurement_gate.hpp"
#include "stgf/core/motion_choice.hpp"
#include "stgf/core/name_index.hpp"
#include "stgf/core/object_track.hpp"
#include "stgf/core/process_noise_pool.hpp"
#include "stgf/core/process_noise_scale.hpp"
#include "stgf/core/records.hpp"
#include "stgf/core/sensor_motion.hpp"
#include "stgf/core/view_noise_scales.hpp"
#include "stgf/core/view_registration.hpp"

namespace stgf {

enum class TrackMode { kPerObject, kPerView };
enum class LatePolicy { kLeaveOut, kStop };

struct FilterOptions {
  RegistrationPrior registration;           // the views' unstated offsets (zero: none)
  bool adapt_process_noise = true;          // scale Q online from the innovations (false: λ = 1)
  // Whether a scene whose innovations say constant velocity predicts it better than the motion model
  // follows constant velocity (motion_choice.hpp).
  MotionFallback motion_fallback = MotionFallback::kAuto;
  // kPerObject: learn the registration prior's scales κ_t, κ_n from the views' disagreements
  // (registration_prior_scale.hpp; false: κ = 1, the prior as given)
  bool adapt_registration_prior = true;
  // Whether the scene's sensors stand still or move, where known beforehand (filter_runner.cpp: from
  // all its rows); unset, from its rows so far (SensorMotionWatch: standing still until one has moved).
  // Where they are of the kind the registration prior was calibrated on, its shape is expected to hold
  // (the two-scale hypothesis a priori unlikely: registration_prior_scale.hpp).
  std::optional<SensorMotion> sensors;
  // What other scenes' disagreements said of the registration prior's scales: this scene's start, and
  // part of every estimate it makes of them (registration_scale_pool.hpp; none: its prior alone).
  std::shared_ptr<const std::vector<double>> registration_scale_start;
  // What other scenes' innovations said of Q's scales λ: this scene's start (process_noise_pool.hpp;
  // none: the prior alone).
  std::shared_ptr<const ProcessNoiseEvidence> process_noise_start;
  // Whether other scenes will start from this one's (its λ grids weighed whole, below 1 too).
  bool process_noise_pooled = false;
  // Started from process_noise_start, whether λ may fall below 1 (false: Q at least as calibrated).
  bool process_noise_below_one = true;
  TrackMode tracks = TrackMode::kPerObject;
  double lag_window = 1.0;                  // s: how late a measurement may come and still count
  // Each Result carries what its track predicted (false: none, for a caller that does not read
  // them: one allocation fewer per object and time).
  bool report_predictions = true;
  LatePolicy late = LatePolicy::kLeaveOut;  // what happens to one that comes later
  GateOptions gate;                         // the χ² gate and the views' noise scales (off)
  // kPerObject with offsets: a measurement that three or more views of its object at its time place far
  // off is fused with its noise scaled up (cross_view_weights.hpp; false: every one as its R states).
  bool cross_view_weights = true;
  // A forecast's covariance counts the error of the velocity it reads from the track's history
  // (object_track.hpp, Var(v̂); false: Q alone, as Q's calibration sees it).
  bool history_velocity_error = true;
};

// A view's noise scale at which the filter goes back over its lag window (design §1.12).
inline constexpr double kRefilterNoiseScale = 4.0;

// Event time between checkpoints (s).
inline constexpr double kCheckpointSpacing = 0.1;

// A measurement that came later than the lag window allows, under LatePolicy::kStop.
class LateMeasurementError : public std::runtime_error {
 public:
  LateMeasurementError(std::size_t id, const std::string& message) : std::runtime_error(message), id_(id) {}
  std::size_t id() const { return id_; }  // the id it was given with

 private:
  std::size_t id_;
};

class SceneFilter {
 public:
  // Throws std::invalid_argument for a negative or non-finite lag window. `predictor` must outlive the filter.
  SceneFilter(const MotionPredictor& predictor, const FilterOptions& options);

  // Takes measurements that arrived together (any times, views and objects of this scene), each with
  // an id the caller chooses; ids come back with the estimates. Does not process them: call advance().
  // Throws std::invalid_argument for a non-finite time or a (view, object, time) given twice, and
  // LateMeasurementError for a measurement too late under LatePolicy::kStop (nothing is taken then).
  // The filter keeps copies of what it needs.
  void receive(std::span<const Measurement* const> measurements, std::span<const std::size_t> ids);

  // How far advance() goes: through every queued event (the state then holds all that was received),
  // or only until every measurement received has its estimate. A late measurement sends the events
  // after it back to be processed again; the second way leaves those after the last measurement still
  // waiting for its estimate queued, so that the next late one, if no earlier, goes on from there
  // instead of going back again. Estimates are the same either way (but where the gate's
  // re-filtering goes back to the window's oldest checkpoint, which the two ways may have pruned
  // differently); the state's accessors below describe what has been processed, so a caller that
  // reads them, or has nothing more to give, advances through everything.
  enum class Advance { kThroughEverything, kUntilReported };
  // Processes queued events until done (true) or a forecast is needed (false: forecast_request()
  // lists the graphs; provide_forecasts() answers them, then advance() again, the same way). With the
  // history's velocity error, the list holds each graph a second time, its histories tilted, for the
  // forecasts' response to their slopes (slope_response.hpp): the predictor answers every graph alike.
  bool advance(Advance how = Advance::kThroughEverything);
  const std::vector<MotionGraph>& forecast_request() const { return request_; }
  void provide_forecasts(const std::vector<std::vector<MotionForecast>>& forecasts);

  // A measurement's result, once processed.
  struct Result {
    std::size_t id;
    Gaussian3 estimate;
    // What the track predicted for it before the update; none: diffuse start, or left out as too late.
    // Shared by the rows of one object and time (one copy per object, not per row).
    std::shared_ptr<const TrackPrediction> prediction;
    bool gated = false;  // it failed the gate and was not fused (`estimate` is from the rest)
  };
  // The results of measurements processed since the last call, in processing order, into `results`
  // (its contents replaced). The two vectors swap storage, so a caller that passes the same vector
  // every time allocates nothing in the steady state.
  void take_results(std::vector<Result>& results);

  std::size_t restarted_tracks() const { return state_.restarted_tracks; }
  // Predictions of tracks beyond the predictor's horizon, by constant velocity (ObjectTrack::coasts_to).
  std::size_t coasting_predictions() const { return state_.coasting_predictions; }
  std::size_t late_measurements() const { return late_measurements_; }  // too late for the window
  std::size_t rewinds() const { return rewinds_; }                      // went back for a late measurement
  // Rows fused in their place in time though a later time had been processed when they came (one
  // that joins a time already processed goes back too, but is not late).
  std::size_t late_rows() const { return late_rows_; }
  std::size_t refilters() const { return refilters_; }  // went back for a view's understated noise or jump
  // What the gate did (measurement_gate.hpp, view_noise_scales.hpp), and the tracks it restarted
  // (counted in restarted_tracks() too).
  const ViewNoiseScales& view_noise_scales() const { return state_.view_noise; }
  std::size_t gate_restarts() const { return state_.gate_restarts; }
  const Vector3d& process_noise_scales() const { return state_.process_noise_scale.scales(); }
  // λ per world axis of the coasting tracks' Q (design §1.9), taught by their own innovations.
  const Vector3d& coasting_noise_scales() const { return state_.coasting_scale.scales(); }
  // Which motion the tracks follow, and the evidence for it (motion_choice.hpp).
  const MotionChoice& motion_choice() const { return state_.motion_choice; }
  // The estimated registration offset of a view (t, δ; zero for a zero prior or an unknown view).
  OffsetVector registration_offset(std::string_view view) const;
  // κ̂_t, κ̂_n, the scales learned for the registration prior (1 when not learned), and whether they were: the
  // views' same-time disagreements reached RegistrationPriorScale::kFirstEstimateDimensions.
  RegistrationPriorScales registration_prior_scales() const { return state_.joint.prior_scales(); }
  bool registration_prior_scale_learned() const { return state_.joint.prior_scale_estimated(); }
  // The views with an offset in the registration (per-object mode).
  std::size_t registration_views() const { return state_.joint.view_count(); }
  // The scene's evidence on the scales, as a grid (registration_scale_pool.hpp); empty without any.
  std::vector<double> registration_likelihood_grid() const {
    return state_.joint.prior_scale_evidence() > 0.0 ? state_.joint.prior_scale_log_likelihood_grid() : std::vector<double>{};
  }
  // What the scene's innovations said of Q's scales, beyond options' process_noise_start.
  ProcessNoiseEvidence process_noise_evidence() const;
  // The latest event time processed (−∞ before any).
  double latest_time() const { return latest_time_; }

 private:
  struct Row {
    std::size_t id;
    Measurement measurement;
    bool reported = false;
  };
  // The rows of one track in an event: rows [first, next entry's first) of it.
  struct TrackRows {
    std::size_t first;
    ObjectTrack* track;
  };
  struct Event {
    double time;
    std::vector<Row> rows;  // (object, view) order
    bool started = false;   // step 1 done
    // Set by start(), valid until the state is next restored (which makes the event start again).
    std::vector<TrackRows> tracks;
  };
  using TrackKey = std::pair<std::string, std::string>;  // (view or "" in kPerObject, object)
  // Everything a checkpoint restores.
  struct State {
    std::map<TrackKey, ObjectTrack> tracks;
    ViewRegistration registration;  // kPerView
    JointRegistration joint;        // kPerObject, with a registration prior
    ProcessNoiseScale process_noise_scale;
    // λ of the coasting tracks' Q (their own curve: design §1.9), taught by their innovations alone.
    ProcessNoiseScale coasting_scale;
    MotionChoice motion_choice;
    ViewNoiseScales view_noise;
    // The shortest interval between two consecutive times of the scene: its frame interval, for a
    // track that has no interval of its own yet (ObjectTrack::unseen_limit).
    std::optional<double> last_time;
    double frame_interval = std::numeric_limits<double>::infinity();
    std::size_t restarted_tracks = 0;
    std::size_t coasting_predictions = 0;
    std::size_t gate_restarts = 0;
    std::vector<std::size_t> applied_releases;  // indices into scheduled_releases_
  };
  // A view's offset released from `time` on, found later (learn_view_noise).
  struct ScheduledRelease {
    std::string view;
    double time;
    Matrix3d covariance;
  };
  struct Checkpoint {
    double time;  // replays the events at or after this time
    State state;
  };

  TrackKey key_of(const Measurement& measurement) const;
  void insert(Event event);
  void rewind_to(double time);
  void start(Event& event);
  bool request_forecasts(const Event& event);
  void close_frames(double time);
  // The rows [first, end) of `event` that have not reported yet report `estimate` (and `prediction`).
  void report(Event& event, std::size_t first, std::size_t end, const Gaussian3& estimate,
              const std::optional<TrackPrediction>& prediction, const std::vector<bool>& gated);
  double noise_scale(std::string_view view) const;  // μ of the view; 1 without the gate
  // Whether this event's tracks follow constant velocity, and the λ of the motion they follow.
  bool follows_constant_velocity() const;
  const ProcessNoiseScale& followed_scale() const;
  // Whether step 4 takes samples at all; from a coasting track, only to adapt the coasting Q.
  bool learns_motion() const { return options_.adapt_process_noise || state_.motion_choice.compares(); }
  bool learns_from(bool coasting) const { return coasting ? options_.adapt_process_noise : learns_motion(); }
  // The error each motion's forecast takes from the velocity it reads off the track's history, from the
  // state to `time` (object_track.hpp, Var(v̂)): Φ's from the whole history, constant velocity's (and a
  // coasting track's) from its last two positions. Zero without history_velocity_error.
  struct VelocityErrors {
    Matrix3d learned = Matrix3d::Zero();
    Matrix3d fallback = Matrix3d::Zero();
  };
  VelocityErrors velocity_errors(const ObjectTrack& track, double time) const;
  // Step 4 for one sample of a track that learns_from(coasting): a coasting track's teaches the
  // coasting λ alone; any other's goes to learn_motion.
  void learn_sample(bool coasting, bool constant_velocity, const Vector3d& innovation, const Matrix3d& known_covariance,
                    const VelocityErrors& velocity_errors, const Matrix3d& process_noise,
                    const Vector3d& displacement_difference);
  // Step 4 for one sample: whether the event's predictions followed constant velocity (read at the
  // event's start: the choice may switch part-way through the event's samples), the innovation ν of
  // the motion followed, A = P̂_s + R, each motion's velocity error (A_m = A + its own: each is judged,
  // and its λ learnt, with what its own forecast knows it lacks), Q(τ) − Q(τ_s), and d_followed −
  // d_other, the two motions' displacements (the other's innovation is ν + that).
  void learn_motion(bool constant_velocity, const Vector3d& innovation, const Matrix3d& known_covariance,
                    const VelocityErrors& velocity_errors, const Matrix3d& process_noise,
                    const Vector3d& displacement_difference);
  // A release of a view's offset that add() found (view_noise_scales.hpp): applied now, or scheduled
  // from when the shift began and the filter set to go back there.
  void schedule_release(const std::string& view, const ViewNoiseScales::Release& release, double time);
  // Applies the scheduled releases due by `time` that the state has not applied.
  void apply_scheduled_releases(double time);
  // Each row's CrossViewWeights noise scale among those the gate passed (1 for the rest), counted per view.
  std::vector<double> cross_view_scales(std::span<const Row> rows, const MeasurementGate::Decision& decision);
  // Teaches the views' noise scales from one object's measurements at one time (`alone`: each
  // corrected for its view's offset, with its μ): each against the information-weighted mean of the
  // others that passed the gate — its disagreement with the other views, not with the track.
  void learn_view_noise(std::span<const Row> rows, const std::vector<Gaussian3>& alone, const std::vector<bool>& passes,
                        double time);
  bool joint() const { return options_.tracks == TrackMode::kPerObject && state_.joint.active(); }
  void process_joint(Event& event);
  void process(Event& event);
  void prune();
  void leave_out(const Measurement& measurement, std::size_t id);

  const MotionPredictor& predictor_;
  FilterOptions options_;
  MeasurementGate gate_;
  State state_;
  std::deque<Event> queue_;   // to process, time order
  std::deque<Event> log_;     // processed, time order, back to the oldest checkpoint
  std::deque<Checkpoint> checkpoints_;  // time order
  double latest_time_;   // of the last event processed (back to the log's end on going back)
  double reached_time_;  // the latest event time ever processed: what "too late" is measured from
  std::size_t unreported_ = 0;  // rows received (not left out) that have not reported yet
  // The tracks' graphs, then (with the history's velocity error) each again, tilted.
  std::vector<MotionGraph> request_;
  std::size_t request_graphs_ = 0;    // the tracks' graphs among request_
  std::vector<std::vector<Vector3d>> request_tilts_;  // of each graph's objects
  std::vector<std::vector<ObjectTrack*>> request_tracks_;  // of request_'s objects (the state is not changed meanwhile)
  // A closing frame's measurements, aligned (frame_alignment.hpp): lists kept for their room.
  struct AlignedFrame {
    std::vector<const Measurement*> measurements;
    std::vector<double> noise_scales;
    std::vector<Matrix3d> covariances;
  };
  // The registration scales' two-scale hypothesis's prior probability for the scene's sensors (FilterOptions::sensors).
  double registration_two_scales_probability() const;
  // Learns the registration prior's scales from the disagreements gathered (JointRegistration::adapt_prior_scale).
  void adapt_registration_prior_scale();

  AlignedFrame aligned_;
  std::vector<Result> results_;
  SensorMotionWatch sensor_motion_;  // the scene's sensors as its rows so far show (options_.sensors unset)
  std::size_t late_measurements_ = 0;
  std::size_t rewinds_ = 0;
  std::size_t late_rows_ = 0;
  NameIndex object_names_, view_names_;  // receive()'s ordering of rows by name
  // The gate's re-filtering (learn_view_noise): the noise scale each view is presumed to have from
  // the start of the window, whatever the state restored; whether to go back once the event is done;
  // how often it went back.
  std::map<std::string, double, std::less<>> presumed_noise_scales_;
  std::vector<ScheduledRelease> scheduled_releases_;
  bool refilter_ = false;
  double refilter_from_ = std::numeric_limits<double>::infinity();
  std::size_t refilters_ = 0;
};

}  // namespace stgf
