// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include <fmt/format.h>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

// The steps of each scene: its distinct times (within 1e-6 s), sorted.
class StepTimes {
 public:
  void add(const std::string& scene, double time) { times_[scene].push_back(time); }

  void finish() {
    for (auto& [scene, times] : times_) {
      std::sort(times.begin(), times.end());
      std::vector<double> steps;
      for (double time : times) {
        if (steps.empty() || time - steps.back() > kSameStepTolerance) steps.push_back(time);
      }
      times = std::move(steps);
    }
  }

  std::optional<int> step_of(const std::string& scene, double time) const {
    const auto it = times_.find(scene);
    if (it == times_.end()) return std::nullopt;
    const std::vector<double>& steps = it->second;
    auto candidate = std::lower_bound(steps.begin(), steps.end(), time - kSameStepTolerance);
    if (candidate == steps.end() || *candidate > time + kSameStepTolerance) return std::nullopt;
    return static_cast<int>(candidate - steps.begin());
  }

  // The scene's first step time (the scene must have one).
  double first_time(const std::string& scene) const { return times_.at(scene).front(); }

 private:
  std::unordered_map<std::string, std::vector<double>> times_;
};

struct ReferenceRow {
  int views = 0;                         // views that saw the object at this step
  std::optional<Vector3d> sensor;        // of the row's view
  bool excluded = false;                 // before the scoring start
  std::string description;               // for messages
  std::size_t order = 0;                 // position in the reference rows
};

std::string row_key(const std::string& scene, int step, const std::string& view, const std::string& object) {
  return fmt::format("{}\n{}\n{}\n{}", scene, step, view, object);
}

// The reference rows and their step times, from the measurements or from the first method's rows.
template <class Rows, class Describe>
void build_reference(const Rows& rows, const Describe& describe, const ScoringStart& start, StepTimes& steps,
                     std::unordered_map<std::string, ReferenceRow>& reference, std::size_t& excluded) {
  for (const auto& row : rows) steps.add(row.scene, row.time);
  steps.finish();
  std::unordered_map<std::string, int> views_of_object;
  std::vector<std::string> keys;
  keys.reserve(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& row = rows[k];
    const int step = *steps.step_of(row.scene, row.time);
    keys.push_back(row_key(row.scene, step, row.view, row.object));
    ++views_of_object[fmt::format("{}\n{}\n{}", row.scene, step, row.object)];
    ReferenceRow& entry = reference[keys.back()];
    entry.excluded = step < start.from_step ||
                     row.time < steps.first_time(row.scene) + start.from_time_s - kSameStepTolerance;
    entry.description = describe(k);
    entry.order = k;
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& row = rows[k];
    const int step = *steps.step_of(row.scene, row.time);
    ReferenceRow& entry = reference[keys[k]];
    entry.views = views_of_object[fmt::format("{}\n{}\n{}", row.scene, step, row.object)];
    if (entry.excluded) ++excluded;
  }
}

void check_scoring_start(const ScoringStart& start) {
  if (start.from_step < 0) throw std::invalid_argument("--from-step must be >= 0");
  if (!std::isfinite(start.from_time_s) || start.from_time_s < 0.0) {
    throw std::invalid_argument(
        fmt::format("--from-time must be a finite number of seconds >= 0 (got {})", start.from_time_s));
  }
  if (start.from_step > 0 && start.from_time_s > 0.0) {
    throw std::invalid_argument("--from-step and --from-time exclude each other: give one of them");
  }
}

}  // namespace

Evaluation evaluate(const TruthFile& truth, const std::vector<EstimateFile>& estimates,
                    const MeasurementFile* measurements, int from_step) {
  return evaluate(truth, estimates, measurements, ScoringStart{from_step, 0.0});
}

