// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/motion_graphs.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>

#include "stgf/core/multi_view_update.hpp"
#include "stgf/core/steps.hpp"

namespace stgf {
namespace {

// Rows, sightings and tracks are counted in 32 bits: four of these per row instead of eight bytes each.
using Index = std::uint32_t;
constexpr Index kNone = std::numeric_limits<Index>::max();

// The shortest text that reads back as the same double.
std::string format_time(double seconds) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, seconds);
  return std::string(buffer, result.ptr);
}

// Dense ids 0, 1, ... for names, in order of first use. The names are views into the measurements.
class NameIds {
 public:
  Index id(std::string_view name) {
    const auto [it, inserted] = ids_.try_emplace(name, static_cast<Index>(names_.size()));
    if (inserted) names_.push_back(name);
    return it->second;
  }
  std::string_view name(Index id) const { return names_[id]; }
  Index size() const { return static_cast<Index>(names_.size()); }
  void clear() {
    ids_.clear();
    names_.clear();
  }

 private:
  std::unordered_map<std::string_view, Index> ids_;
  std::vector<std::string_view> names_;
};

// One object seen at one step of the current scene (by one or more views).
struct Sighting {
  Index object;
  Index step;
};

// One position of a track: kRawView, measurement row `row`; kFused, the fused position of `sighting`.
struct HistoryEntry {
  Index sighting;  // gives the step (hence the time) and the truth
  Index row;       // kNone for kFused
};

// What a graph's objects are trained towards: nothing (graphs to run Φ on), the truth, or what was
// measured (the target step's fused position, or the view's own measurement for kRawView).
enum class Targets { kNothing, kTruth, kMeasured };

struct Output {
  std::vector<TrainingGraph> graphs;  // .graph always; the target fields unless Targets::kNothing
  std::vector<std::vector<Matrix3d>> latest_covariances;  // when asked for
  std::vector<std::optional<GraphObjectIndex>> predictor_of_row;
  std::size_t restarted_tracks = 0;
};

// Builds the graphs scene by scene (see the header for what they hold). Per scene, objects get dense
// ids; a track is the list of earlier positions of one object (kFused) or one (view, object) pair
// (kRawView), appended to after each step, so a step's histories are the tails of its tracks.
class GraphBuilder {
 public:
  GraphBuilder(std::span<const Measurement> measurements, HistorySource source, int history_length,
               Targets targets, const TruthIndex* truth, bool latest_covariances,
               double max_gap = std::numeric_limits<double>::infinity())
      : measurements_(measurements),
        source_(source),
        history_length_(static_cast<std::size_t>(history_length)),
        max_gap_(max_gap),
        targets_(targets),
        truth_(truth),
        latest_covariances_(latest_covariances) {
    if (history_length < 1) {
      throw std::invalid_argument("motion graphs: history_length must be at least 1, not " +
                                  std::to_string(history_length));
    }
    if (measurements.size() >= kNone) {
      throw std::length_error("motion graphs: more than 2^32 - 2 measurement rows");
    }
  }

  Output build() {
    const std::size_t count = measurements_.size();
    object_of_row_.resize(count);
    view_of_row_.resize(count);
    sighting_of_row_.resize(count);
    if (source_ == HistorySource::kRawView) track_of_row_.resize(count);
    output_.predictor_of_row.assign(count, std::nullopt);
    for (const Scene& scene : group_into_scenes(measurements_)) build_scene(scene);
    return std::move(output_);
  }

 private:
  void build_scene(const Scene& scene) {
    scene_ = &scene;
    objects_.clear();
    for (const Step& step : scene.steps) {
      for (std::size_t row : step.rows) {
        object_of_row_[row] = objects_.id(measurements_[row].object);
        view_of_row_[row] = views_.id(measurements_[row].view);
      }
    }
    slot_of_object_.assign(objects_.size(), kNone);
    view_slot_.resize(views_.size(), kNone);
    view_mark_.resize(views_.size(), 0);
    sightings_.clear();
    fused_.clear();
    truth_known_.clear();
    truth_positions_.clear();
    track_of_key_.clear();
    track_mark_.clear();
    track_count_ = 0;
    if (source_ == HistorySource::kFused) use_tracks(objects_.size());

    for (Index step = 0; step < scene.steps.size(); ++step) {
      const Index first_sighting = add_sightings(step);
      if (source_ == HistorySource::kFused) {
        build_fused_step(step, first_sighting);
      } else {
        build_raw_view_step(step);
      }
      for (Index sighting = first_sighting; sighting < sightings_.size(); ++sighting) {
        slot_of_object_[sightings_[sighting].object] = kNone;
      }
    }
    sighting_serial_base_ += sightings_.size();
  }

