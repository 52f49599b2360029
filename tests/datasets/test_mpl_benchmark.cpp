// SPDX-License-Identifier: Apache-2.0
// The mpl benchmark (datasets/mpl_benchmark.hpp): PETS 2009 S2.L1 pedestrians seen by its seven
// calibrated cameras. Small instance counts (30 / 20 / 40) keep the file fast; the statistical
// checks use fixed seeds and tolerances from the sampling distribution, so they are deterministic
// and still fail when the model is wrong.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/mpl_benchmark.hpp"
#include "stgf/datasets/pets2009.hpp"
#include "support/benchmark_checks.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using testing::file_bytes;
using testing::kBenchmarkFiles;
using testing::mean_of;
using testing::raw_nees;
using testing::ScratchDirectory;
using testing::splits_of;

const std::string kSourceDirectory = std::string(STGF_DATA_DIR) + "/pets2009_s2l1";
const std::vector<std::string> kDefaultViewIds = {"view1", "view3", "view4", "view5",
                                                  "view6", "view7", "view8"};

MplOptions small_options(std::uint64_t seed = 11) {
  MplOptions options;
  options.seed = seed;
  options.source_directory = kSourceDirectory;
  options.train_instances = 30;
  options.val_instances = 20;
  options.test_instances = 40;
  return options;
}

// The source data, read once for the whole file.
const MplSource& source() {
  static const MplSource source = read_mpl_source(small_options());
  return source;
}

Benchmark build(const MplOptions& options) { return make_mpl_benchmark(options, source()); }

int frame_of(double time) { return static_cast<int>(std::lround(time * kPets2009FrameRateHz)); }

// ── Reproducibility ──

TEST(MplBenchmark, SameSeedGivesByteIdenticalFoldersAndAnotherSeedDiffers) {
  const ScratchDirectory directory;
  write_benchmark_folder(directory / "a", make_mpl_benchmark(small_options(5)));  // reads the files itself
  write_benchmark_folder(directory / "b", build(small_options(5)));
  write_benchmark_folder(directory / "c", build(small_options(6)));
  for (const std::string& file : kBenchmarkFiles) {
    const std::string a = file_bytes(fs::path(directory / "a") / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, file_bytes(fs::path(directory / "b") / file)) << file;
    EXPECT_NE(a, file_bytes(fs::path(directory / "c") / file)) << file;
  }
}

TEST(MplBenchmark, InstancesDoNotDependOnHowManyThereAre) {
  // Instance k of a split comes from its own random stream: asking for more instances keeps the first ones.
  MplOptions more = small_options();
  more.train_instances = 60;
  more.val_instances = 40;
  more.test_instances = 80;  // same proportions, so the same frame ranges
  const Benchmark small = build(small_options());
  const Benchmark large = build(more);
  const auto rows_of = [](const BenchmarkSplit& split, const std::string& scene) {
    std::vector<std::tuple<double, std::string, std::string, double, double>> rows;
    for (const Measurement& m : split.measurements) {
      if (m.scene == scene)
        rows.emplace_back(m.time, m.view, m.object, m.position.mean().x(), m.position.mean().y());
    }
    return rows;
  };
  EXPECT_EQ(rows_of(small.test, "mpl-test-0007"), rows_of(large.test, "mpl-test-0007"));
  EXPECT_FALSE(rows_of(small.test, "mpl-test-0007").empty());
}

// ── Shape ──

