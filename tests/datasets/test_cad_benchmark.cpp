// SPDX-License-Identifier: Apache-2.0
// The cad benchmark built from KITTI tracking (datasets/cad_benchmark.hpp).
//
// Small benchmarks (40 / 20 / 40 instances) with fixed seeds. The statistical checks use tolerances
// of 5 standard errors of the sampled statistic (for a χ²₃ NEES: variance 6 per row; for a squared
// standard normal: variance 2), so they are deterministic and still fail when the model is wrong.
// KITTI is not in the repository (licence): every test skips when STGF_KITTI_DIR does not exist.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/cad_benchmark.hpp"
#include "stgf/datasets/kitti_tracking.hpp"
#include "stgf/io/input_error.hpp"
#include "support/benchmark_checks.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using testing::file_bytes;
using testing::kBenchmarkFiles;
using testing::NamedSplit;
using testing::ScratchDirectory;
using testing::splits_of;
using testing::truth_by_key;
using testing::TruthKey;

const char* const kKittiDirectory = STGF_KITTI_DIR;
constexpr double kPi = portable::kPi;

#define SKIP_WITHOUT_KITTI()                                                                        \
  do {                                                                                              \
    if (!fs::is_directory(kKittiDirectory)) GTEST_SKIP() << "no KITTI data at " << kKittiDirectory; \
  } while (false)

// ── Helpers ──

CadOptions small_options() {
  CadOptions options;
  options.seed = 11;
  options.source_directory = kKittiDirectory;
  options.train_instances = 40;
  options.val_instances = 20;
  options.test_instances = 40;
  return options;
}

CadOptions without_gps_error() {
  CadOptions options = small_options();
  options.gps_position_error_m = 0.0;
  options.gps_heading_error_deg = 0.0;
  return options;
}

CadOptions always_detecting() {
  CadOptions options = without_gps_error();
  options.detection_probability_near = 1.0;
  options.detection_probability_far = 1.0;
  return options;
}

// Built once per test program run.
const Benchmark& default_benchmark() {
  static const Benchmark benchmark = make_cad_benchmark(small_options());
  return benchmark;
}
const Benchmark& benchmark_without_gps_error() {
  static const Benchmark benchmark = make_cad_benchmark(without_gps_error());
  return benchmark;
}
const Benchmark& benchmark_always_detecting() {
  static const Benchmark benchmark = make_cad_benchmark(always_detecting());
  return benchmark;
}

int frame_of(double time) { return static_cast<int>(std::lround(time * 10.0)); }

// "cad-<split>-NNNN"
std::string scene_name(const std::string& split, int index) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", index);
  return "cad-" + split + "-" + number;
}

// The vehicle entries of one instance in benchmark.json, by scene.
std::map<std::string, nlohmann::json> instances_by_scene(const Benchmark& benchmark,
                                                         const std::string& split) {
  std::map<std::string, nlohmann::json> instances;
  for (const nlohmann::json& instance : benchmark.description.at("splits").at(split).at("instance_list")) {
    instances[instance.at("scene").get<std::string>()] = instance;
  }
  return instances;
}

// ── Tests ──

TEST(CadBenchmark, SameSeedSameFilesOtherSeedOtherFiles) {
  SKIP_WITHOUT_KITTI();
  const ScratchDirectory scratch;
  write_benchmark_folder(scratch / "first", default_benchmark());
  write_benchmark_folder(scratch / "second", make_cad_benchmark(small_options()));
  for (const std::string& file : kBenchmarkFiles) {
    EXPECT_EQ(file_bytes(scratch / ("first/" + file)), file_bytes(scratch / ("second/" + file))) << file;
  }
  CadOptions other = small_options();
  other.seed = 12;
  write_benchmark_folder(scratch / "other", make_cad_benchmark(other));
  EXPECT_NE(file_bytes(scratch / "first/test/measurements.csv"),
            file_bytes(scratch / "other/test/measurements.csv"));
  EXPECT_NE(file_bytes(scratch / "first/train/truth.csv"), file_bytes(scratch / "other/train/truth.csv"));
}

