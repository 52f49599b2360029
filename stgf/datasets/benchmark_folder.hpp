// SPDX-License-Identifier: Apache-2.0
#pragma once
// A benchmark folder (DESIGN §3), written by every benchmark builder (synthetic and real data):
//
//   DIR/train/measurements.csv   DIR/train/truth.csv
//   DIR/val/measurements.csv     DIR/val/truth.csv
//   DIR/test/measurements.csv    DIR/test/truth.csv
//   DIR/benchmark.json           how it was made (the builder's description) plus "counts"
//
// "counts" holds, per split ("train", "val", "test"), counted over the union of its measurements and
// truth:
//   scenes        distinct scene names
//   steps         distinct (scene, step); times within kSameStepTolerance of a step's earliest time
//                 belong to that step (as core/steps.hpp groups them)
//   objects       distinct (scene, object) pairs — an object id names an object within its scene
//   measurements  measurement rows
//   truth_rows    truth rows
// The writer fills it in (replacing any "counts" the description has), so it always matches the files.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"

namespace stgf {

struct BenchmarkSplit {
  std::vector<Measurement> measurements;
  std::vector<TruthPoint> truth;
};

struct Benchmark {
  BenchmarkSplit train, val, test;
  nlohmann::json description;  // an object: source, seed, views, noise model, ...
};

// The "counts" entry of one split (see above).
nlohmann::json count_split(const BenchmarkSplit& split);

// Writes the folder all or nothing: everything is built in the sibling directory DIR.tmp.<pid> and
// renamed to DIR at the end; on any failure the temporary directory is removed and DIR is left as
// it was. Missing parent directories are created.
//
// If DIR already exists it is replaced only when it holds a benchmark.json (a previous benchmark);
// otherwise std::runtime_error("DIR exists and is not a stgf benchmark folder; remove it or choose
// another --out") before anything is written. std::invalid_argument when `directory` is empty or
// the description is not a JSON object.
void write_benchmark_folder(const std::string& directory, const Benchmark& benchmark);

}  // namespace stgf
