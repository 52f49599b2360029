// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/scene_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string_view>

#include "stgf/core/cross_view_weights.hpp"
#include "stgf/core/multi_view_update.hpp"
#include "stgf/core/name_index.hpp"
#include "stgf/core/slope_response.hpp"

namespace stgf {
namespace {

std::string seconds(double time) {
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(6);
  text << time;
  return text.str();
}

bool row_before(const Measurement& a, const Measurement& b) {
  if (const int object = a.object.compare(b.object); object != 0) return object < 0;
  return a.view < b.view;
}

// Sorts the indices `order` of `measurements` by (object, view) name, stably (row_before's order).
// Returns the position in the sorted `order` of a row whose (object, view) repeats the row before
// it, if any.
std::optional<std::size_t> sort_by_object_and_view(std::span<std::size_t> order,
                                                   std::span<const Measurement* const> measurements,
                                                   NameIndex& objects, NameIndex& views) {
  std::vector<std::uint32_t> object_ids, view_ids;
  object_ids.reserve(order.size());
  view_ids.reserve(order.size());
  for (const std::size_t k : order) {
    object_ids.push_back(objects.id(measurements[k]->object));
    view_ids.push_back(views.id(measurements[k]->view));
  }
  objects.rank(object_ids);
  views.rank(view_ids);
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed;  // (object rank, view rank), row
  keyed.reserve(order.size());
  for (std::size_t r = 0; r < order.size(); ++r) {
    keyed.emplace_back(std::uint64_t{objects.rank_of(object_ids[r])} << 32 | views.rank_of(view_ids[r]), order[r]);
  }
  const auto by_key = [](const auto& a, const auto& b) { return a.first < b.first; };
  if (!std::is_sorted(keyed.begin(), keyed.end(), by_key)) std::stable_sort(keyed.begin(), keyed.end(), by_key);
  std::optional<std::size_t> repeated;
  for (std::size_t r = 0; r < keyed.size(); ++r) {
    order[r] = keyed[r].second;
    if (r > 0 && keyed[r].first == keyed[r - 1].first && !repeated) repeated = r;
  }
  return repeated;
}

// What is added to the covariance of a track started from measurements that conflict (no two agree,
// nothing to check them against; measurement_gate.hpp): with each of them equally likely the right one,
// the covariance of that mixture about their information-weighted mean m,
//     W = (1/n) Σ_k [C_k + (z_k − m)(z_k − m)ᵀ],
// which the fused covariance (smaller than every C_k) then only adds to.
Matrix3d conflict_spread(std::span<const Gaussian3> measurements) {
  const Vector3d mean = information_weighted_mean(measurements).mean();
  Matrix3d spread = Matrix3d::Zero();
  for (const Gaussian3& measurement : measurements) {
    const Vector3d offset = measurement.mean() - mean;
    spread.noalias() += measurement.covariance() + offset * offset.transpose();
  }
  return spread / static_cast<double>(measurements.size());
}

// The gate checks a track's measurements against its prediction once the track has a history
// position: with one, the velocity is unknown and the prediction's covariance holds the typical
// speed's spread for it (object_track.hpp), wide enough for any motion the model has seen, not for a
// gross error.
bool gates_against_prediction(const ObjectTrack& track) { return !track.history().empty(); }

// Consecutive events at which every measurement of a track fails the gate before the track starts
// again from them: with a known velocity, kGatedEventsBeforeRestart (the prediction is presumed right
// until several measurements say otherwise); with one history position, at once (either the start
// or the measurement is wrong, and the newer is the better start: on cad's validation split with one
// view's measurements 2 % gross outliers, DE 0.493 m, against 0.497 m when waiting for one more).
int restart_after(const ObjectTrack& track) {
  return track.history().size() >= 2 ? kGatedEventsBeforeRestart : 1;
}

// One of Q's scales as a scene starts it: the prior, plus what other scenes said of it.
ProcessNoiseScale start_scale(const FilterOptions& options, ProcessNoiseScale::Grid ProcessNoiseEvidence::*scale) {
  if (options.process_noise_start) {
    return ProcessNoiseScale((*options.process_noise_start).*scale, options.process_noise_below_one);
  }
  return options.process_noise_pooled ? ProcessNoiseScale::learning_the_whole_grid() : ProcessNoiseScale();
}

}  // namespace

ProcessNoiseEvidence SceneFilter::process_noise_evidence() const {
  return {.followed = state_.process_noise_scale.evidence_since(start_scale(options_, &ProcessNoiseEvidence::followed)),
          .fallback = state_.motion_choice.fallback_scale().evidence_since(start_scale(options_, &ProcessNoiseEvidence::fallback)),
          .coasting = state_.coasting_scale.evidence_since(start_scale(options_, &ProcessNoiseEvidence::coasting))};
}

SceneFilter::SceneFilter(const MotionPredictor& predictor, const FilterOptions& options)
    : predictor_(predictor),
      options_(options),
      gate_(options.gate),
      state_{.tracks = {},
             .registration = ViewRegistration(options.registration),
             .joint = JointRegistration(options.registration),
             .process_noise_scale = start_scale(options, &ProcessNoiseEvidence::followed),
             .coasting_scale = start_scale(options, &ProcessNoiseEvidence::coasting),
             .motion_choice = MotionChoice(options.motion_fallback, start_scale(options, &ProcessNoiseEvidence::fallback)),
             .view_noise = {},
             .last_time = {},
             .frame_interval = std::numeric_limits<double>::infinity(),
             .restarted_tracks = 0,
             .coasting_predictions = 0,
             .gate_restarts = 0,
             .applied_releases = {}},
      latest_time_(-std::numeric_limits<double>::infinity()),
      reached_time_(-std::numeric_limits<double>::infinity()) {
  if (!std::isfinite(options.lag_window) || options.lag_window < 0.0) {
    throw std::invalid_argument("the lag window must be finite and >= 0 seconds");
  }
  state_.joint.set_prior_scale_two_scales_probability(registration_two_scales_probability());
  if (options_.registration_scale_start) state_.joint.start_prior_scale_from(options_.registration_scale_start);
  if (options_.lag_window > 0.0) checkpoints_.push_back({-std::numeric_limits<double>::infinity(), state_});
}

double SceneFilter::registration_two_scales_probability() const {
  const SensorMotion sensors = options_.sensors.value_or(sensor_motion_.motion());
  return options_.registration.calibrated_sensors == sensors ? RegistrationPriorScale::kTwoScalesOnCalibratedSensors
                                                             : RegistrationPriorScale::kTwoScalesAnySensors;
}

void SceneFilter::adapt_registration_prior_scale() {
  // Set each time: a rewind restores the registration as it was, and the sensors may have been found
  // moving since.
  state_.joint.set_prior_scale_two_scales_probability(registration_two_scales_probability());
  state_.joint.adapt_prior_scale();
}

SceneFilter::TrackKey SceneFilter::key_of(const Measurement& measurement) const {
  return {options_.tracks == TrackMode::kPerView ? measurement.view : std::string(), measurement.object};
}

void SceneFilter::receive(std::span<const Measurement* const> measurements, std::span<const std::size_t> ids) {
  if (!request_.empty()) throw std::logic_error("SceneFilter::receive while a forecast request is open");
  if (measurements.size() != ids.size()) throw std::invalid_argument("SceneFilter::receive needs one id per measurement");
  // Too late: older than the window (or, without a window, not after the latest time).
  const auto too_late = [&](double time) {
    return options_.lag_window > 0.0 ? time < reached_time_ - options_.lag_window
                                     : time <= reached_time_ + kSameStepTolerance;
  };
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& measurement = *measurements[k];
    if (!std::isfinite(measurement.time)) {
      throw std::invalid_argument("measurement of object '" + measurement.object + "' by view '" + measurement.view +
                                  "' has a non-finite time");
    }
    if (too_late(measurement.time) && options_.late == LatePolicy::kStop) {
      throw LateMeasurementError(ids[k], "measured at t = " + seconds(measurement.time) +
                                             " s, it arrived after the scene had reached t = " + seconds(reached_time_) +
                                             " s: later than the lag window of " + seconds(options_.lag_window) +
                                             " s allows");
    }
  }
  if (!options_.sensors) {
    for (const Measurement* measurement : measurements) sensor_motion_.see(*measurement);
  }
  // The rest by time into events (rows within kSameStepTolerance of an event's earliest time join it).
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    if (!too_late(measurements[k]->time)) order.push_back(k);
  }
  const auto by_time = [&](std::size_t a, std::size_t b) { return measurements[a]->time < measurements[b]->time; };
  if (!std::is_sorted(order.begin(), order.end(), by_time)) std::stable_sort(order.begin(), order.end(), by_time);
  // Each event's rows in (object, view) order: the indices are sorted, and each row copied once. A
  // (view, object) twice at one time within the call is found on the way.
  const auto twice = [&](const Measurement& measurement, double time) {
    return std::invalid_argument("view '" + measurement.view + "' measured object '" + measurement.object +
                                 "' twice at t = " + seconds(time) + " s");
  };
  object_names_.trim();
  view_names_.trim();
  std::vector<Event> events;
  for (std::size_t first = 0; first < order.size();) {
    const double time = measurements[order[first]]->time;
    std::size_t end = first;
    while (end < order.size() && measurements[order[end]]->time - time <= kSameStepTolerance) ++end;
    const std::span<std::size_t> rows = std::span(order).subspan(first, end - first);
    if (const auto repeated = sort_by_object_and_view(rows, measurements, object_names_, view_names_)) {
      throw twice(*measurements[rows[*repeated]], time);
    }
    Event& event = events.emplace_back(Event{time, {}, false, {}});
    event.rows.reserve(end - first);
    for (std::size_t k = first; k < end; ++k) event.rows.push_back(Row{ids[order[k]], *measurements[order[k]], false});
    first = end;
  }
  // A (view, object) at one time both in the call and in what the filter already holds.
  const auto same_time_event = [&](const std::deque<Event>& list, double time) -> const Event* {
    for (const Event& event : list) {
      if (std::abs(event.time - time) <= kSameStepTolerance) return &event;
    }
    return nullptr;
  };
  for (const Event& event : events) {
    std::vector<const Measurement*> at_time;
    for (const std::deque<Event>* list : {&log_, &queue_}) {
      if (const Event* held = same_time_event(*list, event.time)) {
        for (const Row& row : held->rows) at_time.push_back(&row.measurement);
      }
    }
    if (at_time.empty()) continue;
    for (const Row& row : event.rows) at_time.push_back(&row.measurement);
    std::sort(at_time.begin(), at_time.end(), [](const Measurement* a, const Measurement* b) { return row_before(*a, *b); });
    for (std::size_t k = 1; k < at_time.size(); ++k) {
      if (at_time[k]->object == at_time[k - 1]->object && at_time[k]->view == at_time[k - 1]->view) {
        throw twice(*at_time[k], event.time);
      }
    }
  }
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    if (too_late(measurements[k]->time)) {
      leave_out(*measurements[k], ids[k]);
    } else if (measurements[k]->time < reached_time_ - kSameStepTolerance) {
      ++late_rows_;
    }
  }
  for (Event& event : events) {
    unreported_ += event.rows.size();
    insert(std::move(event));
  }
}

