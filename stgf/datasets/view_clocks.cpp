// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/view_clocks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "stgf/core/records.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

// |jitter| ≤ this many frame periods (redrawn beyond).
constexpr double kMaxJitterInPeriods = 0.45;
// Message times of a scene closer than this (seconds) are merged: after rounding to the microsecond
// they are then equal or at least 2 µs apart.
constexpr double kMergeBelow_s = 1.5e-6;

double to_microseconds(double seconds) { return std::round(seconds * 1e6) / 1e6; }

// An object's true track: known positions at increasing times, linear between them, extrapolated
// linearly from the two nearest beyond them (constant with one).
class Track {
 public:
  void add(double time, const Vector3d& position) { samples_.push_back({time, position}); }
  void sort() {
    std::sort(samples_.begin(), samples_.end(), [](const Sample& a, const Sample& b) { return a.time < b.time; });
  }
  bool empty() const { return samples_.empty(); }
  double first_time() const { return samples_.front().time; }
  double last_time() const { return samples_.back().time; }

  Vector3d at(double time) const {
    if (samples_.size() == 1) return samples_.front().position;
    const auto upper = std::upper_bound(samples_.begin(), samples_.end(), time,
                                        [](double t, const Sample& sample) { return t < sample.time; });
    const auto right = std::clamp<std::ptrdiff_t>(upper - samples_.begin(), 1,
                                                  static_cast<std::ptrdiff_t>(samples_.size()) - 1);
    const Sample& a = samples_[static_cast<std::size_t>(right - 1)];
    const Sample& b = samples_[static_cast<std::size_t>(right)];
    if (time == a.time) return a.position;
    if (time == b.time) return b.position;
    const double fraction = (time - a.time) / (b.time - a.time);
    return a.position + fraction * (b.position - a.position);
  }

 private:
  struct Sample {
    double time;
    Vector3d position;
  };
  std::vector<Sample> samples_;
};

// One view's clock in one scene: its phase, and per frame of the scene the message time and (with
// a latency) the delay of its arrival.
struct ViewClock {
  double phase_s = 0.0;
  std::vector<double> times;
  std::vector<double> delays;
};

// The rows of one scene and what the clocks need of them.
struct Scene {
  std::string name;
  std::vector<std::size_t> measurements;  // indices into split.measurements, in split order
  std::vector<std::size_t> truth;         // indices into split.truth
  std::vector<double> frame_times;        // distinct, increasing
  std::map<std::string, ViewClock> clocks;
  std::map<std::string, Track> tracks;  // object → track
};

// Distinct times (within kSameStepTolerance of the previous distinct one), increasing.
std::vector<double> distinct_times(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  std::vector<double> distinct;
  for (const double time : times) {
    if (distinct.empty() || time - distinct.back() > kSameStepTolerance) distinct.push_back(time);
  }
  return distinct;
}

std::size_t frame_index(const Scene& scene, double time) {
  const auto it = std::lower_bound(scene.frame_times.begin(), scene.frame_times.end(), time - kSameStepTolerance);
  return static_cast<std::size_t>(it - scene.frame_times.begin());
}

// N(0, σ²) truncated to |j| ≤ bound by redrawing.
double truncated_normal(RandomStream& random, double standard_deviation, double bound) {
  for (;;) {
    const double jitter = standard_deviation * random.normal();
    if (std::abs(jitter) <= bound) return jitter;
  }
}

// min, mean, max of `values` (nulls when empty).
nlohmann::json summary_json(const std::vector<double>& values) {
  if (values.empty()) return {{"count", 0}, {"min", nullptr}, {"mean", nullptr}, {"max", nullptr}};
  double sum = 0.0;
  for (const double value : values) sum += value;
  return {{"count", values.size()},
          {"min", *std::min_element(values.begin(), values.end())},
          {"mean", sum / static_cast<double>(values.size())},
          {"max", *std::max_element(values.begin(), values.end())}};
}

class ClockApplier {
 public:
  ClockApplier(const ViewClockOptions& options, double frame_period_s, const RandomStream& root,
               const TrackBeyondWindow& track_beyond_window)
      : options_(options),
        period_(frame_period_s),
        clocks_root_(root.child("clocks")),
        latency_root_(root.child("latency")),
        track_beyond_window_(track_beyond_window) {}

  nlohmann::json apply(BenchmarkSplit& split) {
    std::vector<Scene> scenes = group_by_scene(split);
    for (Scene& scene : scenes) {
      draw_clocks(scene);
      if (options_.asynchronous) {
        merge_close_times(scene);
        build_tracks(scene, split);
      }
    }
    std::vector<Measurement> measurements;
    std::vector<TruthPoint> truth;
    measurements.reserve(split.measurements.size());
    for (Scene& scene : scenes) move_scene(scene, split, measurements, truth);
    split.measurements = std::move(measurements);
    if (options_.asynchronous) split.truth = std::move(truth);
    return describe(scenes);
  }