  // Makes `count` empty tracks (keeping the capacity of earlier scenes' tracks).
  void use_tracks(std::size_t count) {
    if (tracks_.size() < count) tracks_.resize(count);
    for (std::size_t track = 0; track < count; ++track) tracks_[track].clear();
    track_count_ = count;
  }

  // One sighting per distinct object of the step, in order of first appearance; returns the first.
  Index add_sightings(Index step) {
    const auto first = static_cast<Index>(sightings_.size());
    for (std::size_t row : scene_->steps[step].rows) {
      Index& slot = slot_of_object_[object_of_row_[row]];
      if (slot == kNone) {
        slot = static_cast<Index>(sightings_.size());
        sightings_.push_back(Sighting{object_of_row_[row], step});
      }
      sighting_of_row_[row] = slot;
    }
    truth_known_.resize(sightings_.size(), 0);
    truth_positions_.resize(sightings_.size());
    return first;
  }

  void build_fused_step(Index step, Index first_sighting) {
    const Step& rows = scene_->steps[step];
    // x_s, P_s of every object of the step: the information sum of its rows, in row order (the
    // order information_weighted_mean would add them in, so the result is the same to the bit).
    sums_.assign(sightings_.size() - first_sighting, InformationSum{});
    for (std::size_t row : rows.rows) {
      const Index sighting = sighting_of_row_[row];
      std::uint64_t& mark = view_mark_[view_of_row_[row]];
      if (mark == sighting_serial_base_ + sighting + 1) throw_duplicate(row);
      mark = sighting_serial_base_ + sighting + 1;
      sums_[sighting - first_sighting].add(measurements_[row].position);
    }
    for (const InformationSum& sum : sums_) fused_.push_back(sum.solve());

    // The step's graph: the objects with a track, in sighting order.
    object_in_graph_.assign(sums_.size(), kNone);
    std::optional<std::size_t> graph_index;
    for (Index sighting = first_sighting; sighting < sightings_.size(); ++sighting) {
      std::vector<HistoryEntry>& track = tracks_[sightings_[sighting].object];
      restart_if_stale(track, step);
      if (track.empty()) continue;
      if (!graph_index) graph_index = start_graph(step, std::string_view());
      object_in_graph_[sighting - first_sighting] =
          static_cast<Index>(output_.graphs[*graph_index].graph.objects.size());
      add_object(*graph_index, track, HistoryEntry{sighting, kNone});
    }
    if (graph_index) {
      for (std::size_t row : rows.rows) {
        const Index object = object_in_graph_[sighting_of_row_[row] - first_sighting];
        if (object != kNone) output_.predictor_of_row[row] = GraphObjectIndex{*graph_index, object};
      }
    }
    for (Index sighting = first_sighting; sighting < sightings_.size(); ++sighting) {
      tracks_[sightings_[sighting].object].push_back(HistoryEntry{sighting, kNone});
    }
  }