void SceneFilter::leave_out(const Measurement& measurement, std::size_t id) {
  const Measurement* alone = &measurement;
  const Gaussian3 estimate = joint()                      ? state_.joint.corrected(measurement)
                             : state_.registration.active() ? state_.registration.combine(std::span(&alone, 1))
                                                            : measurement.position;
  results_.push_back(Result{id, estimate, nullptr, false});
  ++late_measurements_;
}

void SceneFilter::insert(Event event) {
  if (event.time <= latest_time_ + kSameStepTolerance) {
    rewind_to(event.time);
    ++rewinds_;
  }
  auto position = queue_.begin();
  while (position != queue_.end() && position->time < event.time - kSameStepTolerance) ++position;
  // `event`'s rows are in (object, view) order; those of two events are merged into it.
  if (position != queue_.end() && std::abs(position->time - event.time) <= kSameStepTolerance) {
    position->time = std::min(position->time, event.time);
    const auto middle = static_cast<std::ptrdiff_t>(position->rows.size());
    for (Row& row : event.rows) position->rows.push_back(std::move(row));
    std::inplace_merge(position->rows.begin(), position->rows.begin() + middle, position->rows.end(),
                       [](const Row& a, const Row& b) { return row_before(a.measurement, b.measurement); });
    position->started = false;
  } else {
    queue_.insert(position, std::move(event));
  }
}

