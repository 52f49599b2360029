// The synthetic benchmark layer: the portable random source (datasets/random.hpp), the benchmark
// folder writer (datasets/benchmark_folder.hpp) and the synthetic generator (datasets/synthetic.hpp).
//
// The statistical checks use fixed seeds and tolerances derived from the sampling distribution
// (5 standard errors), so they are deterministic and still fail when the model is wrong.

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/synthetic.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/truth_file.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = portable::kPi;

// ── Helpers ──

// A fresh empty directory under the system temporary directory, removed with everything in it.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("stgf-test-datasets-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;

  const fs::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::vector<std::string> entries_of(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

const std::vector<std::string> kBenchmarkFiles = {
    "benchmark.json", "train/measurements.csv", "train/truth.csv", "val/measurements.csv",
    "val/truth.csv",  "test/measurements.csv",  "test/truth.csv"};

// The default benchmark, generated once for the tests that only read it.
const Benchmark& default_benchmark() {
  static const Benchmark benchmark = make_synthetic_benchmark(SyntheticOptions{});
  return benchmark;
}

std::vector<const BenchmarkSplit*> splits_of(const Benchmark& benchmark) {
  return {&benchmark.train, &benchmark.val, &benchmark.test};
}

int step_of(double time, double rate_hz) { return static_cast<int>(std::lround(time * rate_hz)); }

// Truth positions of one split: (scene, object) → position at every step, in step order.
std::map<std::pair<std::string, std::string>, std::vector<Vector3d>> tracks_of(const BenchmarkSplit& split) {
  std::map<std::pair<std::string, std::string>, std::vector<Vector3d>> tracks;
  for (const TruthPoint& point : split.truth) tracks[{point.scene, point.object}].push_back(point.position);
  return tracks;
}

// Ground speeds between consecutive steps of a track (m/s).
std::vector<Eigen::Vector2d> velocities_of(const std::vector<Vector3d>& track, double rate_hz) {
  std::vector<Eigen::Vector2d> velocities;
  for (std::size_t k = 1; k < track.size(); ++k) {
    velocities.push_back((track[k] - track[k - 1]).head<2>() * rate_hz);
  }
  return velocities;
}

bool same_measurement(const Measurement& a, const Measurement& b) {
  return a.scene == b.scene && a.time == b.time && a.view == b.view && a.object == b.object &&
         a.position.mean() == b.position.mean() && a.position.covariance() == b.position.covariance() &&
         a.sensor_position == b.sensor_position;
}

bool same_split(const BenchmarkSplit& a, const BenchmarkSplit& b) {
  if (a.measurements.size() != b.measurements.size() || a.truth.size() != b.truth.size()) return false;
  for (std::size_t k = 0; k < a.measurements.size(); ++k) {
    if (!same_measurement(a.measurements[k], b.measurements[k])) return false;
  }
  for (std::size_t k = 0; k < a.truth.size(); ++k) {
    const TruthPoint& x = a.truth[k];
    const TruthPoint& y = b.truth[k];
    if (x.scene != y.scene || x.time != y.time || x.object != y.object || x.position != y.position)
      return false;
  }
  return true;
}

// ═════════════════════════════ RandomStream and portable math ═════════════════════════════

// splitmix64 is a published function; its first output for state 0 is a well-known constant.
TEST(RandomStream, Splitmix64MatchesTheReferenceValue) { EXPECT_EQ(splitmix64(0), 0xE220A8397B1DCDAFULL); }

// The numbers below were produced by this implementation; they pin the exact bits so that a change
// of engine, seeding, or conversion (or a platform that computes differently) is caught.
TEST(RandomStream, GoldenValuesPinTheBits) {
  RandomStream random(42);
  EXPECT_EQ(random.next_word(), 2576493707698874361ULL);
  EXPECT_EQ(random.uniform01(), 0.9693205787161252);
  EXPECT_EQ(random.uniform(-3.0, 5.0), 4.7615674548518108);
  EXPECT_EQ(random.normal(), -1.0527957142746032);
  EXPECT_EQ(random.normal(), 0.82644805844118496);
  RandomStream child = RandomStream(42).child("train").child(3);
  EXPECT_EQ(child.key(), 13970023401542520869ULL);
  EXPECT_EQ(child.next_word(), 14000241428791717553ULL);
}

TEST(RandomStream, ChildDependsOnKeyAndLabelNotOnDrawsSoFar) {
  RandomStream used(7);
  for (int k = 0; k < 1000; ++k) used.normal();
  RandomStream fresh(7);
  RandomStream from_used = used.child("train");
  RandomStream from_fresh = fresh.child("train");
  for (int k = 0; k < 100; ++k) ASSERT_EQ(from_used.next_word(), from_fresh.next_word());

  const std::set<std::uint64_t> keys = {fresh.child("train").key(),
                                        fresh.child("val").key(),
                                        fresh.child("test").key(),
                                        fresh.child(0).key(),
                                        fresh.child(1).key(),
                                        RandomStream(8).child("train").key(),
                                        fresh.child("train").child(1).key(),
                                        fresh.child(1).child("train").key()};
  EXPECT_EQ(keys.size(), 8u);
}

TEST(RandomStream, UniformHasTheMomentsOfU01) {
  RandomStream random(3);
  constexpr int kDraws = 200000;
  double sum = 0.0;
  double sum_of_squares = 0.0;
  for (int k = 0; k < kDraws; ++k) {
    const double u = random.uniform01();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_of_squares += u * u;
  }
  const double mean = sum / kDraws;
  EXPECT_NEAR(mean, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / kDraws));
  EXPECT_NEAR(sum_of_squares / kDraws - mean * mean, 1.0 / 12.0, 5.0 * std::sqrt(1.0 / 180.0 / kDraws));

  for (int k = 0; k < 1000; ++k) {
    const double x = random.uniform(-2.0, 3.0);
    ASSERT_GE(x, -2.0);
    ASSERT_LT(x, 3.0);
  }
}