TEST(MplBenchmark, CountsMatchTheRequestedShape) {
  const MplOptions options = small_options();
  const Benchmark benchmark = build(options);
  const std::map<std::string, std::pair<const BenchmarkSplit*, int>> splits = {
      {"train", {&benchmark.train, 30}}, {"val", {&benchmark.val, 20}}, {"test", {&benchmark.test, 40}}};
  for (const auto& [name, split_and_count] : splits) {
    const auto& [split, instances] = split_and_count;
    // Every chosen pedestrian at every step of every instance.
    EXPECT_EQ(split->truth.size(), static_cast<std::size_t>(instances * options.steps * options.pedestrians))
        << name;
    std::map<std::string, std::set<std::string>> people_by_scene;
    std::map<std::string, std::set<int>> frames_by_scene;
    for (const TruthPoint& point : split->truth) {
      people_by_scene[point.scene].insert(point.object);
      frames_by_scene[point.scene].insert(frame_of(point.time));
    }
    ASSERT_EQ(people_by_scene.size(), static_cast<std::size_t>(instances)) << name;
    int index = 0;
    for (const auto& [scene, people] : people_by_scene) {
      char expected_name[64];
      std::snprintf(expected_name, sizeof expected_name, "mpl-%s-%04d", name.c_str(), index++);
      EXPECT_EQ(scene, expected_name);
      EXPECT_EQ(people.size(), 4u) << scene;
      const std::set<int>& frames = frames_by_scene[scene];
      ASSERT_EQ(frames.size(), static_cast<std::size_t>(options.steps)) << scene;
      EXPECT_EQ(*frames.rbegin() - *frames.begin(), options.steps - 1) << scene << ": consecutive frames";
    }
    // At most 7 views per (scene, step, person), each one of the seven cameras; no duplicates.
    std::map<std::tuple<std::string, int, std::string>, std::set<std::string>> views_by_sighting;
    for (const Measurement& measurement : split->measurements) {
      ASSERT_NE(std::find(kDefaultViewIds.begin(), kDefaultViewIds.end(), measurement.view),
                kDefaultViewIds.end());
      const auto sighting =
          std::make_tuple(measurement.scene, frame_of(measurement.time), measurement.object);
      EXPECT_TRUE(views_by_sighting[sighting].insert(measurement.view).second) << "a second row for one view";
      EXPECT_TRUE(people_by_scene[measurement.scene].count(measurement.object))
          << "measured but not in the truth";
    }
    std::size_t most_views = 0;
    for (const auto& [sighting, views] : views_by_sighting) most_views = std::max(most_views, views.size());
    EXPECT_EQ(most_views, 7u) << name;
  }
  // The counts written with the folder agree.
  const nlohmann::json counts = count_split(benchmark.test);
  EXPECT_EQ(counts["scenes"], 40);
  EXPECT_EQ(counts["steps"], 40 * options.steps);
  EXPECT_EQ(counts["objects"], 40 * 4);
  EXPECT_EQ(counts["truth_rows"], 40 * options.steps * 4);
}

TEST(MplBenchmark, OtherShapesAndViews) {
  MplOptions options = small_options();
  options.steps = 8;
  options.pedestrians = 2;
  options.views = {8, 2};
  const Benchmark benchmark = make_mpl_benchmark(options);
  EXPECT_EQ(benchmark.val.truth.size(), 20u * 8u * 2u);
  std::set<std::string> views;
  for (const auto& [name, split] : splits_of(benchmark)) {
    for (const Measurement& measurement : split->measurements) views.insert(measurement.view);
  }
  EXPECT_EQ(views, (std::set<std::string>{"view2", "view8"}));
}

TEST(MplBenchmark, RowsAreSortedAndTruthComesFromTheRecording) {
  const Benchmark benchmark = build(small_options());
  const Recording& recording = source().recording;
  for (const auto& [name, split] : splits_of(benchmark)) {
    EXPECT_TRUE(std::is_sorted(split->measurements.begin(), split->measurements.end(),
                               [](const Measurement& a, const Measurement& b) {
                                 return std::tie(a.scene, a.time, a.view, a.object) <
                                        std::tie(b.scene, b.time, b.view, b.object);
                               }));
    EXPECT_TRUE(std::is_sorted(
        split->truth.begin(), split->truth.end(), [](const TruthPoint& a, const TruthPoint& b) {
          return std::tie(a.scene, a.time, a.object) < std::tie(b.scene, b.time, b.object);
        }));
    for (const TruthPoint& point : split->truth) {
      const int frame = frame_of(point.time);
      EXPECT_DOUBLE_EQ(point.time, frame / 7.0);
      EXPECT_EQ(point.position, recording.frames.at(frame).at(point.object));
    }
    // Each measurement carries its view's FILE camera centre.
    for (const Measurement& measurement : split->measurements) {
      const auto view = std::find_if(source().views.begin(), source().views.end(),
                                     [&](const MplView& v) { return v.id == measurement.view; });
      ASSERT_NE(view, source().views.end());
      ASSERT_TRUE(measurement.sensor_position.has_value());
      EXPECT_EQ(*measurement.sensor_position, view->camera.centre());
    }
  }
}

// ── Time ──