Evaluation evaluate(const TruthFile& truth, const std::vector<EstimateFile>& estimates,
                    const MeasurementFile* measurements, const ScoringStart& start) {
  if (estimates.empty()) throw std::invalid_argument("evaluate: no estimate file");
  check_scoring_start(start);
  Evaluation evaluation;
  evaluation.truth_file = truth.path;
  evaluation.from_step = start.from_step;
  evaluation.from_time_s = start.from_time_s;
  const TruthIndex truth_index(truth);

  // Methods by name, each from one file.
  struct MethodRows {
    const EstimateFile* file;
    std::vector<std::size_t> rows;
  };
  std::vector<std::pair<std::string, MethodRows>> methods;
  for (const EstimateFile& file : estimates) {
    for (std::size_t k = 0; k < file.rows.size(); ++k) {
      auto it = std::find_if(methods.begin(), methods.end(),
                             [&](const auto& entry) { return entry.first == file.methods[k]; });
      if (it == methods.end()) {
        methods.push_back({file.methods[k], MethodRows{&file, {}}});
        it = methods.end() - 1;
      } else if (it->second.file != &file) {
        throw InputError(file.path, file.lines[k],
                         fmt::format("method '{}' already comes from {}", file.methods[k], it->second.file->path));
      }
      it->second.rows.push_back(k);
    }
  }
  if (methods.empty()) throw InputError(estimates.front().path, 0, "no estimates");

  StepTimes steps;
  std::unordered_map<std::string, ReferenceRow> reference;
  if (measurements != nullptr) {
    check_truth_matches(*measurements, truth);
    evaluation.measurements_file = measurements->path;
    build_reference(
        measurements->rows,
        [&](std::size_t k) { return fmt::format("{}:{}", measurements->path, measurements->lines[k]); },
        start, steps, reference, evaluation.rows_excluded);
    for (std::size_t k = 0; k < measurements->rows.size(); ++k) {
      const Measurement& row = measurements->rows[k];
      reference[row_key(row.scene, *steps.step_of(row.scene, row.time), row.view, row.object)].sensor =
          row.sensor_position;
    }
  } else {
    const EstimateFile& first = *methods.front().second.file;
    std::vector<Estimate> first_rows;
    for (std::size_t k : methods.front().second.rows) first_rows.push_back(first.rows[k]);
    build_reference(
        first_rows,
        [&](std::size_t k) {
          return fmt::format("{}:{}", first.path, first.lines[methods.front().second.rows[k]]);
        },
        start, steps, reference, evaluation.rows_excluded);
  }

  for (const auto& [method, method_rows] : methods) {
    const EstimateFile& file = *method_rows.file;
    MethodScore score{method, file.path, {}, {}, {}};
    ErrorAccumulator overall;
    std::map<int, ErrorAccumulator> by_views;
    ErrorByVariance by_variance;
    std::unordered_map<std::string, bool> seen;
    for (std::size_t k : method_rows.rows) {
      const Estimate& row = file.rows[k];
      const auto fail = [&](const std::string& what) { throw InputError(file.path, file.lines[k], what); };
      const std::optional<int> step = steps.step_of(row.scene, row.time);
      const std::string key = step ? row_key(row.scene, *step, row.view, row.object) : std::string();
      const auto entry = step ? reference.find(key) : reference.end();
      if (entry == reference.end()) {
        fail(fmt::format("estimate for scene '{}', t {}, view '{}', object '{}' has no matching {}", row.scene,
                         row.time, row.view, row.object,
                         measurements ? "measurement in " + measurements->path : "row in the first method"));
      }
      seen[key] = true;
      const std::optional<Vector3d> truth_position = truth_index.find(row.scene, row.time, row.object);
      if (!truth_position) {
        fail(fmt::format("no truth for scene '{}', t {}, object '{}' in {}", row.scene, row.time, row.object,
                         truth.path));
      }
      if (entry->second.excluded) continue;
      overall.add(row.position, *truth_position, entry->second.sensor);
      by_views[entry->second.views].add(row.position, *truth_position, entry->second.sensor);
      by_variance.add(row.position, *truth_position);
    }
    if (seen.size() != reference.size()) {
      const ReferenceRow* first_missing = nullptr;
      for (const auto& [key, entry] : reference) {
        if (!seen.count(key) && (first_missing == nullptr || entry.order < first_missing->order)) {
          first_missing = &entry;
        }
      }
      throw InputError(file.path, 0,
                       fmt::format("method '{}' has no estimate for the row at {}", method, first_missing->description));
    }
    score.overall = overall.summary();
    for (const auto& [views, accumulator] : by_views) score.by_views[views] = accumulator.summary();
    score.by_variance = by_variance.bins();
    evaluation.methods.push_back(std::move(score));
  }
  return evaluation;
}