TEST(RandomStream, NormalHasTheMomentsOfNZeroOne) {
  RandomStream random(5);
  constexpr int kDraws = 200000;
  double sum = 0.0;
  double sum_of_squares = 0.0;
  double sum_of_fourth_powers = 0.0;
  int within_one = 0;
  for (int k = 0; k < kDraws; ++k) {
    const double x = random.normal();
    sum += x;
    sum_of_squares += x * x;
    sum_of_fourth_powers += x * x * x * x;
    within_one += std::abs(x) < 1.0;
  }
  EXPECT_NEAR(sum / kDraws, 0.0, 5.0 / std::sqrt(kDraws));
  EXPECT_NEAR(sum_of_squares / kDraws, 1.0, 5.0 * std::sqrt(2.0 / kDraws));
  EXPECT_NEAR(sum_of_fourth_powers / kDraws, 3.0, 5.0 * std::sqrt(96.0 / kDraws));  // var of x⁴ = 105 − 9
  const double inside = 0.682689492137;
  EXPECT_NEAR(static_cast<double>(within_one) / kDraws, inside,
              5.0 * std::sqrt(inside * (1 - inside) / kDraws));
}

TEST(RandomStream, BernoulliHasItsProbability) {
  RandomStream random(11);
  constexpr int kDraws = 100000;
  int hits = 0;
  for (int k = 0; k < kDraws; ++k) hits += random.bernoulli(0.3);
  EXPECT_NEAR(static_cast<double>(hits) / kDraws, 0.3, 5.0 * std::sqrt(0.3 * 0.7 / kDraws));
  for (int k = 0; k < 1000; ++k) {
    ASSERT_FALSE(random.bernoulli(0.0));
    ASSERT_TRUE(random.bernoulli(1.0));
  }
}

// The portable functions agree with the C library to a few units in the last place.
TEST(PortableMath, AgreesWithTheCLibrary) {
  constexpr double kUlp = 2.220446049250313e-16;
  for (int k = 0; k <= 20000; ++k) {
    const double x = std::exp(-50.0 + 100.0 * k / 20000.0);
    ASSERT_NEAR(portable::log(x), std::log(x), 4 * kUlp * std::max(1.0, std::abs(std::log(x)))) << x;
    const double y = -60.0 + 120.0 * k / 20000.0;
    ASSERT_NEAR(portable::exp(y), std::exp(y), 4 * kUlp * std::exp(y)) << y;
    const double angle = -200.0 + 400.0 * k / 20000.0;
    const portable::SineCosine sine_cosine = portable::sin_cos(angle);
    ASSERT_NEAR(sine_cosine.sine, std::sin(angle), 4 * kUlp) << angle;
    ASSERT_NEAR(sine_cosine.cosine, std::cos(angle), 4 * kUlp) << angle;
  }
  EXPECT_EQ(portable::log(1.0), 0.0);
  EXPECT_EQ(portable::exp(0.0), 1.0);
  EXPECT_EQ(portable::sin_cos(0.0).sine, 0.0);
  EXPECT_EQ(portable::sin_cos(0.0).cosine, 1.0);
  EXPECT_TRUE(std::isnan(portable::log(-1.0)));
  EXPECT_EQ(portable::exp(-1000.0), 0.0);
  EXPECT_TRUE(std::isinf(portable::exp(1000.0)));
}