TEST(MplBenchmark, SplitRangesShareOutTheFramesInProportion) {
  MplOptions options = small_options();
  options.train_instances = 1500;
  options.val_instances = 1000;
  options.test_instances = 2000;
  const MplSplitRanges ranges = mpl_split_ranges(options, source().recording);
  // 795 frames · (1500, 2500) / 4500 = 265, 441.67.
  EXPECT_EQ(ranges.train.first_frame, 0);
  EXPECT_EQ(ranges.train.end_frame, 265);
  EXPECT_EQ(ranges.val.first_frame, 265);
  EXPECT_EQ(ranges.val.end_frame, 442);
  EXPECT_EQ(ranges.test.first_frame, 442);
  EXPECT_EQ(ranges.test.end_frame, 795);
}

TEST(MplBenchmark, SplitsAreDisjointInTime) {
  const MplOptions options = small_options();
  const Benchmark benchmark = build(options);
  const MplSplitRanges ranges = mpl_split_ranges(options, source().recording);
  const std::vector<FrameRange> expected = {ranges.train, ranges.val, ranges.test};
  const std::vector<testing::NamedSplit> splits = splits_of(benchmark);
  for (std::size_t index = 0; index < splits.size(); ++index) {
    int first = 1 << 30;
    int last = -1;
    for (const TruthPoint& point : splits[index].split->truth) {
      first = std::min(first, frame_of(point.time));
      last = std::max(last, frame_of(point.time));
    }
    for (const Measurement& measurement : splits[index].split->measurements) {
      EXPECT_GE(frame_of(measurement.time), first);
      EXPECT_LE(frame_of(measurement.time), last);
    }
    // Inside the split's range, windows never crossing its end.
    EXPECT_GE(first, expected[index].first_frame) << index;
    EXPECT_LT(last, expected[index].end_frame) << index;
  }
  EXPECT_LE(ranges.train.end_frame, ranges.val.first_frame);
  EXPECT_LE(ranges.val.end_frame, ranges.test.first_frame);
  // The description records them.
  const nlohmann::json& described = benchmark.description["splits"];
  EXPECT_EQ(described["val"]["first_frame"], ranges.val.first_frame);
  EXPECT_EQ(described["val"]["end_frame"], ranges.val.end_frame);
  EXPECT_GT(described["val"]["eligible_windows"].get<int>(), 20);
  EXPECT_EQ(described["val"]["instances"], 20);
}

// ── The noise model ──

TEST(MplBenchmark, WithoutCalibrationErrorRawNeesIsThree) {
  // z − p ≈ N(0, R) when the only error is the pixel noise (first order in the back-projection),
  // so the NEES is χ²(3): mean 3, variance 6. Rows are independent (their noise is), so the mean of
  // N of them has standard error √(6/N); allow 5 of them.
  MplOptions options = small_options(21);
  options.calibration_rotation_error_deg = 0.0;
  options.calibration_translation_error_m = 0.0;
  const std::vector<double> nees = raw_nees(build(options));
  ASSERT_GT(nees.size(), 30000u);
  const double tolerance = 5.0 * std::sqrt(6.0 / static_cast<double>(nees.size()));
  EXPECT_NEAR(mean_of(nees), 3.0, tolerance);
  // And its spread: the share inside the two-sided 95% interval of χ²(3), [0.216, 9.348], is 0.95 ± 5 s.e.
  const auto inside = std::count_if(nees.begin(), nees.end(),
                                    [](double value) { return value >= 0.2158 && value <= 9.3484; });
  const double share = static_cast<double>(inside) / static_cast<double>(nees.size());
  EXPECT_NEAR(share, 0.95, 5.0 * std::sqrt(0.95 * 0.05 / static_cast<double>(nees.size())));
}

TEST(MplBenchmark, CalibrationErrorMakesTheNeesClearlyLarger) {
  // The default calibration error (0.05°, 0.02 m) biases each view in each instance and is not in R.
  // At full size the mean raw NEES is ≈ 4.6; with 90 instances × 7 cameras of independent biases it
  // is well above 3 + the pixel-noise tolerance.
  const std::vector<double> biased = raw_nees(build(small_options(21)));
  EXPECT_GT(mean_of(biased), 3.8);
  // Larger errors, larger NEES.
  MplOptions larger = small_options(21);
  larger.calibration_rotation_error_deg = 0.2;
  larger.calibration_translation_error_m = 0.1;
  EXPECT_GT(mean_of(raw_nees(build(larger))), 2.0 * mean_of(biased));
}