SceneScores::SceneScores(std::string truth_path, std::vector<std::string> estimate_paths,
                         std::string measurements_path, const ScoringStart& start)
    : estimate_paths_(std::move(estimate_paths)), start_(start) {
  check_scoring_start(start);
  evaluation_.truth_file = std::move(truth_path);
  evaluation_.measurements_file = std::move(measurements_path);
  evaluation_.from_step = start.from_step;
  evaluation_.from_time_s = start.from_time_s;
}

bool SceneScores::add(const TruthFile& truth, const std::vector<EstimateFile>& estimates,
                      const MeasurementFile* measurements) {
  // Each method's rows of the scene, in file order. Methods come in the order evaluate() finds them:
  // by file, then row. The first scene must show them all (in a later one, a new method could have
  // come earlier in evaluate()'s order, and lacks the earlier scenes' rows anyway).
  std::vector<std::vector<std::size_t>> rows_of(methods_.size());
  for (std::size_t file = 0; file < estimates.size(); ++file) {
    for (std::size_t k = 0; k < estimates[file].rows.size(); ++k) {
      const std::string& name = estimates[file].methods[k];
      auto method = std::find_if(methods_.begin(), methods_.end(), [&](const Method& m) { return m.name == name; });
      if (method == methods_.end()) {
        if (!first_scene_) return false;
        methods_.push_back(Method{name, file, {}, {}, {}});
        rows_of.emplace_back();
        method = methods_.end() - 1;
      } else if (method->file != file) {
        return false;  // one method from two files
      }
      rows_of[static_cast<std::size_t>(method - methods_.begin())].push_back(k);
    }
  }
  first_scene_ = false;
  if (methods_.empty()) return false;

  const TruthIndex truth_index(truth);
  StepTimes steps;
  std::unordered_map<std::string, ReferenceRow> reference;
  // Messages are evaluate()'s to write: nothing here describes a row.
  const auto undescribed = [](std::size_t) { return std::string(); };
  if (measurements != nullptr) {
    for (const Measurement& row : measurements->rows) {
      if (!truth_index.find(row.scene, row.time, row.object)) return false;
    }
    build_reference(measurements->rows, undescribed, start_, steps, reference, evaluation_.rows_excluded);
    for (const Measurement& row : measurements->rows) {
      reference[row_key(row.scene, *steps.step_of(row.scene, row.time), row.view, row.object)].sensor =
          row.sensor_position;
    }
  } else {
    const EstimateFile& first = estimates[methods_.front().file];
    std::vector<Estimate> first_rows;
    for (std::size_t k : rows_of.front()) first_rows.push_back(first.rows[k]);
    build_reference(first_rows, undescribed, start_, steps, reference, evaluation_.rows_excluded);
  }

  for (std::size_t m = 0; m < methods_.size(); ++m) {
    Method& method = methods_[m];
    const EstimateFile& file = estimates[method.file];
    std::unordered_map<std::string, bool> seen;
    for (std::size_t k : rows_of[m]) {
      const Estimate& row = file.rows[k];
      const std::optional<int> step = steps.step_of(row.scene, row.time);
      if (!step) return false;
      const std::string key = row_key(row.scene, *step, row.view, row.object);
      const auto entry = reference.find(key);
      if (entry == reference.end()) return false;
      seen[key] = true;
      const std::optional<Vector3d> truth_position = truth_index.find(row.scene, row.time, row.object);
      if (!truth_position) return false;
      if (entry->second.excluded) continue;
      method.overall.add(row.position, *truth_position, entry->second.sensor);
      method.by_views[entry->second.views].add(row.position, *truth_position, entry->second.sensor);
      method.by_variance.add(row.position, *truth_position);
    }
    if (seen.size() != reference.size()) return false;
  }
  return true;
}

std::optional<Evaluation> SceneScores::result() const {
  if (methods_.empty()) return std::nullopt;
  Evaluation evaluation = evaluation_;
  for (const Method& method : methods_) {
    MethodScore score{method.name, estimate_paths_.at(method.file), method.overall.summary(), {},
                      method.by_variance.bins()};
    for (const auto& [views, accumulator] : method.by_views) score.by_views[views] = accumulator.summary();
    evaluation.methods.push_back(std::move(score));
  }
  return evaluation;
}

}  // namespace stgf