void SceneFilter::rewind_to(double time) {
  // The newest checkpoint from which the events at `time` replay.
  auto checkpoint = checkpoints_.end();
  for (auto it = checkpoints_.begin(); it != checkpoints_.end(); ++it) {
    if (it->time <= time + kSameStepTolerance) checkpoint = it;
  }
  if (checkpoint == checkpoints_.end()) throw std::logic_error("SceneFilter: no checkpoint covers a late measurement");
  state_ = checkpoint->state;
  while (!log_.empty() && log_.back().time >= checkpoint->time) {
    log_.back().started = false;
    queue_.push_front(std::move(log_.back()));
    log_.pop_back();
  }
  checkpoints_.erase(std::next(checkpoint), checkpoints_.end());
  latest_time_ = log_.empty() ? -std::numeric_limits<double>::infinity() : log_.back().time;
  for (const auto& [view, scale] : presumed_noise_scales_) state_.view_noise.presume(view, scale);
}

bool SceneFilter::advance(Advance how) {
  if (!request_.empty()) throw std::logic_error("SceneFilter::advance before the requested forecasts were provided");
  while (!queue_.empty()) {
    if (how == Advance::kUntilReported && unreported_ == 0) break;
    Event& event = queue_.front();
    if (!event.started) start(event);
    if (request_forecasts(event)) return false;
    process(event);
    if (refilter_) {
      // A view's noise was found understated, or its offset shifted some events ago: the filter goes
      // back and takes the window again from then — this event too, whose rows not yet reported wait
      // for it — with the learned scale or the release in place.
      refilter_ = false;
      event.started = false;
      rewind_to(std::max(refilter_from_, checkpoints_.front().time));
      refilter_from_ = std::numeric_limits<double>::infinity();
      ++refilters_;
      continue;
    }
    latest_time_ = std::max(latest_time_, event.time);
    reached_time_ = std::max(reached_time_, latest_time_);
    if (options_.lag_window > 0.0) log_.push_back(std::move(event));
    queue_.pop_front();
    prune();
  }
  return true;
}

void SceneFilter::start(Event& event) {
  if (options_.lag_window > 0.0 && event.time - checkpoints_.back().time >= kCheckpointSpacing) {
    checkpoints_.push_back({event.time, state_});
  }
  if (state_.last_time && event.time - *state_.last_time > kSameStepTolerance) {
    state_.frame_interval = std::min(state_.frame_interval, event.time - *state_.last_time);
  }
  state_.last_time = event.time;
  // The event's tracks: kPerObject, one per object (rows are in object order); kPerView, one per row.
  event.tracks.clear();
  for (std::size_t k = 0; k < event.rows.size(); ++k) {
    const Measurement& measurement = event.rows[k].measurement;
    if (options_.tracks == TrackMode::kPerObject && k > 0 && same_name(event.rows[k - 1].measurement.object, measurement.object)) {
      continue;
    }
    ObjectTrack& track = state_.tracks[key_of(measurement)];
    if (track.started_in_conflict()) {
      track.clear();  // no start for a velocity (object_track.hpp): starts again here, before any forecast reads it
    } else if (!track.empty() && event.time - track.state().time > track.unseen_limit(predictor_, state_.frame_interval)) {
      track.clear();  // unseen for too long: starts again, like an object never seen
      ++state_.restarted_tracks;
    } else if (track.coasts_to(event.time, predictor_)) {
      ++state_.coasting_predictions;
    }
    event.tracks.push_back(TrackRows{k, &track});
  }
  close_frames(event.time);
  event.started = true;
}

bool SceneFilter::request_forecasts(const Event& event) {
  std::vector<std::string> groups;  // track groups with a track that needs a forecast
  for (const TrackRows& rows : event.tracks) {
    if (!rows.track->needs_forecast() || rows.track->coasts_to(event.time, predictor_)) continue;
    const std::string group = options_.tracks == TrackMode::kPerView ? event.rows[rows.first].measurement.view : std::string();
    if (std::find(groups.begin(), groups.end(), group) == groups.end()) groups.push_back(group);
  }
  if (groups.empty()) return false;
  std::sort(groups.begin(), groups.end());
  const std::string& scene = event.rows.front().measurement.scene;
  for (const std::string& group : groups) {
    MotionGraph& graph = request_.emplace_back(MotionGraph{scene, group, event.time, {}});
    std::vector<ObjectTrack*>& tracks = request_tracks_.emplace_back();
    for (auto it = state_.tracks.lower_bound({group, std::string()}); it != state_.tracks.end() && it->first.first == group;
         ++it) {
      ObjectTrack& track = it->second;
      if (track.history().empty() || event.time - track.state().time > predictor_.prediction_horizon()) continue;
      ObjectHistory history{it->first.second, {}, {}};
      history.positions.reserve(track.history().size());
      history.times.reserve(track.history().size());
      for (const TrackPoint& point : track.history()) {
        history.positions.push_back(point.estimate.mean());
        history.times.push_back(point.time);
      }
      graph.objects.push_back(std::move(history));
      tracks.push_back(&track);
    }
  }
  // Each graph again, its histories tilted, for Φ's response to their slopes (slope_response.hpp).
  request_graphs_ = request_.size();
  if (options_.history_velocity_error) {
    request_tilts_.resize(request_graphs_);
    for (std::size_t g = 0; g < request_graphs_; ++g) {
      std::vector<Vector3d>& tilts = request_tilts_[g];
      tilts.clear();
      for (const ObjectTrack* track : request_tracks_[g]) {
        tilts.push_back(slope_tilt(track->velocity_variance(/*last_two=*/false), predictor_.typical_speed()));
      }
      request_.push_back(tilted_graph(request_[g], tilts));
    }
  }
  return true;
}