 private:
  std::vector<Scene> group_by_scene(const BenchmarkSplit& split) const {
    std::vector<Scene> scenes;
    std::unordered_map<std::string, std::size_t> index_of;
    const auto scene_of = [&](const std::string& name) -> Scene& {
      const auto [it, inserted] = index_of.try_emplace(name, scenes.size());
      if (inserted) scenes.push_back(Scene{name, {}, {}, {}, {}, {}});
      return scenes[it->second];
    };
    for (std::size_t k = 0; k < split.measurements.size(); ++k)
      scene_of(split.measurements[k].scene).measurements.push_back(k);
    for (std::size_t k = 0; k < split.truth.size(); ++k) scene_of(split.truth[k].scene).truth.push_back(k);
    for (Scene& scene : scenes) {
      std::vector<double> times;
      for (const std::size_t k : scene.measurements) times.push_back(split.measurements[k].time);
      for (const std::size_t k : scene.truth) times.push_back(split.truth[k].time);
      scene.frame_times = distinct_times(std::move(times));
      std::set<std::tuple<std::string, std::string, std::size_t>> seen;
      for (const std::size_t k : scene.measurements) {
        const Measurement& row = split.measurements[k];
        if (!seen.emplace(row.view, row.object, frame_index(scene, row.time)).second) {
          throw std::invalid_argument(fmt::format(
              "view clocks: scene '{}' has two rows of view '{}' and object '{}' at t {}; a synchronous split has "
              "at most one per frame",
              scene.name, row.view, row.object, row.time));
        }
        scene.clocks.try_emplace(row.view);
      }
    }
    return scenes;
  }

  // φ and the jitters from R.child("clocks").child(s).child(v); the delays from
  // R.child("latency").child(s).child(v); one of each per frame of the scene.
  void draw_clocks(Scene& scene) const {
    const std::size_t frames = scene.frame_times.size();
    for (auto& [view, clock] : scene.clocks) {
      clock.times = scene.frame_times;
      if (options_.asynchronous) {
        RandomStream random = clocks_root_.child(scene.name).child(view);
        clock.phase_s = random.uniform(0.0, period_);
        for (std::size_t k = 0; k < frames; ++k) {
          const double jitter = truncated_normal(random, options_.jitter_s, kMaxJitterInPeriods * period_);
          clock.times[k] = to_microseconds(scene.frame_times[k] + clock.phase_s + jitter);
        }
      }
      if (options_.latency_s > 0.0) {
        RandomStream random = latency_root_.child(scene.name).child(view);
        clock.delays.resize(frames);
        for (std::size_t k = 0; k < frames; ++k) clock.delays[k] = random.uniform(0.0, options_.latency_s);
      }
    }
  }

  // Message times of the scene 1 µs apart become the earlier one (all views, all frames).
  void merge_close_times(Scene& scene) {
    std::vector<double*> times;
    for (auto& [view, clock] : scene.clocks) {
      for (double& time : clock.times) times.push_back(&time);
    }
    std::stable_sort(times.begin(), times.end(), [](const double* a, const double* b) { return *a < *b; });
    double cluster_start = -std::numeric_limits<double>::infinity();
    for (double* time : times) {
      if (*time - cluster_start < kMergeBelow_s) {
        if (*time != cluster_start) ++merged_times_;
        *time = cluster_start;
      } else {
        cluster_start = *time;
      }
    }
  }

  // Each object's truth rows, and the recording's frames just outside them when the builder has them.
  void build_tracks(Scene& scene, const BenchmarkSplit& split) {
    for (const std::size_t k : scene.truth) {
      const TruthPoint& point = split.truth[k];
      scene.tracks[point.object].add(point.time, point.position);
    }
    for (auto& [object, track] : scene.tracks) {
      track.sort();
      const double first = track.first_time();
      const double last = track.last_time();
      const auto beyond = [&](double time) -> std::optional<Vector3d> {
        if (!track_beyond_window_) return std::nullopt;
        return track_beyond_window_(scene.name, object, time);
      };
      if (const auto before = beyond(first - period_)) {
        track.add(first - period_, *before);
        ++ends_from_recording_;
      } else {
        ++ends_extrapolated_;
      }
      if (const auto after = beyond(last + period_)) {
        track.add(last + period_, *after);
        ++ends_from_recording_;
        if (const auto second = beyond(last + 2.0 * period_)) track.add(last + 2.0 * period_, *second);
      } else {
        ++ends_extrapolated_;
      }
      track.sort();
    }
  }