// ═════════════════════════════ Synthetic benchmark ═════════════════════════════

SyntheticOptions small_options(std::uint64_t seed) {
  SyntheticOptions options;
  options.seed = seed;
  options.scenes = 2;
  options.steps = 10;
  options.objects = 3;
  options.views = 2;
  return options;
}

TEST(SyntheticBenchmark, SameSeedGivesIdenticalData) {
  const Benchmark first = make_synthetic_benchmark(small_options(5));
  const Benchmark again = make_synthetic_benchmark(small_options(5));
  EXPECT_TRUE(same_split(first.train, again.train));
  EXPECT_TRUE(same_split(first.val, again.val));
  EXPECT_TRUE(same_split(first.test, again.test));
  EXPECT_EQ(first.description, again.description);
}

TEST(SyntheticBenchmark, SameSeedWritesByteIdenticalFolders) {
  SyntheticOptions options;
  options.seed = 99;
  options.scenes = 2;
  ScratchDirectory scratch;
  write_benchmark_folder(scratch / "first", make_synthetic_benchmark(options));
  write_benchmark_folder(scratch / "second", make_synthetic_benchmark(options));
  for (const std::string& file : kBenchmarkFiles) {
    const std::string first = file_bytes(scratch.path() / "first" / file);
    ASSERT_FALSE(first.empty()) << file;
    EXPECT_EQ(first, file_bytes(scratch.path() / "second" / file)) << file;
  }
}

// Exact bits of the last rows of the default benchmark (the end of 50 steps × 5 substeps of coupled
// motion, where any difference in rounding has grown), as produced by GCC 12 -O0, -O3 and
// -O3 -march=native (FMA) and Clang 14 -O2 -march=native. A platform or compiler that breaks the
// "same seed, same files everywhere" promise fails here; a deliberate change of the model updates
// the numbers.
TEST(SyntheticBenchmark, GoldenRowsAreTheSameOnEveryPlatform) {
  const Benchmark& benchmark = default_benchmark();
  EXPECT_EQ(benchmark.train.measurements.size(), 10262u);
  EXPECT_EQ(benchmark.val.measurements.size(), 10235u);
  EXPECT_EQ(benchmark.test.measurements.size(), 10314u);
  const TruthPoint& truth = benchmark.test.truth.back();
  EXPECT_EQ(truth.scene, "synthetic-test-0009");
  EXPECT_EQ(truth.object, "o5");
  EXPECT_EQ(truth.time, 4.9000000000000004);
  EXPECT_EQ(truth.position.x(), -5.0127950789314459);
  EXPECT_EQ(truth.position.y(), 10.825724914912);
  const Measurement& measurement = benchmark.test.measurements.back();
  EXPECT_EQ(measurement.view, "v3");
  EXPECT_EQ(measurement.object, "o5");
  EXPECT_EQ(measurement.position.mean().x(), -5.6604066684578438);
  EXPECT_EQ(measurement.position.mean().y(), 11.665171088531997);
  EXPECT_EQ(measurement.position.mean().z(), -0.067620584965560199);
  EXPECT_EQ(measurement.position.covariance()(0, 1), -0.29927573956411851);
}

TEST(SyntheticBenchmark, DifferentSeedGivesDifferentData) {
  const Benchmark first = make_synthetic_benchmark(small_options(5));
  const Benchmark other = make_synthetic_benchmark(small_options(6));
  EXPECT_FALSE(same_split(first.train, other.train));
  EXPECT_FALSE(same_split(first.val, other.val));
  EXPECT_FALSE(same_split(first.test, other.test));
  EXPECT_NE(first.train.truth.front().position, other.train.truth.front().position);
  EXPECT_NE(first.description["views"], other.description["views"]);
}

TEST(SyntheticBenchmark, SplitsAndScenesAreIndependentStreams) {
  const Benchmark& benchmark = default_benchmark();
  // Scene 0 of train and of val start differently; so do scenes 0 and 1 of train.
  EXPECT_NE(benchmark.train.truth.front().position, benchmark.val.truth.front().position);
  const SyntheticOptions options;
  const std::size_t scene_rows = static_cast<std::size_t>(options.steps * options.objects);
  EXPECT_NE(benchmark.train.truth[0].position, benchmark.train.truth[scene_rows].position);

  // The number of views does not change the trajectories.
  SyntheticOptions more_views;
  more_views.views = 6;
  more_views.scenes = 1;
  const Benchmark with_six = make_synthetic_benchmark(more_views);
  ASSERT_EQ(with_six.train.truth.size(), scene_rows);
  for (std::size_t k = 0; k < scene_rows; ++k) {
    ASSERT_EQ(with_six.train.truth[k].position, benchmark.train.truth[k].position);
  }
}