void SceneFilter::provide_forecasts(const std::vector<std::vector<MotionForecast>>& forecasts) {
  if (forecasts.size() != request_.size()) throw std::invalid_argument("SceneFilter: one forecast list per requested graph");
  for (std::size_t g = 0; g < request_.size(); ++g) {
    if (forecasts[g].size() != request_[g].objects.size()) {
      throw std::invalid_argument("SceneFilter: one forecast per object of each requested graph");
    }
  }
  const bool tilted = request_.size() > request_graphs_;
  for (std::size_t g = 0; g < request_graphs_; ++g) {
    for (std::size_t i = 0; i < request_tracks_[g].size(); ++i) {
      ObjectTrack& track = *request_tracks_[g][i];
      if (!track.needs_forecast()) continue;
      const MotionForecast& forecast = forecasts[g][i];
      track.set_forecast(tilted ? with_slope_response(forecast, forecasts[request_graphs_ + g][i], request_tilts_[g][i])
                                : forecast);
    }
  }
  request_.clear();
  request_tracks_.clear();
}

void SceneFilter::close_frames(double time) {
  const double window = options_.tracks == TrackMode::kPerObject ? predictor_.history_spacing() : 0.0;
  bool compared = false;
  for (auto& [key, track] : state_.tracks) {
    if (!track.has_frame()) continue;
    const double age = time - track.frame_time();
    if (!(age > kSameStepTolerance && age >= window)) continue;
    // The history position it makes is the state's, at the frame's last update, which may be its first:
    // it stays open until that is a window after the last history position too (two views measuring
    // microseconds apart would otherwise give two history positions that close, and Φ a velocity
    // from their difference).
    if (!track.history().empty() && track.state().time - track.history().back().time < window) continue;
    // Jointly, later measurements of other objects may have refined this one's position through the
    // offsets: the history gets what is known of it now.
    if (joint()) track.update(track.state().time, state_.joint.position(key.second), track.state().estimate.covariance());
    if (joint() && options_.adapt_registration_prior && track.frame_alignment().size() >= 2) {
      // The measurements fused alone within the frame, compared along the track's path.
      track.frame_alignment().aligned(aligned_.measurements, aligned_.noise_scales, aligned_.covariances);
      state_.joint.observe_differences(aligned_.measurements, aligned_.noise_scales, aligned_.covariances);
      compared = true;
    }
    track.close_frame(predictor_);
  }
  if (compared) adapt_registration_prior_scale();
}

OffsetVector SceneFilter::registration_offset(std::string_view view) const {
  return joint() ? state_.joint.offset(view) : state_.registration.offset(view);
}

std::vector<double> SceneFilter::cross_view_scales(std::span<const Row> rows, const MeasurementGate::Decision& decision) {
  std::vector<double> scales(rows.size(), 1.0);
  if (!options_.cross_view_weights || decision.conflicting) return scales;
  std::vector<std::size_t> judged;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (decision.passes[k]) judged.push_back(k);
  }
  if (judged.size() < 3) return scales;
  std::vector<CrossViewWeights::Measurement> measurements;
  measurements.reserve(judged.size());
  for (const std::size_t k : judged) {
    const Measurement& measurement = rows[k].measurement;
    // Corrected here, not taken from the gate's `alone`: learn_view_noise may have changed μ since.
    const double view_scale = noise_scale(measurement.view);
    const Gaussian3 corrected = state_.joint.corrected(measurement, view_scale);
    const Matrix3d noise = view_scale * measurement.position.covariance();
    measurements.push_back({corrected.mean(), noise, corrected.covariance() - noise});
  }
  const std::vector<double> judged_scales = CrossViewWeights::noise_scales(measurements);
  for (std::size_t i = 0; i < judged.size(); ++i) {
    scales[judged[i]] = judged_scales[i];
    if (judged_scales[i] > 1.0) state_.view_noise.count_down_weighted(rows[judged[i]].measurement.view);
  }
  return scales;
}

