// SPDX-License-Identifier: Apache-2.0
// The benchmark folder writer (datasets/benchmark_folder.hpp), on small synthetic benchmarks: the
// layout the readers accept, replacing a previous benchmark all or nothing, and the counts.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/synthetic.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/truth_file.hpp"
#include "support/benchmark_checks.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using testing::entries_of;
using testing::file_bytes;
using testing::kBenchmarkFiles;
using testing::ScratchDirectory;
using testing::splits_of;

// A small synthetic benchmark: 2 scenes per split of 10 steps, 3 objects, 2 views.
Benchmark small_benchmark(std::uint64_t seed) {
  return make_synthetic_benchmark({.seed = seed, .objects = 3, .views = 2, .steps = 10, .scenes = 2});
}

TEST(BenchmarkFolder, WritesTheLayoutTheReadersAccept) {
  ScratchDirectory scratch;
  const Benchmark benchmark = small_benchmark(4);
  const std::string directory = scratch / "nested/bench";  // missing parents are created
  write_benchmark_folder(directory, benchmark);

  EXPECT_EQ(entries_of(directory), (std::vector<std::string>{"benchmark.json", "test", "train", "val"}));
  EXPECT_EQ(entries_of(scratch.path() / "nested"), std::vector<std::string>{"bench"}) << "no temporary left";

  const nlohmann::json description =
      nlohmann::json::parse(file_bytes(fs::path(directory) / "benchmark.json"));
  EXPECT_EQ(description["source"], "synthetic");
  EXPECT_EQ(description["seed"], 4);
  EXPECT_EQ(description["counts"]["val"], count_split(benchmark.val));
  EXPECT_EQ(description["counts"]["test"]["truth_rows"], 2 * 10 * 3);

  for (const auto& [name, split] : splits_of(benchmark)) {
    const MeasurementFile measurements = read_measurements(directory + "/" + name + "/measurements.csv");
    const TruthFile truth = read_truth(directory + "/" + name + "/truth.csv");
    EXPECT_NO_THROW(check_truth_matches(measurements, truth));
    ASSERT_EQ(measurements.rows.size(), split->measurements.size());
    ASSERT_EQ(truth.rows.size(), split->truth.size());
    EXPECT_TRUE(measurements.has_sensor_positions);
    const Measurement& written = split->measurements.back();
    const Measurement& read = measurements.rows.back();
    EXPECT_EQ(read.scene, written.scene);
    EXPECT_EQ(read.view, written.view);
    EXPECT_LT((read.position.mean() - written.position.mean()).norm(), 1e-9);
    EXPECT_LT((read.position.covariance() - written.position.covariance()).norm(),
              1e-8 * written.position.covariance().norm());
  }
}

TEST(BenchmarkFolder, ReplacesAPreviousBenchmark) {
  ScratchDirectory scratch;
  const std::string directory = scratch / "bench";
  write_benchmark_folder(directory, small_benchmark(1));
  const Benchmark second = small_benchmark(2);
  write_benchmark_folder(directory + "/", second);  // a trailing separator names the same folder

  const nlohmann::json description =
      nlohmann::json::parse(file_bytes(fs::path(directory) / "benchmark.json"));
  EXPECT_EQ(description["seed"], 2);
  EXPECT_EQ(read_truth(directory + "/train/truth.csv").rows.front().position.x(),
            std::stod(format_position(second.train.truth.front().position.x())));
  EXPECT_EQ(entries_of(scratch.path()), std::vector<std::string>{"bench"}) << "nothing left beside it";
}

TEST(BenchmarkFolder, RefusesADirectoryThatIsNotABenchmark) {
  ScratchDirectory scratch;
  const std::string directory = scratch / "photos";
  fs::create_directory(directory);
  { std::ofstream(fs::path(directory) / "holiday.jpg") << "precious"; }
  try {
    write_benchmark_folder(directory, small_benchmark(1));
    FAIL() << "an unrelated directory was overwritten";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()),
              directory + " exists and is not a stgf benchmark folder; remove it or choose another --out");
  }
  EXPECT_EQ(entries_of(directory), std::vector<std::string>{"holiday.jpg"});
  EXPECT_EQ(file_bytes(fs::path(directory) / "holiday.jpg"), "precious");
  EXPECT_EQ(entries_of(scratch.path()), std::vector<std::string>{"photos"});

  const std::string file = scratch / "a-file";
  { std::ofstream(file) << "x"; }
  EXPECT_THROW(write_benchmark_folder(file, small_benchmark(1)), std::runtime_error);
  EXPECT_EQ(file_bytes(file), "x");
}

// A failure after the temporary folder is filled (here: a description that is not valid UTF-8, so
// benchmark.json, written last, cannot be produced) leaves neither a temporary folder nor a
// half-written benchmark, and a previous benchmark stays as it was.
TEST(BenchmarkFolder, FailureLeavesNoTraceAndKeepsThePreviousBenchmark) {
  ScratchDirectory scratch;
  const std::string directory = scratch / "bench";
  Benchmark broken = small_benchmark(3);
  broken.description["note"] = std::string("\xff\xfe not UTF-8");

  EXPECT_ANY_THROW(write_benchmark_folder(directory, broken));
  EXPECT_TRUE(entries_of(scratch.path()).empty());

  write_benchmark_folder(directory, small_benchmark(1));
  std::map<std::string, std::string> before;
  for (const std::string& file : kBenchmarkFiles) before[file] = file_bytes(fs::path(directory) / file);
  EXPECT_ANY_THROW(write_benchmark_folder(directory, broken));
  EXPECT_EQ(entries_of(scratch.path()), std::vector<std::string>{"bench"});
  for (const std::string& file : kBenchmarkFiles)
    EXPECT_EQ(file_bytes(fs::path(directory) / file), before[file]);
}

TEST(BenchmarkFolder, CountsStepsWithinTheTimeTolerance) {
  BenchmarkSplit split;
  const Gaussian3 z = Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity());
  split.measurements.push_back({"a", 0.0, "v0", "o0", z, std::nullopt, std::nullopt});
  split.measurements.push_back({"a", 0.0000004, "v1", "o0", z, std::nullopt, std::nullopt});  // same step
  split.measurements.push_back({"a", 0.1, "v0", "o1", z, std::nullopt, std::nullopt});
  split.truth.push_back({"a", 0.2, "o0", Vector3d::Zero()});
  split.truth.push_back({"b", 0.0, "o0", Vector3d::Zero()});
  const nlohmann::json counts = count_split(split);
  EXPECT_EQ(counts["scenes"], 2);
  EXPECT_EQ(counts["steps"], 4);    // a: 0, 0.1, 0.2; b: 0
  EXPECT_EQ(counts["objects"], 3);  // a/o0, a/o1, b/o0
  EXPECT_EQ(counts["measurements"], 3);
  EXPECT_EQ(counts["truth_rows"], 2);
}

}  // namespace
}  // namespace stgf