TEST(CadBenchmark, CountsAndShapeMatchTheOptions) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = small_options();
  const Benchmark& benchmark = default_benchmark();
  const std::map<std::string, int> instances = {
      {"train", options.train_instances}, {"val", options.val_instances}, {"test", options.test_instances}};
  for (const auto& [name, split] : splits_of(benchmark)) {
    SCOPED_TRACE(name);
    const int count = instances.at(name);
    // Truth: every instance has `objects` objects at `steps` steps 0.1 s apart.
    std::map<std::string, std::set<double>> times;
    std::map<std::string, std::map<std::string, int>> object_rows;
    for (const TruthPoint& point : split->truth) {
      times[point.scene].insert(point.time);
      ++object_rows[point.scene][point.object];
    }
    ASSERT_EQ(static_cast<int>(times.size()), count);
    for (int k = 0; k < count; ++k) {
      const std::string scene = scene_name(name, k);
      ASSERT_EQ(times.count(scene), 1u) << scene;
      ASSERT_EQ(static_cast<int>(times[scene].size()), options.steps);
      EXPECT_NEAR(*times[scene].rbegin() - *times[scene].begin(), 0.1 * (options.steps - 1), 1e-9);
      ASSERT_EQ(static_cast<int>(object_rows[scene].size()), options.objects);
      for (const auto& [object, rows] : object_rows[scene]) EXPECT_EQ(rows, options.steps) << object;
    }
    EXPECT_EQ(static_cast<int>(split->truth.size()), count * options.steps * options.objects);

    // Measurements: known views, at most max_vehicles per instance, each of a truth row, unique.
    const std::map<TruthKey, Vector3d> truth = truth_by_key(*split);
    const std::map<std::string, nlohmann::json> described = instances_by_scene(benchmark, name);
    std::set<std::tuple<std::string, double, std::string, std::string>> seen;
    std::map<std::string, std::set<std::string>> views;
    for (const Measurement& measurement : split->measurements) {
      EXPECT_EQ(truth.count({measurement.scene, measurement.time, measurement.object}), 1u);
      EXPECT_TRUE(
          seen.insert({measurement.scene, measurement.time, measurement.view, measurement.object}).second);
      EXPECT_TRUE(measurement.sensor_position.has_value());
      views[measurement.scene].insert(measurement.view);
    }
    for (const auto& [scene, scene_views] : views) {
      const nlohmann::json& vehicles = described.at(scene).at("vehicles");
      EXPECT_LE(vehicles.size(), static_cast<std::size_t>(options.max_vehicles));
      EXPECT_GE(vehicles.size(), static_cast<std::size_t>(options.min_vehicles));
      std::set<std::string> listed;
      for (const nlohmann::json& vehicle : vehicles) listed.insert(vehicle.at("view").get<std::string>());
      for (const std::string& view : scene_views) EXPECT_EQ(listed.count(view), 1u) << scene << " " << view;
    }

    // Sorted by (scene, t, view, object) and (scene, t, object).
    EXPECT_TRUE(std::is_sorted(split->measurements.begin(), split->measurements.end(),
                               [](const Measurement& a, const Measurement& b) {
                                 return std::tie(a.scene, a.time, a.view, a.object) <
                                        std::tie(b.scene, b.time, b.view, b.object);
                               }));
    EXPECT_TRUE(std::is_sorted(
        split->truth.begin(), split->truth.end(), [](const TruthPoint& a, const TruthPoint& b) {
          return std::tie(a.scene, a.time, a.object) < std::tie(b.scene, b.time, b.object);
        }));

    // The description agrees with the files.
    const nlohmann::json& entry = benchmark.description.at("splits").at(name);
    EXPECT_EQ(entry.at("instances").get<int>(), count);
    EXPECT_EQ(entry.at("instance_list").size(), static_cast<std::size_t>(count));
    int histogram_total = 0;
    for (const auto& [vehicles, number] : entry.at("vehicles_per_instance").items()) {
      EXPECT_LE(std::stoi(vehicles), options.max_vehicles);
      histogram_total += number.get<int>();
    }
    EXPECT_EQ(histogram_total, count);
    EXPECT_EQ(entry.at("eligible_windows").get<int>() +
                  entry.at("rejected_windows").at("too_few_vehicles").get<int>() +
                  entry.at("rejected_windows").at("too_few_objects").get<int>(),
              entry.at("candidate_windows").get<int>());
    for (const auto& [scene, instance] : described) {
      EXPECT_EQ(instance.at("vehicles").at(0).at("track"), "ego");
      std::set<std::string> objects(instance.at("objects").begin(), instance.at("objects").end());
      std::set<std::string> in_truth;
      for (const auto& [object, rows] : object_rows[scene]) in_truth.insert(object);
      EXPECT_EQ(objects, in_truth) << scene;
      for (const nlohmann::json& vehicle : instance.at("vehicles")) {
        EXPECT_EQ(objects.count(vehicle.at("track").get<std::string>()), 0u) << "a vehicle is also an object";
      }
    }
  }
  EXPECT_EQ(benchmark.description.at("seed").get<std::uint64_t>(), options.seed);
  EXPECT_DOUBLE_EQ(benchmark.description.at("options").at("gps_heading_error_deg").get<double>(),
                   options.gps_heading_error_deg);
}