  void build_raw_view_step(Index step) {
    const Step& rows = scene_->steps[step];
    // Views in order of first appearance, each with the number of its rows that have a history.
    step_views_.clear();
    rows_with_history_.clear();
    for (std::size_t row : rows.rows) {
      const Index view = view_of_row_[row];
      if (view_slot_[view] == kNone) {
        view_slot_[view] = static_cast<Index>(step_views_.size());
        step_views_.push_back(view);
        rows_with_history_.push_back(0);
      }
      const Index track = track_of(view, object_of_row_[row]);
      if (track_mark_[track] == step + 1) throw_duplicate(row);
      track_mark_[track] = step + 1;
      track_of_row_[row] = track;
      restart_if_stale(tracks_[track], step);
      if (!tracks_[track].empty()) ++rows_with_history_[view_slot_[view]];
    }
    graph_of_slot_.assign(step_views_.size(), kNone);
    for (std::size_t slot = 0; slot < step_views_.size(); ++slot) {
      if (rows_with_history_[slot] > 0) {
        graph_of_slot_[slot] = start_graph(step, views_.name(step_views_[slot]));
        output_.graphs.back().graph.objects.reserve(rows_with_history_[slot]);
      }
    }
    for (std::size_t row : rows.rows) {
      std::vector<HistoryEntry>& track = tracks_[track_of_row_[row]];
      if (!track.empty()) {
        const std::size_t graph_index = graph_of_slot_[view_slot_[view_of_row_[row]]];
        const std::size_t object = output_.graphs[graph_index].graph.objects.size();
        add_object(graph_index, track, HistoryEntry{sighting_of_row_[row], static_cast<Index>(row)});
        output_.predictor_of_row[row] = GraphObjectIndex{graph_index, object};
      }
      track.push_back(HistoryEntry{sighting_of_row_[row], static_cast<Index>(row)});
    }
    for (Index view : step_views_) view_slot_[view] = kNone;
  }

  // Empties a track whose last entry is more than max_gap_ before `step`.
  void restart_if_stale(std::vector<HistoryEntry>& track, Index step) {
    if (track.empty() || !(scene_->steps[step].time - time_of(track.back().sighting) > max_gap_)) return;
    track.clear();
    ++output_.restarted_tracks;
  }

  // The track of (view, object) in the current scene, made empty on first use.
  Index track_of(Index view, Index object) {
    const std::uint64_t key = (static_cast<std::uint64_t>(view) << 32) | object;
    const auto [it, inserted] = track_of_key_.try_emplace(key, static_cast<Index>(track_count_));
    if (inserted) {
      if (tracks_.size() <= track_count_) tracks_.emplace_back();
      tracks_[track_count_].clear();
      track_mark_.push_back(0);
      ++track_count_;
    }
    return it->second;
  }

  std::size_t start_graph(Index step, std::string_view view) {
    TrainingGraph& graph = output_.graphs.emplace_back();
    graph.graph.scene = scene_->name;
    graph.graph.view = std::string(view);
    graph.graph.target_time = scene_->steps[step].time;
    if (latest_covariances_) output_.latest_covariances.emplace_back();
    return output_.graphs.size() - 1;
  }

  const Gaussian3& position_of(const HistoryEntry& entry) const {
    return entry.row == kNone ? fused_[entry.sighting] : measurements_[entry.row].position;
  }
  double time_of(Index sighting) const { return scene_->steps[sightings_[sighting].step].time; }

  // Appends the object of `target` (the entry its track gets at this step) to the graph, with the last
  // history_length entries of its track.
  void add_object(std::size_t graph_index, std::span<const HistoryEntry> track, const HistoryEntry& target) {
    const Index sighting = target.sighting;
    const std::span<const HistoryEntry> history = track.last(std::min(track.size(), history_length_));
    TrainingGraph& graph = output_.graphs[graph_index];
    ObjectHistory& object = graph.graph.objects.emplace_back();
    object.object = std::string(objects_.name(sightings_[sighting].object));
    object.positions.reserve(history.size());
    object.times.reserve(history.size());
    for (const HistoryEntry& entry : history) {
      object.positions.push_back(position_of(entry).mean());
      object.times.push_back(time_of(entry.sighting));
    }
    if (latest_covariances_) {
      output_.latest_covariances[graph_index].push_back(position_of(history.back()).covariance());
    }
    if (targets_ == Targets::kNothing) return;
    std::vector<Matrix3d>& covariances = graph.history_covariances.emplace_back();
    covariances.reserve(history.size());
    for (const HistoryEntry& entry : history) covariances.push_back(position_of(entry).covariance());
    if (targets_ == Targets::kMeasured) {
      graph.targets.push_back(position_of(target).mean());
      graph.target_covariances.push_back(position_of(target).covariance());
      return;
    }
    graph.targets.push_back(true_position(sighting, sighting));
    std::vector<Vector3d>& true_history = graph.true_histories.emplace_back();
    true_history.reserve(history.size());
    for (const HistoryEntry& entry : history) true_history.push_back(true_position(entry.sighting, sighting));
  }