TEST(MplBenchmark, CovarianceIsAnisotropicAndGrowsWithRange) {
  const Benchmark benchmark = build(small_options());
  std::vector<double> ranges;
  std::vector<double> traces;
  double most_elongated = 0.0;
  for (const auto& [name, split] : splits_of(benchmark)) {
    for (const Measurement& measurement : split->measurements) {
      const Matrix3d& covariance = measurement.position.covariance();
      ranges.push_back((measurement.position.mean() - *measurement.sensor_position).norm());
      traces.push_back(covariance.trace());
      EXPECT_EQ(covariance(0, 2), 0.0);
      EXPECT_EQ(covariance(2, 2), 0.05 * 0.05);
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> horizontal(covariance.topLeftCorner<2, 2>());
      most_elongated = std::max(most_elongated, horizontal.eigenvalues()(1) / horizontal.eigenvalues()(0));
    }
  }
  // Pearson correlation of trace(R) with the distance from the camera.
  const double mean_range = mean_of(ranges);
  const double mean_trace = mean_of(traces);
  double covariance = 0.0, range_variance = 0.0, trace_variance = 0.0;
  for (std::size_t index = 0; index < ranges.size(); ++index) {
    covariance += (ranges[index] - mean_range) * (traces[index] - mean_trace);
    range_variance += (ranges[index] - mean_range) * (ranges[index] - mean_range);
    trace_variance += (traces[index] - mean_trace) * (traces[index] - mean_trace);
  }
  const double correlation = covariance / std::sqrt(range_variance * trace_variance);
  EXPECT_GT(correlation, 0.5);
  // Long along the line of sight: far more than the σ_v/σ_u = 1.5 of the pixel noise.
  EXPECT_GT(most_elongated, 25.0);
}

TEST(MplBenchmark, ACameraMeasuresExactlyThePeopleInsideItsImage) {
  // With no calibration error and certain detection, view v measures a person iff the file camera
  // projects the foot point inside its image — and the low, wide views miss many people.
  MplOptions options = small_options();
  options.calibration_rotation_error_deg = 0.0;
  options.calibration_translation_error_m = 0.0;
  options.detection_probability = 1.0;
  const Benchmark benchmark = build(options);
  std::map<std::string, std::pair<int, int>> measured_and_possible;  // by view
  for (const auto& [name, split] : splits_of(benchmark)) {
    std::set<std::tuple<std::string, int, std::string, std::string>> measured;
    for (const Measurement& m : split->measurements)
      measured.insert({m.scene, frame_of(m.time), m.object, m.view});
    for (const TruthPoint& point : split->truth) {
      for (const MplView& view : source().views) {
        const bool is_measured =
            measured.count({point.scene, frame_of(point.time), point.object, view.id}) > 0;
        EXPECT_EQ(is_measured, view.camera.sees(point.position))
            << view.id << " " << point.scene << " " << point.object << " t=" << point.time;
        measured_and_possible[view.id].first += is_measured ? 1 : 0;
        measured_and_possible[view.id].second += 1;
      }
    }
  }
  for (const std::string view : {"view5", "view6", "view7", "view8"}) {
    const auto [measured, possible] = measured_and_possible[view];
    EXPECT_LT(measured, 0.9 * possible) << view << " should miss people outside its image";
    EXPECT_GT(measured, 0.2 * possible) << view;
  }
}

TEST(MplBenchmark, DetectionProbabilityThinsTheMeasurements) {
  MplOptions certain = small_options();
  certain.detection_probability = 1.0;
  MplOptions never = small_options();
  never.detection_probability = 0.0;
  MplOptions half = small_options();
  half.detection_probability = 0.5;
  const std::size_t all = build(certain).test.measurements.size();
  EXPECT_EQ(build(never).test.measurements.size(), 0u);
  // The calibration draws (and so who is visible) do not depend on the detection probability, so
  // the halved count is Binomial(all, ½): within 5 standard deviations of all/2.
  const double halved = static_cast<double>(build(half).test.measurements.size());
  EXPECT_NEAR(halved, 0.5 * static_cast<double>(all), 5.0 * std::sqrt(0.25 * static_cast<double>(all)));
}

// ── Options and description ──