  void move_scene(const Scene& scene, const BenchmarkSplit& split, std::vector<Measurement>& measurements,
                  std::vector<TruthPoint>& truth) {
    const std::size_t first = measurements.size();
    std::set<std::pair<double, std::string>> measured;  // (t', object)
    for (const std::size_t k : scene.measurements) {
      Measurement row = split.measurements[k];
      const std::size_t frame = frame_index(scene, row.time);
      const ViewClock& clock = scene.clocks.at(row.view);
      if (options_.asynchronous) {
        const auto track = scene.tracks.find(row.object);
        if (track == scene.tracks.end()) {
          throw std::invalid_argument(fmt::format("view clocks: scene '{}' measures object '{}', which has no truth",
                                                  scene.name, row.object));
        }
        const double time = clock.times[frame];
        const Vector3d moved = row.position.mean() + (track->second.at(time) - track->second.at(row.time));
        row.position = Gaussian3::from_covariance(moved, row.position.covariance());
        row.time = time;
        measured.emplace(time, row.object);
      }
      if (options_.latency_s > 0.0) row.arrival = row.time + clock.delays[frame];
      measurements.push_back(std::move(row));
    }
    std::stable_sort(measurements.begin() + static_cast<std::ptrdiff_t>(first), measurements.end(),
                     [](const Measurement& a, const Measurement& b) { return a.time < b.time; });
    for (const auto& [time, object] : measured) truth.push_back({scene.name, time, object, scene.tracks.at(object).at(time)});
  }

  nlohmann::json describe(const std::vector<Scene>& scenes) const {
    std::vector<double> phases;
    std::vector<double> offsets;  // t' − t_k − φ: the jitter after rounding and merging
    std::vector<double> delays;
    for (const Scene& scene : scenes) {
      for (const auto& [view, clock] : scene.clocks) {
        if (options_.asynchronous) {
          phases.push_back(clock.phase_s);
          for (std::size_t k = 0; k < clock.times.size(); ++k)
            offsets.push_back(clock.times[k] - scene.frame_times[k] - clock.phase_s);
        }
        delays.insert(delays.end(), clock.delays.begin(), clock.delays.end());
      }
    }
    nlohmann::json entry = {{"scenes", scenes.size()}};
    if (options_.asynchronous) {
      entry["phase_s"] = summary_json(phases);
      entry["jitter_drawn_s"] = summary_json(offsets);
      entry["merged_message_times"] = merged_times_;
      entry["track_ends_from_recording"] = ends_from_recording_;
      entry["track_ends_extrapolated"] = ends_extrapolated_;
    }
    if (options_.latency_s > 0.0) entry["delay_s"] = summary_json(delays);
    return entry;
  }

  const ViewClockOptions& options_;
  double period_;
  RandomStream clocks_root_;
  RandomStream latency_root_;
  const TrackBeyondWindow& track_beyond_window_;
  long long merged_times_ = 0;
  long long ends_from_recording_ = 0;
  long long ends_extrapolated_ = 0;
};

}  // namespace

void check_view_clock_options(const OptionChecks& check, const ViewClockOptions& options, double frame_period_s) {
  check.not_negative("latency_s", options.latency_s);
  if (!options.asynchronous) return;
  check.real("jitter_s", options.jitter_s, options.jitter_s >= 0.0 && options.jitter_s < frame_period_s / 10.0,
             fmt::format("zero or positive and below a tenth of the frame period ({} s)", frame_period_s / 10.0));
}

nlohmann::json apply_view_clocks(BenchmarkSplit& split, const ViewClockOptions& options, double frame_period_s,
                                 const RandomStream& root, const TrackBeyondWindow& track_beyond_window) {
  if (!(std::isfinite(frame_period_s) && frame_period_s > 0.0)) {
    throw std::invalid_argument(fmt::format("view clocks: the frame period must be positive (got {})", frame_period_s));
  }
  check_view_clock_options(OptionChecks("view clocks"), options, frame_period_s);
  if (!options.active()) return nullptr;
  return ClockApplier(options, frame_period_s, root, track_beyond_window).apply(split);
}

nlohmann::json view_clocks_json(const ViewClockOptions& options, double frame_period_s, nlohmann::json splits) {
  nlohmann::json entry = {
      {"asynchronous", options.asynchronous},
      {"jitter_s", options.asynchronous ? nlohmann::json(options.jitter_s) : nlohmann::json(nullptr)},
      {"latency_s", options.latency_s},
      {"frame_period_s", frame_period_s},
      {"streams",
       "phase and jitters of view v in scene s: RandomStream(seed).child(\"clocks\").child(s).child(v): phase = "
       "uniform(0, T), then one jitter per frame of the scene; delays: RandomStream(seed).child(\"latency\")"
       ".child(s).child(v), one uniform(0, latency_s) per frame"},
      {"splits", std::move(splits)},
  };
  if (options.asynchronous) {
    entry["clock_model"] =
        "a view's message of frame k (all its rows of that frame) is measured at t' = t_k + phase + jitter, "
        "rounded to the microsecond, phase ~ U[0, T) per view and scene, jitter ~ N(0, jitter_s^2) truncated to "
        "|jitter| <= 0.45 T; message times of a scene 1 microsecond apart are merged into the earlier; each row "
        "moves with its object, z' = z + p(t') - p(t_k), R and the sensor position unchanged; the truth is p(t') at "
        "every distinct measured (scene, t', object), p linear between the known frames (the instance's and, "
        "where the recording has them, the frame before and the two after it) and extrapolated linearly beyond";
  }
  if (options.latency_s > 0.0)
    entry["latency_model"] = "arrival = t' + U[0, latency_s), one draw per message (view, frame)";
  return entry;
}

}  // namespace stgf