void SceneFilter::learn_view_noise(std::span<const Row> rows, const std::vector<Gaussian3>& alone,
                                   const std::vector<bool>& passes, double time) {
  if (!gate_.enabled() || rows.size() < 2) return;
  std::vector<const Measurement*> combined;  // the view's measurement, then the others'
  std::vector<Matrix3d> weights;
  for (std::size_t u = 0; u < rows.size(); ++u) {
    InformationSum others;
    for (std::size_t j = 0; j < rows.size(); ++j) {
      if (j != u && passes[j]) others.add(alone[j]);
    }
    if (others.count() == 0) continue;
    const Gaussian3 mean = others.solve();
    const Measurement& measurement = rows[u].measurement;
    const Matrix3d& noise = measurement.position.covariance();
    // ν = (z_u corrected) − Σ_j W_j (z_j corrected), W_j = (Σ I)⁻¹ I_j: all of its covariance but the
    // view's own noise μR. Jointly, the others' noise Σ_j W_j μ_j R_j W_jᵀ, independent from one
    // disagreement to the next, and the offsets' errors, which recur (offsets_covariance: the offset
    // common to the views cancels); else the others' mean's covariance and the view's offset's, all
    // taken to recur.
    Matrix3d rest = alone[u].covariance() + mean.covariance() - noise_scale(measurement.view) * noise;
    Matrix3d recurring = rest;
    if (joint()) {
      combined.assign(1, &measurement);
      weights.assign(1, Matrix3d::Identity());
      Matrix3d others_noise = Matrix3d::Zero();
      for (std::size_t j = 0; j < rows.size(); ++j) {
        if (j == u || !passes[j]) continue;
        const Matrix3d weight = mean.covariance() * alone[j].information();
        const Measurement& other = rows[j].measurement;
        others_noise.noalias() += weight * (noise_scale(other.view) * other.position.covariance()) * weight.transpose();
        combined.push_back(&other);
        weights.push_back(-weight);
      }
      recurring = state_.joint.offsets_covariance(combined, weights);
      rest = recurring + others_noise;
    }
    const std::optional<ViewNoiseScales::Release> release = state_.view_noise.add(
        measurement.view, time, alone[u].mean() - mean.mean(), rest, recurring, noise, /*separate_bias=*/joint());
    if (release) schedule_release(measurement.view, *release, time);
    // A noise scale this large (and twice the one presumed so far) says the view's R was understated
    // all along: what it already taught the tracks and the offsets is taught again with it.
    const double scale = state_.view_noise.scale(measurement.view);
    if (options_.lag_window > 0.0 && !release && scale >= kRefilterNoiseScale) {
      double& presumed = presumed_noise_scales_[measurement.view];
      if (scale >= 2.0 * presumed) {
        presumed = scale;
        refilter_from_ = -std::numeric_limits<double>::infinity();  // the whole window
        refilter_ = true;
      }
    }
  }
}

void SceneFilter::schedule_release(const std::string& view, const ViewNoiseScales::Release& release, double time) {
  // A shift that began at an earlier event, within the window: the view's offset is released from
  // then on, and the filter goes back to take what came since with it. Each such release of a view
  // begins after the one before (so going back ends).
  double latest = -std::numeric_limits<double>::infinity();
  for (const ScheduledRelease& earlier : scheduled_releases_) {
    if (earlier.view == view) latest = std::max(latest, earlier.time);
  }
  const double since = std::max(release.since, checkpoints_.empty() ? time : checkpoints_.front().time);
  if (options_.lag_window > 0.0 && since < time - kSameStepTolerance && since > latest + kSameStepTolerance) {
    scheduled_releases_.push_back(ScheduledRelease{view, since, release.covariance});
    refilter_from_ = std::min(refilter_from_, since);
    refilter_ = true;
    return;
  }
  state_.joint.release_offset(view, release.covariance);
}

void SceneFilter::apply_scheduled_releases(double time) {
  for (std::size_t k = 0; k < scheduled_releases_.size(); ++k) {
    const ScheduledRelease& release = scheduled_releases_[k];
    if (release.time > time + kSameStepTolerance ||
        std::find(state_.applied_releases.begin(), state_.applied_releases.end(), k) != state_.applied_releases.end()) {
      continue;
    }
    state_.joint.release_offset(release.view, release.covariance);
    state_.view_noise.restart_after_release(release.view, time);
    state_.applied_releases.push_back(k);
  }
}

double SceneFilter::noise_scale(std::string_view view) const {
  return gate_.enabled() ? state_.view_noise.scale(view) : 1.0;
}

bool SceneFilter::follows_constant_velocity() const { return state_.motion_choice.constant_velocity(); }

const ProcessNoiseScale& SceneFilter::followed_scale() const {
  return follows_constant_velocity() ? state_.motion_choice.fallback_scale() : state_.process_noise_scale;
}

SceneFilter::VelocityErrors SceneFilter::velocity_errors(const ObjectTrack& track, double time) const {
  if (!options_.history_velocity_error) return {};
  return {track.velocity_error_to(time, /*last_two=*/false), track.velocity_error_to(time, /*last_two=*/true)};
}

void SceneFilter::learn_sample(bool coasting, bool constant_velocity, const Vector3d& innovation,
                               const Matrix3d& known_covariance, const VelocityErrors& velocity_errors,
                               const Matrix3d& process_noise, const Vector3d& displacement_difference) {
  if (coasting) {  // by constant velocity
    state_.coasting_scale.add(innovation, known_covariance + velocity_errors.fallback, process_noise);
  } else {
    learn_motion(constant_velocity, innovation, known_covariance, velocity_errors, process_noise, displacement_difference);
  }
}

void SceneFilter::learn_motion(bool constant_velocity, const Vector3d& innovation,
                               const Matrix3d& known_covariance, const VelocityErrors& velocity_errors,
                               const Matrix3d& process_noise, const Vector3d& displacement_difference) {
  const Vector3d other = innovation + displacement_difference;
  const Vector3d& learned = constant_velocity ? other : innovation;
  const Vector3d& fallback = constant_velocity ? innovation : other;
  const Matrix3d learned_known = known_covariance + velocity_errors.learned;
  const Matrix3d fallback_known = known_covariance + velocity_errors.fallback;
  const bool adapt = options_.adapt_process_noise;
  if (state_.motion_choice.compares()) {
    state_.motion_choice.add(learned, fallback, learned_known, fallback_known, process_noise,
                             state_.process_noise_scale, adapt);
  } else if (options_.motion_fallback == MotionFallback::kAlways && adapt) {
    state_.motion_choice.learn_fallback(fallback, fallback_known, process_noise);
  }
  if (adapt) state_.process_noise_scale.add(learned, learned_known, process_noise);
}