TEST(SyntheticBenchmark, CountsNamesAndTimesMatchTheOptions) {
  SyntheticOptions options;
  options.objects = 5;
  options.views = 3;
  options.steps = 20;
  options.scenes = 4;
  options.rate_hz = 7.0;
  const Benchmark benchmark = make_synthetic_benchmark(options);
  const std::vector<std::string> split_names = {"train", "val", "test"};
  const std::vector<const BenchmarkSplit*> splits = splits_of(benchmark);
  const std::vector<SyntheticView> views = place_synthetic_views(options);
  ASSERT_EQ(views.size(), 3u);

  for (std::size_t s = 0; s < splits.size(); ++s) {
    const BenchmarkSplit& split = *splits[s];
    SCOPED_TRACE(split_names[s]);
    ASSERT_EQ(split.truth.size(), static_cast<std::size_t>(options.scenes * options.steps * options.objects));

    std::set<std::string> scenes;
    std::set<std::tuple<std::string, int, std::string>> truth_keys;
    for (const TruthPoint& point : split.truth) {
      scenes.insert(point.scene);
      const int step = step_of(point.time, options.rate_hz);
      ASSERT_GE(step, 0);
      ASSERT_LT(step, options.steps);
      ASSERT_NEAR(point.time, step / options.rate_hz, 1e-12);
      ASSERT_EQ(point.position.z(), 0.0);
      truth_keys.emplace(point.scene, step, point.object);
    }
    EXPECT_EQ(truth_keys.size(), split.truth.size()) << "every object at every step, once";
    const std::set<std::string> expected_scenes = {
        "synthetic-" + split_names[s] + "-0000", "synthetic-" + split_names[s] + "-0001",
        "synthetic-" + split_names[s] + "-0002", "synthetic-" + split_names[s] + "-0003"};
    EXPECT_EQ(scenes, expected_scenes);

    std::set<std::string> objects;
    std::set<std::string> view_ids;
    for (const Measurement& measurement : split.measurements) {
      const int step = step_of(measurement.time, options.rate_hz);
      ASSERT_TRUE(truth_keys.count({measurement.scene, step, measurement.object}))
          << measurement.scene << " " << measurement.time << " " << measurement.object;
      objects.insert(measurement.object);
      view_ids.insert(measurement.view);
      const SyntheticView& view = views[static_cast<std::size_t>(std::stoi(measurement.view.substr(1)))];
      ASSERT_EQ(measurement.view, view.id);
      ASSERT_TRUE(measurement.sensor_position.has_value());
      ASSERT_EQ(*measurement.sensor_position, view.sensor_position);
    }
    EXPECT_EQ(objects, (std::set<std::string>{"o0", "o1", "o2", "o3", "o4"}));
    EXPECT_EQ(view_ids, (std::set<std::string>{"v0", "v1", "v2"}));

    const nlohmann::json counts = count_split(split);
    EXPECT_EQ(counts["scenes"], options.scenes);
    EXPECT_EQ(counts["steps"], options.scenes * options.steps);
    EXPECT_EQ(counts["objects"], options.scenes * options.objects);
    EXPECT_EQ(counts["measurements"], split.measurements.size());
    EXPECT_EQ(counts["truth_rows"], split.truth.size());
  }
}

TEST(SyntheticBenchmark, RowsAreSortedBySceneStepViewObject) {
  const BenchmarkSplit& split = default_benchmark().train;
  const auto key = [](const Measurement& m) {
    return std::make_tuple(m.scene, m.time, std::stoi(m.view.substr(1)), std::stoi(m.object.substr(1)));
  };
  for (std::size_t k = 1; k < split.measurements.size(); ++k) {
    ASSERT_LT(key(split.measurements[k - 1]), key(split.measurements[k])) << "row " << k;
  }
  const auto truth_key = [](const TruthPoint& p) {
    return std::make_tuple(p.scene, p.time, std::stoi(p.object.substr(1)));
  };
  for (std::size_t k = 1; k < split.truth.size(); ++k) {
    ASSERT_LT(truth_key(split.truth[k - 1]), truth_key(split.truth[k])) << "row " << k;
  }
}