  // The truth of `sighting`'s object at its step (looked up once), needed by the graph of `needed_by`.
  const Vector3d& true_position(Index sighting, Index needed_by) {
    if (truth_known_[sighting] == 0) {
      const std::string_view object = objects_.name(sightings_[sighting].object);
      const std::optional<Vector3d> position = truth_->find(scene_->name, time_of(sighting), object);
      if (!position) {
        throw std::invalid_argument("make_training_graphs: no truth for scene '" + scene_->name + "', t " +
                                    format_time(time_of(sighting)) + ", object '" + std::string(object) +
                                    "' (needed by the motion graph of t " + format_time(time_of(needed_by)) +
                                    ")");
      }
      truth_positions_[sighting] = *position;
      truth_known_[sighting] = 1;
    }
    return truth_positions_[sighting];
  }

  [[noreturn]] void throw_duplicate(std::size_t row) const {
    const Measurement& measurement = measurements_[row];
    throw std::invalid_argument("motion graphs: scene '" + measurement.scene + "', t " +
                                format_time(measurement.time) + ": view '" + measurement.view +
                                "' has two rows of object '" + measurement.object + "' in one step");
  }

  std::span<const Measurement> measurements_;
  HistorySource source_;
  std::size_t history_length_;
  double max_gap_;
  Targets targets_;
  const TruthIndex* truth_;
  bool latest_covariances_;
  Output output_;

  // Per row (indexed by row).
  std::vector<Index> object_of_row_, view_of_row_, sighting_of_row_, track_of_row_;

  // Views: ids over all scenes; per view, its slot in the current step (kRawView) and the serial
  // number + 1 of the last sighting it measured (kFused duplicate check; serials unique over scenes).
  NameIds views_;
  std::vector<Index> view_slot_;
  std::vector<std::uint64_t> view_mark_;
  std::uint64_t sighting_serial_base_ = 0;

  // The current scene.
  const Scene* scene_ = nullptr;
  NameIds objects_;
  std::vector<Index> slot_of_object_;  // its sighting at the current step, or kNone
  std::vector<Sighting> sightings_;
  std::vector<Gaussian3> fused_;   // kFused: per sighting
  std::vector<char> truth_known_;  // per sighting
  std::vector<Vector3d> truth_positions_;
  std::vector<std::vector<HistoryEntry>> tracks_;  // the first track_count_ are the scene's
  std::size_t track_count_ = 0;
  std::unordered_map<std::uint64_t, Index> track_of_key_;  // kRawView: (view << 32 | object) → track
  std::vector<Index> track_mark_;                          // kRawView: step + 1 of its last row

  // The current step.
  std::vector<InformationSum> sums_;
  std::vector<Index> object_in_graph_;
  std::vector<Index> step_views_;
  std::vector<Index> rows_with_history_;
  std::vector<std::size_t> graph_of_slot_;
};

}  // namespace

MotionGraphSet make_motion_graph_set(std::span<const Measurement> measurements, HistorySource source,
                                     int history_length, double max_gap) {
  Output output =
      GraphBuilder(measurements, source, history_length, Targets::kNothing, nullptr, true, max_gap).build();
  MotionGraphSet set;
  set.graphs.reserve(output.graphs.size());
  for (TrainingGraph& graph : output.graphs) set.graphs.push_back(std::move(graph.graph));
  set.latest_covariances = std::move(output.latest_covariances);
  set.predictor_of_row = std::move(output.predictor_of_row);
  set.restarted_tracks = output.restarted_tracks;
  return set;
}

std::vector<MotionGraph> make_motion_graphs(std::span<const Measurement> measurements, HistorySource source,
                                            int history_length) {
  return std::move(make_motion_graph_set(measurements, source, history_length).graphs);
}

std::vector<TrainingGraph> make_training_graphs(std::span<const Measurement> measurements,
                                                const TruthIndex& truth, HistorySource source,
                                                int history_length) {
  return GraphBuilder(measurements, source, history_length, Targets::kTruth, &truth, false).build().graphs;
}

std::vector<TrainingGraph> make_measured_training_graphs(std::span<const Measurement> measurements,
                                                         HistorySource source, int history_length) {
  return GraphBuilder(measurements, source, history_length, Targets::kMeasured, nullptr, false)
      .build()
      .graphs;
}

}  // namespace stgf