TEST(CadBenchmark, SplitsAreDisjointBySequence) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = small_options();
  const std::map<std::string, std::vector<std::string>> assigned = {
      {"train", options.train_sequences}, {"val", options.val_sequences}, {"test", options.test_sequences}};
  std::map<std::string, std::string> owner;  // sequence → split that used it
  for (const auto& [name, split] : splits_of(default_benchmark())) {
    for (const TruthPoint& point : split->truth) {
      const std::string sequence = point.object.substr(0, point.object.find('-'));
      const std::vector<std::string>& allowed = assigned.at(name);
      EXPECT_NE(std::find(allowed.begin(), allowed.end(), sequence), allowed.end())
          << name << " " << point.object;
      const auto [it, fresh] = owner.emplace(sequence, name);
      EXPECT_EQ(it->second, name) << sequence << " used by " << it->second << " and " << name;
    }
  }
  EXPECT_GE(owner.size(), 3u);

  CadOptions overlapping = options;
  overlapping.test_sequences.push_back(overlapping.train_sequences.front());
  try {
    validate_cad_options(overlapping);
    ADD_FAILURE() << "overlapping splits accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(overlapping.train_sequences.front()), std::string::npos)
        << error.what();
  }
}

// Without GPS error z − p ~ N(0, R) exactly, so (z − p)ᵀ R⁻¹ (z − p) is χ²₃: mean 3, variance 6.
TEST(CadBenchmark, RawNeesIsThreeWithoutGpsError) {
  SKIP_WITHOUT_KITTI();
  double sum = 0.0;
  int inside = 0;
  std::size_t rows = 0;
  for (const auto& [name, split] : splits_of(benchmark_without_gps_error())) {
    for (const double nees : testing::raw_nees(*split)) {
      sum += nees;
      if (nees >= 0.2158 && nees <= 9.3484) ++inside;  // two-sided 95% interval of χ²₃
      ++rows;
    }
  }
  ASSERT_GT(rows, 2000u);
  const double n = static_cast<double>(rows);
  EXPECT_NEAR(sum / n, 3.0, 5.0 * std::sqrt(6.0 / n));
  EXPECT_NEAR(inside / n, 0.95, 5.0 * std::sqrt(0.95 * 0.05 / n));
}

