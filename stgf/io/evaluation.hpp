#pragma once
// Scores estimate files against the truth (DESIGN §4): DE, REL-DE and NEES per method, overall
// and by the number of views that saw the object.
//
// Every method is scored on the same rows. The reference rows are the measurements when given
// (each measured (scene, t, view, object) must have exactly one estimate from every method), or
// else the rows of the first method. A method that misses a reference row, adds a row that is not
// one, or a row without truth is an InputError naming the file and line. Steps are counted per
// scene from 0 in time order; rows of steps before `from_step` are left out for every method (the
// history a learned method needs).

#include <map>
#include <string>
#include <vector>

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
};

struct Evaluation {
  std::string truth_file;
  std::string measurements_file;  // empty when views were counted from the estimates
  int from_step = 0;
  std::size_t rows_excluded = 0;  // reference rows before from_step
  std::vector<MethodScore> methods;
};

Evaluation evaluate(const TruthFile& truth, const std::vector<EstimateFile>& estimates,
                    const MeasurementFile* measurements, int from_step);

}  // namespace stgf