// z − p ~ N(0, R) exactly, so the NEES of the raw measurements is χ²₃: mean 3, variance 6, and 95%
// of the values inside the two-sided 95% interval [0.2158, 9.3484].
TEST(SyntheticBenchmark, RawMeasurementErrorsMatchTheirCovariance) {
  const Benchmark& benchmark = default_benchmark();
  double nees_sum = 0.0;
  int inside = 0;
  int count = 0;
  Eigen::Vector3d error_sum = Eigen::Vector3d::Zero();
  for (const BenchmarkSplit* split : splits_of(benchmark)) {
    std::map<std::tuple<std::string, double, std::string>, Vector3d> truth;
    for (const TruthPoint& point : split->truth)
      truth[{point.scene, point.time, point.object}] = point.position;
    for (const Measurement& measurement : split->measurements) {
      const Vector3d& true_position = truth.at({measurement.scene, measurement.time, measurement.object});
      const double nees = measurement.position.mahalanobis_squared(true_position);
      nees_sum += nees;
      inside += nees > 0.2157953 && nees < 9.3484036;
      // Whitened error: each component N(0, 1) when R is right, so a bias shows up here.
      const Eigen::LLT<Matrix3d> cholesky(measurement.position.covariance());
      error_sum += cholesky.matrixL().solve(measurement.position.mean() - true_position);
      ++count;
    }
  }
  ASSERT_GT(count, 10000);
  const double standard_error = std::sqrt(6.0 / count);
  EXPECT_NEAR(nees_sum / count, 3.0, 5.0 * standard_error);
  EXPECT_NEAR(static_cast<double>(inside) / count, 0.95, 5.0 * std::sqrt(0.95 * 0.05 / count));
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(error_sum(axis) / count, 0.0, 5.0 / std::sqrt(count));
}

// Hand-computed case: sensor at the origin at ground level, object 20 m along x, g = 1:
//   σ_r = 0.05 + 5e-4·400 = 0.25,  σ_c = 0.03 + 0.005·20 = 0.13,  σ_v = 0.03 + 0.004·20 = 0.11
// and the line of sight is x, so R = diag(0.25², 0.13², 0.11²).
TEST(SyntheticNoise, HandComputedLineOfSightCovariance) {
  const SyntheticOptions options;
  const SyntheticView view{"v0", Vector3d(0.0, 0.0, 0.0), 1.0};
  const LineOfSightNoise noise = line_of_sight_noise(options, view, Vector3d(20.0, 0.0, 0.0));
  EXPECT_DOUBLE_EQ(noise.range, 20.0);
  EXPECT_NEAR(noise.standard_deviations(0), 0.25, 1e-15);
  EXPECT_NEAR(noise.standard_deviations(1), 0.13, 1e-15);
  EXPECT_NEAR(noise.standard_deviations(2), 0.11, 1e-15);
  const Matrix3d expected = Vector3d(0.0625, 0.0169, 0.0121).asDiagonal();
  EXPECT_LT((noise.covariance() - expected).cwiseAbs().maxCoeff(), 1e-15);
}