// With GPS error the raw NEES is far above 3; undoing exactly the documented map
// p' = s + δc + Rz(δψ)(p − s) with the errors recorded in benchmark.json brings it back to 3, and R is
// the sensor's line-of-sight covariance rotated by the heading error.
TEST(CadBenchmark, GpsErrorIsTheDocumentedRigidMapAndNotInR) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = small_options();
  const Benchmark& benchmark = default_benchmark();
  double raw = 0.0;
  double corrected = 0.0;
  std::size_t rows = 0;
  for (const auto& [name, split] : splits_of(benchmark)) {
    const std::map<TruthKey, Vector3d> truth = truth_by_key(*split);
    const std::map<std::string, nlohmann::json> described = instances_by_scene(benchmark, name);
    for (const Measurement& measurement : split->measurements) {
      const Vector3d& p = truth.at({measurement.scene, measurement.time, measurement.object});
      raw += measurement.position.mahalanobis_squared(p);
      const nlohmann::json& vehicle =
          described.at(measurement.scene).at("vehicles").at(std::stoi(measurement.view.substr(1)));
      ASSERT_EQ(vehicle.at("view"), measurement.view);
      const Vector3d offset(vehicle.at("gps_position_error_m").at(0).get<double>(),
                            vehicle.at("gps_position_error_m").at(1).get<double>(), 0.0);
      const double heading = vehicle.at("gps_heading_error_deg").get<double>() * kPi / 180.0;
      const Vector3d reported = *measurement.sensor_position;
      const Vector3d sensor = reported - offset;
      const Vector3d lever = p - sensor;
      const Vector3d displaced =
          reported + Vector3d(std::cos(heading) * lever.x() - std::sin(heading) * lever.y(),
                              std::sin(heading) * lever.x() + std::cos(heading) * lever.y(), lever.z());
      corrected += measurement.position.mahalanobis_squared(displaced);
      ++rows;

      // R is the vehicle's own line-of-sight covariance rotated by its reported heading: Rz R_true Rzᵀ.
      const CadSensorNoise noise = cad_sensor_noise(options, sensor, p);
      const Matrix3d root = noise.basis * noise.standard_deviations.asDiagonal();
      Matrix3d turn;
      turn << std::cos(heading), -std::sin(heading), 0.0, std::sin(heading), std::cos(heading), 0.0, 0.0, 0.0,
          1.0;
      const Matrix3d expected = turn * (root * root.transpose()) * turn.transpose();
      EXPECT_LT((measurement.position.covariance() - expected).norm(), 1e-9 * expected.norm())
          << measurement.scene << " " << measurement.view;
    }
  }
  const double n = static_cast<double>(rows);
  EXPECT_GT(raw / n, 10.0);  // ≈ 50 at full size with the defaults (0.3 m, 0.5°)
  EXPECT_NEAR(corrected / n, 3.0, 5.0 * std::sqrt(6.0 / n));
}

// σ_d = a + b r² along the line of sight and σ = r σ_θ across it, in R and in the errors drawn.
TEST(CadBenchmark, DepthVarianceGrowsWithRange) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = without_gps_error();
  double normalised_sum = 0.0;
  std::size_t rows = 0;
  double near_sum = 0.0;
  double far_sum = 0.0;
  int near_rows = 0;
  int far_rows = 0;
  for (const auto& [name, split] : splits_of(benchmark_without_gps_error())) {
    const std::map<TruthKey, Vector3d> truth = truth_by_key(*split);
    for (const Measurement& measurement : split->measurements) {
      const Vector3d& p = truth.at({measurement.scene, measurement.time, measurement.object});
      const Vector3d offset = p - *measurement.sensor_position;
      const double range = offset.norm();
      const Vector3d along = offset / range;
      const Vector3d across = Vector3d(-along.y(), along.x(), 0.0).normalized();
      const Matrix3d& covariance = measurement.position.covariance();
      const double depth_sigma = options.depth_noise_m + options.depth_noise_per_m2 * range * range;
      EXPECT_NEAR(along.dot(covariance * along), depth_sigma * depth_sigma, 1e-9 * depth_sigma * depth_sigma);
      const double across_sigma = range * options.lateral_angle_noise_rad;
      EXPECT_NEAR(across.dot(covariance * across), across_sigma * across_sigma,
                  1e-9 * depth_sigma * depth_sigma);
      EXPECT_LE(range, options.max_range_m);

      const double depth_error = along.dot(measurement.position.mean() - p);
      normalised_sum += depth_error * depth_error / (depth_sigma * depth_sigma);
      ++rows;
      if (range < 15.0) {
        near_sum += depth_error * depth_error;
        ++near_rows;
      } else if (range > 30.0) {
        far_sum += depth_error * depth_error;
        ++far_rows;
      }
    }
  }
  const double n = static_cast<double>(rows);
  EXPECT_NEAR(normalised_sum / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  ASSERT_GT(near_rows, 100);
  ASSERT_GT(far_rows, 100);
  // σ_d(15 m) = 0.16 m, σ_d(30 m) = 0.5 m: far depth errors are (much) more than 4 times the variance.
  EXPECT_GT(far_sum / far_rows, 4.0 * (near_sum / near_rows));
}