void SceneFilter::process_joint(Event& event) {
  // Three passes over the event's objects, so that every check is against the state before the
  // event and every estimate includes all of it (through the offsets, one object's measurements move
  // the others' positions): each object is predicted and its measurements checked; then each is
  // updated with those that passed; then each reports its fused position.
  const double time = event.time;
  const bool constant_velocity = follows_constant_velocity();  // as the earlier events decided
  const ProcessNoiseScale scale = followed_scale();              // λ from the earlier events
  const ProcessNoiseScale coasting_scale = state_.coasting_scale;
  ViewNoiseScales& view_noise = state_.view_noise;
  struct Checked {
    std::size_t first, end;  // its rows
    ObjectTrack* track;
    std::optional<TrackPrediction> prediction;
    Matrix3d prior_covariance;  // P̂_s + the motion's: what the update started from (of a track that goes on)
    MeasurementGate::Decision decision;
    Matrix3d conflict_spread;  // with decision.conflicting
    std::vector<double> noise_scales;  // of its rows (cross_view_scales, times the views' μ)
  };
  std::vector<Checked> checked;
  checked.reserve(event.tracks.size());
  for (std::size_t g = 0; g < event.tracks.size(); ++g) {
    const std::size_t first = event.tracks[g].first;
    const std::size_t end = g + 1 < event.tracks.size() ? event.tracks[g + 1].first : event.rows.size();
    const std::string& object = event.rows[first].measurement.object;
    const std::span<Row> rows(event.rows.data() + first, end - first);
    ObjectTrack& track = *event.tracks[g].track;
    std::vector<Gaussian3> alone;  // with the gate: each measurement alone, corrected for its view's offset
    if (gate_.enabled()) {
      for (const Row& row : rows) alone.push_back(state_.joint.corrected(row.measurement, noise_scale(row.measurement.view)));
    }
    std::optional<TrackPrediction> prediction;
    std::optional<ObjectTrack::Motion> motion;
    std::vector<double> distances;
    // The measurements fused where a frame opens teach the scale of Q (§1.2), with their combined
    // innovation against the prediction from two or more history positions: Φ's λ (or constant
    // velocity's, §1.13), or the coasting λ when the track coasts.
    bool teaches_process_noise = false;
    bool coasting = false;
    if (!track.empty()) {
      coasting = track.coasts_to(time, predictor_);
      motion = track.motion_to(time, predictor_, coasting ? coasting_scale : scale, constant_velocity,
                               options_.history_velocity_error);
      if (options_.report_predictions) {
        // The predicted position: p_i + d, Σ_ii + Q (what position() gives after predict(), without
        // recomputing it). Not formed when nobody reads it: the marginal costs a substitution with M's factor.
        const Gaussian3 state = state_.joint.position(object);
        prediction = TrackPrediction{
            Gaussian3::from_covariance(state.mean() + motion->displacement, state.covariance() + motion->covariance),
            state.covariance(), motion->process_noise, motion->interval, track.history().size()};
      }
      state_.joint.predict(object, motion->displacement, motion->covariance);
      if (options_.adapt_registration_prior && track.has_frame()) {
        track.frame_alignment().follow(motion->displacement, motion->covariance);  // gathered only then
      }
      // Every row's innovation against the prediction, for the gate.
      teaches_process_noise = !track.has_frame() && track.history().size() >= 2 && learns_from(coasting);
      if (gate_.enabled() && gates_against_prediction(track)) {
        for (const Row& row : rows) {
          const JointRegistration::Innovation innovation = state_.joint.innovation(row.measurement, noise_scale(row.measurement.view));
          distances.push_back(distance_squared(innovation.value, innovation.covariance));
        }
      }
    }
    MeasurementGate::Decision decision = gate_.enabled()
                                             ? gate_.decide(distances, alone, track.gated_events(), restart_after(track))
                                             : MeasurementGate::pass_all(rows.size());
    for (std::size_t k = 0; k < rows.size() && decision.checked; ++k) {
      view_noise.count(rows[k].measurement.view, decision.passes[k]);
    }
    // Measurements that conflict say that one of them is wrong, not which: nothing is learnt of the
    // views from them.
    if (!decision.conflicting) learn_view_noise(rows, alone, decision.passes, time);
    // Each row's noise scale: its view's μ, and where the other views place it far off, more.
    std::vector<double> scales = cross_view_scales(rows, decision);
    for (std::size_t k = 0; k < rows.size(); ++k) scales[k] *= noise_scale(rows[k].measurement.view);
    if (decision.restart) {
      // Every measurement disagrees with the prediction: the track is what is wrong.
      track.clear();
      ++state_.restarted_tracks;
      ++state_.gate_restarts;
      prediction.reset();
    }
    if (teaches_process_noise && !track.empty()) {  // (a restart above has emptied it)
      // The combined innovation of the measurements that passed (of the first, when they conflict:
      // one of them is wrong).
      std::vector<const Measurement*> passed;
      std::vector<double> passed_scales;
      for (std::size_t k = 0; k < rows.size(); ++k) {
        if (!decision.passes[k] || (decision.conflicting && !passed.empty())) continue;
        passed.push_back(&rows[k].measurement);
        passed_scales.push_back(scales[k]);
      }
      if (!passed.empty()) {
        const JointRegistration::Innovation innovation = state_.joint.innovation(passed, passed_scales);
        // λ scales Q alone: the history's velocity error is known, as the state's is (each motion's its own).
        learn_sample(coasting, constant_velocity, innovation.value,
                     innovation.covariance - motion->covariance, velocity_errors(track, time),
                     motion->process_noise, motion->displacement - track.displacement_to(time, !constant_velocity));
      }
    }
    const Matrix3d spread = decision.conflicting ? conflict_spread(alone) : Matrix3d::Zero();
    const Matrix3d prior_covariance = motion && !track.empty() ? Matrix3d(track.state().estimate.covariance() + motion->covariance)
                                                               : Matrix3d::Identity();  // (unused for an empty track)
    checked.push_back(Checked{first, end, &track, std::move(prediction), prior_covariance, std::move(decision), spread,
                              std::move(scales)});
  }
  if (refilter_) return;  // going back: the whole event comes again
  std::vector<const Measurement*> fused;
  std::vector<double> fused_scales;
  for (const Checked& object : checked) {
    const std::span<Row> rows(event.rows.data() + object.first, object.end - object.first);
    ObjectTrack& track = *object.track;
    const MeasurementGate::Decision& decision = object.decision;
    fused.clear();
    fused_scales.clear();
    if (track.empty()) {
      // A diffuse start from the anchor, then the measurements that agree with it.
      const Measurement& anchor = rows[decision.anchor].measurement;
      state_.joint.remove_object(anchor.object);
      state_.joint.add_object(anchor, object.noise_scales[decision.anchor]);
    }
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (!decision.passes[k] || (track.empty() && k == decision.anchor)) continue;
      fused.push_back(&rows[k].measurement);
      fused_scales.push_back(object.noise_scales[k]);
    }
    state_.joint.update(fused, fused_scales);
    if (decision.conflicting) {
      state_.joint.predict(rows.front().measurement.object, Vector3d::Zero(), object.conflict_spread);
      track.mark_started_in_conflict();
    } else if (options_.adapt_registration_prior) {
      // Every fused measurement of the object at this time, the anchor too, shows how the views
      // disagree; one alone is compared with the frame's others when the frame closes.
      if (track.empty()) {
        const Measurement& anchor = rows[decision.anchor].measurement;
        fused.insert(fused.begin(), &anchor);
        fused_scales.insert(fused_scales.begin(), object.noise_scales[decision.anchor]);
      }
      if (fused.size() == 1) {
        track.frame_alignment().gather(*fused.front(), fused_scales.front());
      } else {
        state_.joint.observe_differences(fused, fused_scales);
      }
    }
    if (track.empty() || !fused.empty()) {
      track.reset_gated_events();
    } else {
      track.count_gated_event();
    }
  }
  if (options_.adapt_registration_prior) adapt_registration_prior_scale();
  std::vector<std::string_view> objects;
  objects.reserve(checked.size());
  for (const Checked& object : checked) objects.push_back(event.rows[object.first].measurement.object);
  const std::vector<Gaussian3> estimates = state_.joint.positions(objects);
  for (std::size_t i = 0; i < checked.size(); ++i) {
    const Checked& object = checked[i];
    const std::span<Row> rows(event.rows.data() + object.first, object.end - object.first);
    ObjectTrack& track = *object.track;
    std::vector<bool> gated(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) gated[k] = !object.decision.passes[k];
    const Gaussian3& estimate = estimates[i];
    if (!track.has_frame()) track.open_frame(time);
    // P⁻ is the state's as the track last held it plus the motion's: the share G = P⁺ (P⁻)⁻¹ counts what
    // other objects' measurements told of this one through the offsets since as part of this update.
    track.update(time, estimate, object.prior_covariance);
    report(event, object.first, object.end, estimate, object.prediction, gated);
  }
}

