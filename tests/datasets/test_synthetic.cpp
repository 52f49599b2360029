// SPDX-License-Identifier: Apache-2.0
// The synthetic benchmark (datasets/synthetic.hpp): motion, views, line-of-sight noise and misses.
//
// The statistical checks use fixed seeds and tolerances derived from the sampling distribution
// (5 standard errors), so they are deterministic and still fail when the model is wrong.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/synthetic.hpp"
#include "support/benchmark_checks.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

constexpr double kPi = portable::kPi;

// ── Helpers ──

using testing::file_bytes;
using testing::kBenchmarkFiles;
using testing::ScratchDirectory;
using testing::splits_of;
using testing::truth_by_key;
using testing::TruthKey;

// The default benchmark, generated once for the tests that only read it.
const Benchmark& default_benchmark() {
  static const Benchmark benchmark = make_synthetic_benchmark(SyntheticOptions{});
  return benchmark;
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
  const std::vector<SyntheticView> views = place_synthetic_views(options);
  ASSERT_EQ(views.size(), 3u);

  for (const auto& [name, split_pointer] : splits_of(benchmark)) {
    const BenchmarkSplit& split = *split_pointer;
    const std::string split_name = name;
    SCOPED_TRACE(split_name);
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
        "synthetic-" + split_name + "-0000", "synthetic-" + split_name + "-0001",
        "synthetic-" + split_name + "-0002", "synthetic-" + split_name + "-0003"};
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
  for (const auto& [name, split] : splits_of(benchmark)) {
    const std::map<TruthKey, Vector3d> truth = truth_by_key(*split);
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
  for (const auto& [name, split] : splits_of(benchmark)) {
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
  for (const auto& [name, split] : splits_of(default_benchmark())) {
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
  for (const auto& [name, split] : splits_of(default_benchmark())) {
    for (const TruthPoint& point : split->truth) {
      ASSERT_LE(point.position.head<2>().cwiseAbs().maxCoeff(), options.area_half_width_m + 1.0);
    }
  }
}

// Fraction of (scene, step, pair of objects) closer than `distance`.
double close_pair_fraction(const Benchmark& benchmark, double distance) {
  long long pairs = 0;
  long long close = 0;
  for (const auto& [name, split] : splits_of(benchmark)) {
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
    for (const auto& [name, split] : splits_of(benchmark)) {
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

}  // namespace
}  // namespace stgf