// Misses: with P_d = 1 every visible object is measured; with the defaults the number of rows is the
// sum of P_d(r) over those, within 5 standard deviations of a sum of Bernoulli draws.
TEST(CadBenchmark, MissesHappenAsOftenAsTheModelSays) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = without_gps_error();
  std::size_t all_rows = 0;
  std::size_t kept_rows = 0;
  double expected = 0.0;
  double variance = 0.0;
  for (const NamedSplit& always : splits_of(benchmark_always_detecting())) {
    const std::map<TruthKey, Vector3d> truth = truth_by_key(*always.split);
    for (const Measurement& measurement : always.split->measurements) {
      const double range =
          (truth.at({measurement.scene, measurement.time, measurement.object}) - *measurement.sensor_position)
              .norm();
      const double probability = cad_detection_probability(options, range);
      expected += probability;
      variance += probability * (1.0 - probability);
      ++all_rows;
    }
  }
  std::set<std::tuple<std::string, double, std::string, std::string>> visible;
  for (const NamedSplit& always : splits_of(benchmark_always_detecting())) {
    for (const Measurement& m : always.split->measurements)
      visible.insert({m.scene, m.time, m.view, m.object});
  }
  for (const NamedSplit& sometimes : splits_of(benchmark_without_gps_error())) {
    for (const Measurement& m : sometimes.split->measurements) {
      EXPECT_EQ(visible.count({m.scene, m.time, m.view, m.object}), 1u) << "measured but not visible";
      ++kept_rows;
    }
  }
  EXPECT_LT(kept_rows, all_rows);
  EXPECT_NEAR(static_cast<double>(kept_rows), expected, 5.0 * std::sqrt(variance));
  EXPECT_DOUBLE_EQ(cad_detection_probability(options, 0.0), options.detection_probability_near);
  EXPECT_DOUBLE_EQ(cad_detection_probability(options, options.max_range_m),
                   options.detection_probability_far);
  EXPECT_EQ(cad_detection_probability(options, options.max_range_m + 0.01), 0.0);
}

// The selection criterion: with P_d = 1, every object is measured by some vehicle in at least
// ⌈min_visible_fraction · steps⌉ steps of its instance.
TEST(CadBenchmark, ObjectsAreSeenMostOfTheTime) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = always_detecting();
  const int needed = static_cast<int>(std::ceil(options.min_visible_fraction * options.steps - 1e-9));
  for (const auto& [name, split] : splits_of(benchmark_always_detecting())) {
    std::map<std::pair<std::string, std::string>, std::set<double>> seen_at;  // (scene, object) → times
    for (const Measurement& m : split->measurements) seen_at[{m.scene, m.object}].insert(m.time);
    std::set<std::pair<std::string, std::string>> objects;
    for (const TruthPoint& point : split->truth) objects.insert({point.scene, point.object});
    for (const auto& key : objects) {
      EXPECT_GE(static_cast<int>(seen_at[key].size()), needed)
          << name << " " << key.first << " " << key.second;
    }
  }
}