TEST(MplBenchmark, RejectsBadOptions) {
  const auto rejects = [](auto change) {
    MplOptions options = small_options();
    change(options);
    EXPECT_THROW(make_mpl_benchmark(options), std::invalid_argument);
  };
  rejects([](MplOptions& o) { o.views = {9}; });
  rejects([](MplOptions& o) { o.views = {1, 3, 1}; });
  rejects([](MplOptions& o) { o.views = {}; });
  rejects([](MplOptions& o) { o.steps = 0; });
  rejects([](MplOptions& o) { o.pedestrians = 0; });
  rejects([](MplOptions& o) { o.train_instances = -1; });
  rejects([](MplOptions& o) { o.train_instances = o.val_instances = o.test_instances = 0; });
  rejects([](MplOptions& o) { o.pixel_noise_v_px = 0.0; });
  rejects([](MplOptions& o) { o.ground_height_noise_m = -1.0; });
  rejects([](MplOptions& o) { o.detection_probability = 1.5; });
  rejects([](MplOptions& o) { o.calibration_rotation_error_deg = -0.1; });
  rejects([](MplOptions& o) { o.calibration_translation_error_m = std::nan(""); });
  rejects([](MplOptions& o) { o.source_directory.clear(); });
  // No window of 20 frames with 9 people (at most 8 are ever in view at once).
  rejects([](MplOptions& o) { o.pedestrians = 9; });
  // Views that differ from the source data's.
  MplOptions other_views = small_options();
  other_views.views = {1, 3};
  EXPECT_THROW(make_mpl_benchmark(other_views, source()), std::invalid_argument);
}

TEST(MplBenchmark, DescriptionRecordsSourceSeedOptionsAndViews) {
  const ScratchDirectory directory;
  write_benchmark_folder(directory / "mpl", build(small_options(3)));
  std::ifstream input(directory / "mpl/benchmark.json");
  const nlohmann::json description = nlohmann::json::parse(input);
  EXPECT_EQ(description["seed"], 3);
  EXPECT_EQ(description["options"]["train_instances"], 30);
  EXPECT_EQ(description["options"]["pixel_noise_v_px"], 3.0);
  EXPECT_EQ(description["options"]["calibration_rotation_error_deg"], 0.05);
  EXPECT_EQ(description["options"]["views"], nlohmann::json({1, 3, 4, 5, 6, 7, 8}));
  ASSERT_EQ(description["views"].size(), 7u);
  EXPECT_EQ(description["views"][0]["id"], "view1");
  EXPECT_NEAR(description["views"][0]["camera_centre_m"][2].get<double>(), 7.07, 0.01);
  EXPECT_EQ(description["source_files"][0]["file"], "PETS2009-S2L1.xml");
  EXPECT_EQ(description["source_files"].size(), 8u);  // annotations + 7 calibrations (view 1 among them)
  EXPECT_EQ(description["recording"]["people"], 19);
  EXPECT_EQ(description["counts"]["train"]["scenes"], 30);
  EXPECT_EQ(description["splits"]["test"]["rays_missing_the_ground"], 0);
  for (const char* key :
       {"truth_model", "instance_model", "visibility_model", "noise_model", "calibration_error_model"}) {
    EXPECT_TRUE(description.contains(key)) << key;
  }
}

// Full size, for the numbers in the report: run with --gtest_also_run_disabled_tests.
TEST(MplBenchmark, DISABLED_FullSizeTimingAndNees) {
  for (const bool with_calibration_error : {false, true}) {
    MplOptions options = small_options(7);
    options.train_instances = 1500;
    options.val_instances = 1000;
    options.test_instances = 2000;
    if (!with_calibration_error) {
      options.calibration_rotation_error_deg = 0.0;
      options.calibration_translation_error_m = 0.0;
    }
    const ScratchDirectory directory;
    const auto start = std::chrono::steady_clock::now();
    const Benchmark benchmark = make_mpl_benchmark(options);
    const auto built = std::chrono::steady_clock::now();
    write_benchmark_folder(directory / "mpl", benchmark);
    const auto written = std::chrono::steady_clock::now();
    const std::vector<double> nees = raw_nees(benchmark);
    std::printf(
        "calibration error %s: make_mpl_benchmark %.2f s, write_benchmark_folder %.2f s, %zu measurement "
        "rows, "
        "mean raw NEES %.4f\n",
        with_calibration_error ? "on " : "off", std::chrono::duration<double>(built - start).count(),
        std::chrono::duration<double>(written - built).count(), nees.size(), mean_of(nees));
  }
}

}  // namespace
}  // namespace stgf
