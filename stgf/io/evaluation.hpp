// SPDX-License-Identifier: Apache-2.0
#pragma once
// Scores estimate files against the truth (DESIGN §4): DE, REL-DE and NEES per method, overall
// and by the number of views that saw the object, and each axis's squared error against its stated
// variance (error_by_variance.hpp).
//
// Every method is scored on the same rows. The reference rows are the measurements when given
// (each measured (scene, t, view, object) must have exactly one estimate from every method), or
// else the rows of the first method. A method that misses a reference row, adds a row that is not
// one, or a row without truth is an InputError naming the file and line.
//
// Where scoring starts (ScoringStart), for every method alike — the history a learned method needs
// is left out:
//   from_step K     steps are counted per scene from 0 in time order (distinct times within
//                   1e-6 s); rows of steps k < K are left out.
//   from_time S     rows of scene s with t < t₀(s) + S − 1e-6 s are left out, t₀(s) the scene's
//                   first reference time. Unlike from_step it does not depend on how many distinct
//                   times there are: on asynchronous data (each view on its own clock) every view
//                   adds its own times, so K steps cover about K/n frames for n views. On
//                   synchronous data at period T, from_time K·T leaves out exactly what from_step K
//                   does.
// At most one of the two may be set (std::invalid_argument otherwise).
//
// Scene by scene. SceneScores gives the same numbers, bit for bit, from one scene's rows of every
// file at a time (`stgf eval` reads its files so when they are grouped by scene in one order:
// evaluation_files.hpp). Each method's rows are added up in file order, as evaluate() adds them.

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "stgf/core/error_by_variance.hpp"
#include "stgf/core/metrics.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/truth_file.hpp"

namespace stgf {

struct MethodScore {
  std::string method;
  std::string file;
  ErrorSummary overall;
  std::map<int, ErrorSummary> by_views;  // number of views that saw the object at that step
  // Per axis (x, y, z): the squared error against the stated variance, in octaves of the variance.
  std::array<std::vector<VarianceBin>, 3> by_variance{};
};

struct ScoringStart {
  int from_step = 0;         // K ≥ 0
  double from_time_s = 0.0;  // S ≥ 0, seconds after each scene's first reference time
};

struct Evaluation {
  std::string truth_file;
  std::string measurements_file;  // empty when views were counted from the estimates
  int from_step = 0;
  double from_time_s = 0.0;
  std::size_t rows_excluded = 0;  // reference rows before the start (from_step or from_time_s)
  std::vector<MethodScore> methods;
};

Evaluation evaluate(const TruthFile& truth, const std::vector<EstimateFile>& estimates,
                    const MeasurementFile* measurements, const ScoringStart& start);
// The same, from step `from_step`.
Evaluation evaluate(const TruthFile& truth, const std::vector<EstimateFile>& estimates,
                    const MeasurementFile* measurements, int from_step);

// evaluate(), one scene at a time. It judges only what one scene shows: anything evaluate() would
// reject, or decide from other scenes, makes add() return false, and the caller then evaluates the
// whole files, which reports it as evaluate() always has.
class SceneScores {
 public:
  // The files' paths as given (for the result); `measurements_path` empty when the scored rows are the
  // first method's. Checks `start` as evaluate() does.
  SceneScores(std::string truth_path, std::vector<std::string> estimate_paths, std::string measurements_path,
              const ScoringStart& start);

  // One scene, after the scenes added before: its truth rows, its rows in each estimate file (in the
  // order of the paths), and its measurements (nullptr: scored on the first method's rows). Returns
  // false, and adds nothing more, when the scene has a row evaluate() rejects (an estimate without a
  // reference row or without truth, a reference row without an estimate, a measurement without
  // truth, a method in two files) or a method the first scene did not have.
  bool add(const TruthFile& truth, const std::vector<EstimateFile>& estimates, const MeasurementFile* measurements);

  // The evaluation of the scenes added; nullopt when they hold no method.
  std::optional<Evaluation> result() const;

 private:
  struct Method {
    std::string name;
    std::size_t file = 0;  // index into the estimate paths
    ErrorAccumulator overall;
    std::map<int, ErrorAccumulator> by_views;
    ErrorByVariance by_variance;
  };

  std::vector<std::string> estimate_paths_;
  Evaluation evaluation_;  // everything but the methods' scores
  ScoringStart start_;
  std::vector<Method> methods_;  // in order of first appearance, as evaluate() lists them
  bool first_scene_ = true;
};

}  // namespace stgf
