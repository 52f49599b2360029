// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers for the tests of the benchmark builders (tests/datasets): the files of a benchmark folder,
// the splits of a benchmark by name, the truth of a split by (scene, t, object), and the NEES of the
// raw measurements against it.

#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"

namespace stgf::testing {

// The files of a benchmark folder (write_benchmark_folder), relative to it.
inline const std::vector<std::string> kBenchmarkFiles = {
    "benchmark.json", "train/measurements.csv", "train/truth.csv", "val/measurements.csv",
    "val/truth.csv",  "test/measurements.csv",  "test/truth.csv"};

struct NamedSplit {
  const char* name;  // "train", "val", "test"
  const BenchmarkSplit* split;
};
inline std::vector<NamedSplit> splits_of(const Benchmark& benchmark) {
  return {{"train", &benchmark.train}, {"val", &benchmark.val}, {"test", &benchmark.test}};
}

// The truth positions of a split by (scene, t, object). The builders write a step's measurements and
// truth with the same t, so a measurement finds its truth with its own (scene, time, object).
using TruthKey = std::tuple<std::string, double, std::string>;
inline std::map<TruthKey, Vector3d> truth_by_key(const BenchmarkSplit& split) {
  std::map<TruthKey, Vector3d> truth;
  for (const TruthPoint& point : split.truth) truth[{point.scene, point.time, point.object}] = point.position;
  return truth;
}

// NEES (z − p)ᵀ R⁻¹ (z − p) of every raw measurement against its truth, in row order.
inline std::vector<double> raw_nees(const BenchmarkSplit& split) {
  const std::map<TruthKey, Vector3d> truth = truth_by_key(split);
  std::vector<double> nees;
  for (const Measurement& measurement : split.measurements) {
    const Vector3d& position = truth.at({measurement.scene, measurement.time, measurement.object});
    nees.push_back(measurement.position.mahalanobis_squared(position));
  }
  return nees;
}

// The same for all splits, train, val, test.
inline std::vector<double> raw_nees(const Benchmark& benchmark) {
  std::vector<double> nees;
  for (const auto& [name, split] : splits_of(benchmark)) {
    const std::vector<double> of_split = raw_nees(*split);
    nees.insert(nees.end(), of_split.begin(), of_split.end());
  }
  return nees;
}

inline double mean_of(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double value : values) sum += value;
  return sum / static_cast<double>(values.size());
}

}  // namespace stgf::testing