void SceneFilter::report(Event& event, std::size_t first, std::size_t end, const Gaussian3& estimate,
                         const std::optional<TrackPrediction>& prediction, const std::vector<bool>& gated) {
  std::shared_ptr<const TrackPrediction> shared;  // made for the first row that reports
  for (std::size_t k = first; k < end; ++k) {
    Row& row = event.rows[k];
    if (row.reported) continue;
    if (options_.report_predictions && prediction && !shared) shared = std::make_shared<const TrackPrediction>(*prediction);
    results_.push_back(Result{row.id, estimate, shared, gated[k - first]});
    row.reported = true;
    --unreported_;
  }
}

void SceneFilter::process(Event& event) {
  if (!scheduled_releases_.empty()) apply_scheduled_releases(event.time);
  if (joint()) {
    process_joint(event);
    return;
  }
  const double time = event.time;
  const bool constant_velocity = follows_constant_velocity();  // as the earlier events decided
  const ProcessNoiseScale scale = followed_scale();              // λ from the earlier events
  const ProcessNoiseScale coasting_scale = state_.coasting_scale;
  ViewNoiseScales& view_noise = state_.view_noise;
  struct Innovation {
    bool coasting;
    Vector3d value;
    Matrix3d known_covariance;        // P̂_s + R
    VelocityErrors velocity_errors;
    Matrix3d process_noise;           // Q(τ) − Q(τ_s)
    Vector3d displacement_difference;  // d_followed − d_other
  };
  std::vector<Innovation> innovations;
  std::vector<const Measurement*> fused_rows;  // every measurement that passed the gate
  const bool registration = state_.registration.active();
  for (std::size_t first = 0; first < event.rows.size();) {
    const std::string& object = event.rows[first].measurement.object;
    std::size_t end = first;
    while (end < event.rows.size() && event.rows[end].measurement.object == object) ++end;
    // The rows with their noise scaled by their views' μ (copies only where μ ≠ 1), and with the gate,
    // each alone corrected for its view's offset.
    std::vector<Measurement> rescaled;
    rescaled.reserve(end - first);  // no reallocation: `scaled` points into it
    std::vector<const Measurement*> scaled;
    for (std::size_t k = first; k < end; ++k) {
      const Measurement& measurement = event.rows[k].measurement;
      const double view_scale = noise_scale(measurement.view);
      if (view_scale == 1.0) {
        scaled.push_back(&measurement);
        continue;
      }
      Measurement& copy = rescaled.emplace_back(measurement);
      copy.position = Gaussian3::from_covariance(measurement.position.mean(), view_scale * measurement.position.covariance());
      scaled.push_back(&copy);
    }
    std::vector<Gaussian3> alone;
    if (gate_.enabled()) {
      for (const Measurement* measurement : scaled) {
        alone.push_back(registration ? state_.registration.combine(std::span(&measurement, 1)) : measurement->position);
      }
    }
    // kPerObject: one track for all rows; kPerView: one per row. The gate checks each row against the
    // prediction of the first of them that has one.
    const std::size_t track_count = options_.tracks == TrackMode::kPerObject ? 1 : end - first;
    ObjectTrack* reference = nullptr;
    std::optional<TrackPrediction> reference_prediction;
    for (std::size_t t = 0; t < track_count; ++t) {
      ObjectTrack& track = state_.tracks[key_of(event.rows[first + t].measurement)];
      if (!track.empty() && !reference) reference = &track;
    }
    std::vector<double> distances;
    if (reference) {
      reference_prediction = reference->predict(time, predictor_, scale, constant_velocity);
      if (gate_.enabled() && gates_against_prediction(*reference)) {
        for (std::size_t k = first; k < end; ++k) {
          const Vector3d innovation = alone[k - first].mean() - reference_prediction->prior.mean();
          distances.push_back(distance_squared(innovation, reference_prediction->prior.covariance() + alone[k - first].covariance()));
        }
      }
    }
    const MeasurementGate::Decision decision =
        gate_.enabled() ? gate_.decide(distances, alone, reference ? reference->gated_events() : 0,
                                       reference ? restart_after(*reference) : kGatedEventsBeforeRestart)
                        : MeasurementGate::pass_all(end - first);
    std::vector<bool> gated(end - first);
    for (std::size_t k = first; k < end; ++k) {
      gated[k - first] = !decision.passes[k - first];
      if (decision.checked) view_noise.count(event.rows[k].measurement.view, decision.passes[k - first]);
    }
    if (!decision.conflicting) {
      learn_view_noise(std::span(event.rows.data() + first, end - first), alone, decision.passes, time);
    }
    if (refilter_) return;  // going back: the rest of the event comes again
    if (decision.restart) {
      for (std::size_t t = 0; t < track_count; ++t) state_.tracks[key_of(event.rows[first + t].measurement)].clear();
      ++state_.restarted_tracks;
      ++state_.gate_restarts;
      reference = nullptr;
      reference_prediction.reset();
    }
    if (reference) {
      if (std::find(gated.begin(), gated.end(), false) != gated.end()) {
        reference->reset_gated_events();
      } else {
        reference->count_gated_event();
      }
    }
    std::vector<const Measurement*> rows;
    std::vector<Gaussian3> positions;
    for (std::size_t k = first; k < end; ++k) {
      if (gated[k - first]) continue;
      rows.push_back(scaled[k - first]);
      positions.push_back(scaled[k - first]->position);
      fused_rows.push_back(&event.rows[k].measurement);
    }
    // One combined measurement of those that passed: corrected for the registration offsets when
    // there are any to account for, else the information-weighted mean (then used for the innovation
    // and a diffuse start). None passed: the tracks keep their predictions.
    std::optional<Gaussian3> combined;
    if (!rows.empty()) {
      combined = registration ? state_.registration.combine(rows) : information_weighted_mean(positions);
      if (decision.conflicting) {
        combined = Gaussian3::from_covariance(combined->mean(), combined->covariance() + conflict_spread(alone));
      }
    }
    std::optional<Innovation> innovation;
    for (std::size_t t = 0; t < track_count; ++t) {
      ObjectTrack& track = state_.tracks[key_of(event.rows[first + t].measurement)];
      std::optional<TrackPrediction> prediction;
      const bool coasting = track.coasts_to(time, predictor_);
      if (!track.empty()) {
        prediction = track.predict(time, predictor_, coasting ? coasting_scale : scale, constant_velocity,
                                   options_.history_velocity_error);
      }
      if (!prediction && !combined) {
        // kPerView: this view's track is empty and every measurement failed the gate against another
        // view's track: nothing to start it from; the row gets that track's prediction.
        report(event, first + t, first + t + 1, reference_prediction->prior, reference_prediction,
               {gated.begin() + t, gated.begin() + t + 1});
        continue;
      }
      // The diffuse start is the limit P⁻¹ → 0 of the update: the combined measurement itself.
      const Gaussian3 fused = !prediction  ? *combined
                              : !combined   ? prediction->prior
                              : registration ? multi_view_update(prediction->prior, std::span(&*combined, 1))
                                             : multi_view_update(prediction->prior, positions);
      const bool opens_frame = !track.has_frame();
      if (opens_frame && prediction && combined && prediction->history_positions >= 2 && learns_from(coasting) &&
          !innovation) {
        innovation = Innovation{coasting, combined->mean() - prediction->prior.mean(),
                                prediction->state_covariance + combined->covariance(), velocity_errors(track, time),
                                prediction->process_noise,
                                track.displacement_to(time, constant_velocity) - track.displacement_to(time, !constant_velocity)};
      }
      if (opens_frame) track.open_frame(time);
      if (prediction) {
        track.update(time, fused, prediction->prior.covariance());
      } else {
        track.update(time, fused);
      }
      if (decision.conflicting) track.mark_started_in_conflict();
      if (options_.tracks == TrackMode::kPerObject) {
        report(event, first, end, fused, prediction, gated);
      } else {
        report(event, first + t, first + t + 1, fused, prediction, {gated.begin() + t, gated.begin() + t + 1});
      }
    }
    if (innovation) innovations.push_back(*innovation);
    first = end;
  }
  if (options_.tracks == TrackMode::kPerView && registration) state_.registration.learn(fused_rows);
  for (const Innovation& innovation : innovations) {
    learn_sample(innovation.coasting, constant_velocity, innovation.value, innovation.known_covariance,
                 innovation.velocity_errors,
                 innovation.process_noise, innovation.displacement_difference);
  }
}

void SceneFilter::prune() {
  if (options_.lag_window <= 0.0) return;
  const double cutoff = latest_time_ - options_.lag_window;
  while (checkpoints_.size() >= 2 && checkpoints_[1].time <= cutoff) checkpoints_.pop_front();
  while (!log_.empty() && log_.front().time < checkpoints_.front().time) log_.pop_front();
}

void SceneFilter::take_results(std::vector<Result>& results) {
  results.clear();
  results.swap(results_);
}

}  // namespace stgf