// From a raised sensor: U is orthonormal with u_r along the line of sight and u_c horizontal;
// square_root() is a square root of R; the eigenvalues of R are the σ²; R grows with range and is
// longest along the range.
TEST(SyntheticNoise, LineOfSightFrameAndSquareRoot) {
  SyntheticOptions options;
  const SyntheticView view{"v3", Vector3d(-25.0, 10.0, 6.0), 1.2};
  const Vector3d target(4.0, -3.0, 0.0);
  const LineOfSightNoise noise = line_of_sight_noise(options, view, target);
  const Matrix3d& basis = noise.basis;
  EXPECT_LT((basis.transpose() * basis - Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((basis.col(0) - (target - view.sensor_position).normalized()).norm(), 1e-14);
  EXPECT_EQ(basis(2, 1), 0.0);
  EXPECT_GT(basis(2, 2), 0.0) << "u_v points up";

  const Matrix3d covariance = noise.covariance();
  EXPECT_EQ(covariance, covariance.transpose()) << "exactly symmetric";
  const Matrix3d root = noise.square_root();
  EXPECT_LT((root * root.transpose() - covariance).cwiseAbs().maxCoeff(), 1e-14);
  Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(covariance);
  Eigen::Vector3d variances = noise.standard_deviations.cwiseAbs2();
  std::sort(variances.data(), variances.data() + 3);
  EXPECT_LT((eigen.eigenvalues() - variances).cwiseAbs().maxCoeff(), 1e-14);

  const double range = noise.range;
  EXPECT_NEAR(noise.standard_deviations(0), 1.2 * (0.05 + 5e-4 * range * range), 1e-14);
  EXPECT_GT(noise.standard_deviations(0), noise.standard_deviations(1)) << "stereo-like: worst along range";
  const LineOfSightNoise nearer = line_of_sight_noise(options, view, Vector3d(-15.0, 5.0, 0.0));
  EXPECT_LT(nearer.covariance().trace(), covariance.trace());
}

TEST(SyntheticNoise, DetectionProbabilityFallsWithRange) {
  const SyntheticOptions options;
  EXPECT_DOUBLE_EQ(detection_probability(options, 0.0), options.detection_probability_near);
  EXPECT_DOUBLE_EQ(detection_probability(options, options.max_range_m), options.detection_probability_far);
  EXPECT_GT(detection_probability(options, 10.0), detection_probability(options, 30.0));
  EXPECT_EQ(detection_probability(options, options.max_range_m + 0.001), 0.0);
}

TEST(SyntheticBenchmark, SomeMeasurementsAreMissedButMostObjectsAreSeen) {
  const SyntheticOptions options;
  const Benchmark& benchmark = default_benchmark();
  std::size_t measurements = 0;
  std::size_t object_steps = 0;
  std::set<std::tuple<std::string, double, std::string>> seen;
  for (const BenchmarkSplit* split : splits_of(benchmark)) {
    measurements += split->measurements.size();
    object_steps += split->truth.size();
    for (const Measurement& m : split->measurements) seen.emplace(m.scene, m.time, m.object);
  }
  const std::size_t every_view_every_object = object_steps * static_cast<std::size_t>(options.views);
  EXPECT_LT(measurements, every_view_every_object);
  EXPECT_GT(static_cast<double>(measurements), 0.7 * static_cast<double>(every_view_every_object));
  EXPECT_GT(static_cast<double>(seen.size()), 0.97 * static_cast<double>(object_steps))
      << "almost every object is seen by at least one view";
  EXPECT_LT(seen.size(), object_steps + 1);
}

TEST(SyntheticBenchmark, ObjectsTurnStopAndWalkOn) {
  const SyntheticOptions options;
  int tracks = 0;
  int tracks_that_turn = 0;
  int tracks_that_stop = 0;
  int stops_then_walks = 0;
  for (const BenchmarkSplit* split : splits_of(default_benchmark())) {
    for (const auto& [key, track] : tracks_of(*split)) {
      ++tracks;
      bool turned = false;
      bool stopped = false;
      bool walked_after_stop = false;
      std::optional<double> first_heading;
      for (const Eigen::Vector2d& velocity : velocities_of(track, options.rate_hz)) {
        const double speed = velocity.norm();
        ASSERT_LT(speed, options.max_speed_m_s + options.avoidance_speed_m_s + 0.1) << "no teleporting";
        if (speed < 0.05) stopped = true;
        if (stopped && speed > 0.5) walked_after_stop = true;
        if (speed > 0.3) {
          const double heading = std::atan2(velocity.y(), velocity.x());
          if (!first_heading) first_heading = heading;
          if (std::abs(std::remainder(heading - *first_heading, 2.0 * kPi)) > kPi / 4.0) turned = true;
        }
      }
      tracks_that_turn += turned;
      tracks_that_stop += stopped;
      stops_then_walks += walked_after_stop;
    }
  }
  EXPECT_GT(tracks_that_turn, tracks * 3 / 10) << "headings change by more than 45° within a scene";
  EXPECT_LT(tracks_that_turn, tracks) << "but not every path is a circle";
  EXPECT_GT(tracks_that_stop, tracks / 10);
  EXPECT_GT(stops_then_walks, 0);
}

TEST(SyntheticBenchmark, ObjectsStayInTheArea) {
  const SyntheticOptions options;
  for (const BenchmarkSplit* split : splits_of(default_benchmark())) {
    for (const TruthPoint& point : split->truth) {
      ASSERT_LE(point.position.head<2>().cwiseAbs().maxCoeff(), options.area_half_width_m + 1.0);
    }
  }
}

// Fraction of (scene, step, pair of objects) closer than `distance`.
double close_pair_fraction(const Benchmark& benchmark, double distance) {
  long long pairs = 0;
  long long close = 0;
  for (const BenchmarkSplit* split : splits_of(benchmark)) {
    std::map<std::pair<std::string, double>, std::vector<Vector3d>> frames;
    for (const TruthPoint& point : split->truth) frames[{point.scene, point.time}].push_back(point.position);
    for (const auto& [key, positions] : frames) {
      for (std::size_t i = 0; i < positions.size(); ++i) {
        for (std::size_t j = i + 1; j < positions.size(); ++j) {
          ++pairs;
          close += (positions[i] - positions[j]).norm() < distance;
        }
      }
    }
  }
  return static_cast<double>(close) / static_cast<double>(pairs);
}

// A crowded scene: with avoidance, objects almost never come within 0.5 m; without it they do
// (which shows that the first number is the avoidance's doing, not emptiness).
TEST(SyntheticBenchmark, ObjectsAvoidEachOther) {
  SyntheticOptions crowded;
  crowded.objects = 20;
  crowded.views = 1;
  crowded.scenes = 2;
  const double with_avoidance = close_pair_fraction(make_synthetic_benchmark(crowded), 0.5);
  crowded.avoidance_radius_m = 0.0;
  const double without_avoidance = close_pair_fraction(make_synthetic_benchmark(crowded), 0.5);
  EXPECT_LT(with_avoidance, 1e-4);
  EXPECT_GT(without_avoidance, 5.0 * with_avoidance + 1e-4);
}

// Rates are per second: the walking speed is the same at 5 Hz and at 25 Hz.
TEST(SyntheticBenchmark, MotionDoesNotDependOnTheFrameRate) {
  const auto mean_speed = [](double rate_hz) {
    SyntheticOptions options;
    options.rate_hz = rate_hz;
    options.steps = static_cast<int>(5.0 * rate_hz);
    options.views = 1;
    options.scenes = 4;
    const Benchmark benchmark = make_synthetic_benchmark(options);
    double sum = 0.0;
    int count = 0;
    for (const BenchmarkSplit* split : splits_of(benchmark)) {
      for (const auto& [key, track] : tracks_of(*split)) {
        for (const Eigen::Vector2d& velocity : velocities_of(track, rate_hz)) {
          sum += velocity.norm();
          ++count;
        }
      }
    }
    return sum / count;
  };
  const double slow = mean_speed(5.0);
  const double fast = mean_speed(25.0);
  EXPECT_GT(slow, 0.8);
  EXPECT_LT(slow, 1.4);
  EXPECT_NEAR(slow, fast, 0.1);
}

TEST(SyntheticViews, PlacedAroundTheScene) {
  SyntheticOptions options;
  options.views = 6;
  const std::vector<SyntheticView> views = place_synthetic_views(options);
  ASSERT_EQ(views.size(), 6u);
  std::vector<double> angles;
  for (std::size_t k = 0; k < views.size(); ++k) {
    const SyntheticView& view = views[k];
    std::string expected_id = "v";
    expected_id += std::to_string(k);  // (not "v" + …: GCC 12 warns falsely about it, -Wrestrict)
    EXPECT_EQ(view.id, expected_id);
    const double radius = view.sensor_position.head<2>().norm();
    EXPECT_GE(radius, options.view_ring_radius_m - options.view_ring_jitter_m);
    EXPECT_LE(radius, options.view_ring_radius_m + options.view_ring_jitter_m);
    EXPECT_GE(view.sensor_position.z(), options.min_sensor_height_m);
    EXPECT_LE(view.sensor_position.z(), options.max_sensor_height_m);
    EXPECT_GE(view.noise_scale, options.min_noise_scale);
    EXPECT_LE(view.noise_scale, options.max_noise_scale);
    angles.push_back(std::atan2(view.sensor_position.y(), view.sensor_position.x()));
  }
  // Consecutive views are 2π/6 apart up to the jitter: they surround the scene.
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const double gap = std::remainder(angles[(k + 1) % angles.size()] - angles[k], 2.0 * kPi);
    EXPECT_NEAR(gap, 2.0 * kPi / 6.0, 2.0 * options.view_angle_jitter_rad + 1e-12);
  }

  const nlohmann::json description = describe_synthetic_benchmark(options, views);
  EXPECT_EQ(description["source"], "synthetic");
  EXPECT_EQ(description["seed"], options.seed);
  EXPECT_EQ(description["options"]["range_noise_per_m2"], options.range_noise_per_m2);
  ASSERT_EQ(description["views"].size(), 6u);
  EXPECT_EQ(description["views"][2]["id"], "v2");
  EXPECT_EQ(description["views"][2]["sensor_position"][2], views[2].sensor_position.z());
  EXPECT_EQ(description["views"][2]["noise_scale"], views[2].noise_scale);
}

TEST(SyntheticOptionsValidation, InvalidOptionsAreRejectedByName) {
  const auto rejects = [](auto change, const std::string& name) {
    SyntheticOptions options;
    change(options);
    try {
      make_synthetic_benchmark(options);
      ADD_FAILURE() << name << " was accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  };
  rejects([](SyntheticOptions& o) { o.objects = 0; }, "objects");
  rejects([](SyntheticOptions& o) { o.views = 0; }, "views");
  rejects([](SyntheticOptions& o) { o.steps = 1; }, "steps");
  rejects([](SyntheticOptions& o) { o.scenes = 0; }, "scenes");
  rejects([](SyntheticOptions& o) { o.rate_hz = 0.0; }, "rate_hz");
  rejects([](SyntheticOptions& o) { o.rate_hz = std::nan(""); }, "rate_hz");
  rejects([](SyntheticOptions& o) { o.min_speed_m_s = 2.0; }, "min_speed_m_s");
  rejects([](SyntheticOptions& o) { o.boundary_margin_m = 20.0; }, "boundary_margin_m");
  rejects([](SyntheticOptions& o) { o.turn_rate_correlation_s = 0.0; }, "turn_rate_correlation_s");
  rejects([](SyntheticOptions& o) { o.range_noise_m = 0.0; }, "range_noise_m");
  rejects([](SyntheticOptions& o) { o.cross_noise_per_m = -1.0; }, "cross_noise_per_m");
  rejects([](SyntheticOptions& o) { o.detection_probability_near = 1.5; }, "detection_probability_near");
  rejects([](SyntheticOptions& o) { o.max_stop_s = std::numeric_limits<double>::infinity(); }, "max_stop_s");

  SyntheticOptions smallest;
  smallest.objects = 1;
  smallest.views = 1;
  smallest.steps = 2;
  smallest.scenes = 1;
  smallest.rate_hz = 0.5;
  const Benchmark benchmark = make_synthetic_benchmark(smallest);
  EXPECT_EQ(benchmark.test.truth.size(), 2u);
}

// ═════════════════════════════ Benchmark folder ═════════════════════════════

TEST(BenchmarkFolder, WritesTheLayoutTheReadersAccept) {
  ScratchDirectory scratch;
  const Benchmark benchmark = make_synthetic_benchmark(small_options(4));
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

  const std::vector<std::string> split_names = {"train", "val", "test"};
  const std::vector<const BenchmarkSplit*> splits = splits_of(benchmark);
  for (std::size_t s = 0; s < splits.size(); ++s) {
    const MeasurementFile measurements =
        read_measurements(directory + "/" + split_names[s] + "/measurements.csv");
    const TruthFile truth = read_truth(directory + "/" + split_names[s] + "/truth.csv");
    EXPECT_NO_THROW(check_truth_matches(measurements, truth));
    ASSERT_EQ(measurements.rows.size(), splits[s]->measurements.size());
    ASSERT_EQ(truth.rows.size(), splits[s]->truth.size());
    EXPECT_TRUE(measurements.has_sensor_positions);
    const Measurement& written = splits[s]->measurements.back();
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
  write_benchmark_folder(directory, make_synthetic_benchmark(small_options(1)));
  const Benchmark second = make_synthetic_benchmark(small_options(2));
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
    write_benchmark_folder(directory, make_synthetic_benchmark(small_options(1)));
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
  EXPECT_THROW(write_benchmark_folder(file, make_synthetic_benchmark(small_options(1))), std::runtime_error);
  EXPECT_EQ(file_bytes(file), "x");
}

// A failure after the temporary folder is filled (here: a description that is not valid UTF-8, so
// benchmark.json, written last, cannot be produced) leaves neither a temporary folder nor a
// half-written benchmark, and a previous benchmark stays as it was.
TEST(BenchmarkFolder, FailureLeavesNoTraceAndKeepsThePreviousBenchmark) {
  ScratchDirectory scratch;
  const std::string directory = scratch / "bench";
  Benchmark broken = make_synthetic_benchmark(small_options(3));
  broken.description["note"] = std::string("\xff\xfe not UTF-8");

  EXPECT_ANY_THROW(write_benchmark_folder(directory, broken));
  EXPECT_TRUE(entries_of(scratch.path()).empty());

  write_benchmark_folder(directory, make_synthetic_benchmark(small_options(1)));
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
  split.measurements.push_back({"a", 0.0, "v0", "o0", z, std::nullopt});
  split.measurements.push_back({"a", 0.0000004, "v1", "o0", z, std::nullopt});  // same step
  split.measurements.push_back({"a", 0.1, "v0", "o1", z, std::nullopt});
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