// Sensors sit on the vehicles named in benchmark.json: the ego's reference camera, the other cars'
// box bottom centre + sensor_height_m; every measured object is within range and field of view;
// the other vehicles move.
TEST(CadBenchmark, SensorsSitOnTheConnectedVehicles) {
  SKIP_WITHOUT_KITTI();
  const CadOptions options = without_gps_error();
  const Benchmark& benchmark = benchmark_without_gps_error();
  std::map<std::string, KittiSequence> sequences;
  const auto sequence_named = [&](const std::string& name) -> const KittiSequence& {
    auto it = sequences.find(name);
    if (it == sequences.end()) it = sequences.emplace(name, load_kitti_sequence(kKittiDirectory, name)).first;
    return it->second;
  };
  const double half_fov_cosine = std::cos(options.field_of_view_deg * kPi / 360.0);
  std::size_t checked = 0;
  for (const auto& [name, split] : splits_of(benchmark)) {
    const std::map<TruthKey, Vector3d> truth = truth_by_key(*split);
    const std::map<std::string, nlohmann::json> described = instances_by_scene(benchmark, name);
    for (const Measurement& measurement : split->measurements) {
      const nlohmann::json& instance = described.at(measurement.scene);
      const std::string sequence_name = instance.at("sequence").get<std::string>();
      const KittiSequence& sequence = sequence_named(sequence_name);
      const int frame = frame_of(measurement.time);
      const KittiFrame& kitti_frame = sequence.frames.at(static_cast<std::size_t>(frame));
      const std::string track = instance.at("vehicles").at(std::stoi(measurement.view.substr(1))).at("track");
      Vector3d sensor;
      Vector3d heading;
      if (track == "ego") {
        sensor = kitti_frame.camera_position;
        heading = kitti_frame.ego_heading;
      } else {
        const auto box = std::find_if(
            kitti_frame.objects.begin(), kitti_frame.objects.end(),
            [&](const KittiObject& o) { return kitti_object_id(sequence_name, o.track_id) == track; });
        ASSERT_NE(box, kitti_frame.objects.end()) << track << " missing in frame " << frame;
        sensor = box->world_position + Vector3d(0.0, 0.0, options.sensor_height_m);
        heading = box->world_heading;
      }
      EXPECT_LT((*measurement.sensor_position - sensor).norm(), 1e-9)
          << measurement.scene << " " << measurement.view;
      const Vector3d offset = truth.at({measurement.scene, measurement.time, measurement.object}) - sensor;
      EXPECT_LE(offset.norm(), options.max_range_m);
      const Vector3d horizontal(offset.x(), offset.y(), 0.0);
      const Vector3d looking = Vector3d(heading.x(), heading.y(), 0.0).normalized();
      EXPECT_GE(horizontal.dot(looking), horizontal.norm() * half_fov_cosine - 1e-9)
          << "outside the field of view";
      ++checked;
    }
    // The other vehicles move at least min_vehicle_speed_m_s over their window.
    for (const auto& [scene, instance] : described) {
      const KittiSequence& sequence = sequence_named(instance.at("sequence").get<std::string>());
      const int first = instance.at("first_frame").get<int>();
      for (const nlohmann::json& vehicle : instance.at("vehicles")) {
        const std::string track = vehicle.at("track");
        if (track == "ego") continue;
        const int track_id = std::stoi(track.substr(track.find('-') + 1));
        const auto position_at = [&](int frame) {
          for (const KittiObject& o : sequence.frames.at(static_cast<std::size_t>(frame)).objects) {
            if (o.track_id == track_id) return o.world_position;
          }
          ADD_FAILURE() << track << " missing in frame " << frame;
          return Vector3d(Vector3d::Zero());
        };
        const Vector3d start = position_at(first);
        const Vector3d end = position_at(first + options.steps - 1);
        EXPECT_GE((end - start).head<2>().norm() / (0.1 * (options.steps - 1)), options.min_vehicle_speed_m_s)
            << scene << " " << track;
      }
    }
  }
  EXPECT_GT(checked, 1000u);
}

TEST(CadBenchmark, RejectsBadOptionsAndMissingFiles) {
  const std::vector<std::pair<std::string, void (*)(CadOptions&)>> cases = {
      {"steps", [](CadOptions& o) { o.steps = 1; }},
      {"objects", [](CadOptions& o) { o.objects = 0; }},
      {"min_vehicles", [](CadOptions& o) { o.min_vehicles = 5; }},
      {"field_of_view_deg", [](CadOptions& o) { o.field_of_view_deg = 0.0; }},
      {"max_range_m", [](CadOptions& o) { o.max_range_m = -1.0; }},
      {"gps_position_error_m", [](CadOptions& o) { o.gps_position_error_m = -0.1; }},
      {"detection_probability_far", [](CadOptions& o) { o.detection_probability_far = 0.99; }},
      {"min_visible_fraction", [](CadOptions& o) { o.min_visible_fraction = 1.5; }},
      {"val_sequences", [](CadOptions& o) { o.val_sequences.clear(); }},
      {"0020", [](CadOptions& o) { o.val_sequences.push_back("0020"); }},
  };
  for (const auto& [expected, change] : cases) {
    CadOptions options = small_options();
    change(options);
    try {
      validate_cad_options(options);
      ADD_FAILURE() << "accepted a bad " << expected;
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
    }
  }
  EXPECT_NO_THROW(validate_cad_options(small_options()));
  // KITTI is not shipped: the default options name no source, and say so.
  EXPECT_THROW(validate_cad_options(CadOptions{}), std::invalid_argument);

  CadOptions missing = small_options();
  missing.source_directory = "/nonexistent/kitti";
  try {
    make_cad_benchmark(missing);
    ADD_FAILURE() << "no error for a missing source";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/kitti/calib/"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace stgf
