// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/benchmark_folder.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "stgf/io/measurement_file.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/truth_file.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDescriptionFile = "benchmark.json";

// "out/bench//" → "out/bench", so that the sibling temporary directory is a sibling, not a child.
std::string without_trailing_separators(std::string directory) {
  while (directory.size() > 1 && directory.back() == '/') directory.pop_back();
  return directory;
}

// Removes a directory tree when destroyed, unless released.
class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(fs::path path) : path_(std::move(path)) {}
  ~TemporaryDirectory() {
    if (released_) return;
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const fs::path& path() const { return path_; }
  void release() { released_ = true; }

 private:
  fs::path path_;
  bool released_ = false;
};

// Distinct steps of one scene: sorted times, a new step whenever a time is more than
// kSameStepTolerance after the current step's earliest time.
long long count_steps(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  long long steps = 0;
  double step_start = 0.0;
  for (const double time : times) {
    if (steps == 0 || time - step_start > kSameStepTolerance) {
      ++steps;
      step_start = time;
    }
  }
  return steps;
}

void write_split(const fs::path& directory, const BenchmarkSplit& split) {
  fs::create_directory(directory);
  write_measurements((directory / "measurements.csv").string(), split.measurements);
  write_truth((directory / "truth.csv").string(), split.truth);
}

// Moves the finished temporary directory to `target`, replacing a previous benchmark there. A
// directory cannot be renamed over a non-empty one, so the previous benchmark is first moved aside
// and put back if the second rename fails.
void move_into_place(const fs::path& finished, const fs::path& target, bool replace) {
  if (!replace) {
    fs::rename(finished, target);
    return;
  }
  const fs::path previous = target.string() + ".old." + std::to_string(::getpid());
  std::error_code ignored;
  fs::remove_all(previous, ignored);
  fs::rename(target, previous);
  try {
    fs::rename(finished, target);
  } catch (...) {
    fs::rename(previous, target, ignored);
    throw;
  }
  fs::remove_all(previous, ignored);
}

}  // namespace

nlohmann::json count_split(const BenchmarkSplit& split) {
  std::set<std::string> scenes;
  std::map<std::string, std::vector<double>> times_by_scene;
  std::set<std::pair<std::string, std::string>> objects;
  for (const Measurement& measurement : split.measurements) {
    scenes.insert(measurement.scene);
    times_by_scene[measurement.scene].push_back(measurement.time);
    objects.emplace(measurement.scene, measurement.object);
  }
  for (const TruthPoint& point : split.truth) {
    scenes.insert(point.scene);
    times_by_scene[point.scene].push_back(point.time);
    objects.emplace(point.scene, point.object);
  }
  long long steps = 0;
  for (auto& [scene, times] : times_by_scene) steps += count_steps(std::move(times));
  return {{"scenes", scenes.size()},
          {"steps", steps},
          {"objects", objects.size()},
          {"measurements", split.measurements.size()},
          {"truth_rows", split.truth.size()}};
}

void write_benchmark_folder(const std::string& directory, const Benchmark& benchmark) {
  const std::string name = without_trailing_separators(directory);
  if (name.empty()) throw std::invalid_argument("benchmark folder: the output directory is empty");
  if (!benchmark.description.is_object()) {
    throw std::invalid_argument("benchmark folder: the description must be a JSON object");
  }
  const fs::path target(name);

  const bool replace = fs::exists(target);
  if (replace && !(fs::is_directory(target) && fs::exists(target / kDescriptionFile))) {
    throw std::runtime_error(name +
                             " exists and is not a stgf benchmark folder; remove it or choose another --out");
  }
  if (target.has_parent_path()) fs::create_directories(target.parent_path());

  TemporaryDirectory temporary(name + ".tmp." + std::to_string(::getpid()));
  std::error_code ignored;
  fs::remove_all(temporary.path(), ignored);  // left over by a crashed run with the same pid
  fs::create_directory(temporary.path());

  write_split(temporary.path() / "train", benchmark.train);
  write_split(temporary.path() / "val", benchmark.val);
  write_split(temporary.path() / "test", benchmark.test);

  nlohmann::json description = benchmark.description;
  description["counts"] = {{"train", count_split(benchmark.train)},
                           {"val", count_split(benchmark.val)},
                           {"test", count_split(benchmark.test)}};
  // Written last: a folder with a benchmark.json is a complete benchmark.
  write_text_file((temporary.path() / kDescriptionFile).string(), description.dump(2) + "\n");

  move_into_place(temporary.path(), target, replace);
  temporary.release();
}

}  // namespace stgf
