// SPDX-License-Identifier: Apache-2.0
// Per-view clocks and latency (datasets/view_clocks.hpp), on hand-made splits and on every builder:
// phases in [0, T) from the documented streams, rows that move with their objects (the synchronous
// noise kept exactly), truth at every measured time, arrivals within [t, t + S), and the default
// output byte for byte what it was before the clocks existed.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/cad_benchmark.hpp"
#include "stgf/datasets/ethucy_benchmark.hpp"
#include "stgf/datasets/mpl_benchmark.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/synthetic.hpp"
#include "stgf/datasets/view_clocks.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/truth_file.hpp"
#include "support/benchmark_checks.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::file_bytes;
using testing::kBenchmarkFiles;
using testing::ScratchDirectory;
using testing::splits_of;

// ── Helpers ──

ViewClockOptions asynchronous(double jitter_s = 0.002, double latency_s = 0.0) {
  ViewClockOptions clocks;
  clocks.asynchronous = true;
  clocks.jitter_s = jitter_s;
  clocks.latency_s = latency_s;
  return clocks;
}

ViewClockOptions latency_only(double latency_s) {
  ViewClockOptions clocks;
  clocks.latency_s = latency_s;
  return clocks;
}

SyntheticOptions small_synthetic(std::uint64_t seed = 3, ViewClockOptions clocks = {}) {
  SyntheticOptions options;
  options.seed = seed;
  options.scenes = 2;
  options.steps = 10;
  options.objects = 3;
  options.views = 2;
  options.clocks = clocks;
  return options;
}

MplOptions small_mpl(ViewClockOptions clocks = {}) {
  MplOptions options;
  options.seed = 3;
  options.source_directory = STGF_DATA_DIR "/pets2009_s2l1";
  options.train_instances = 4;
  options.val_instances = 3;
  options.test_instances = 5;
  options.clocks = clocks;
  return options;
}

EthUcyOptions small_ethucy(ViewClockOptions clocks = {}) {
  EthUcyOptions options;
  options.seed = 3;
  options.source_directory = STGF_DATA_DIR "/eth_ucy";
  options.train_instances = 4;
  options.val_instances = 3;
  options.test_instances = 5;
  options.clocks = clocks;
  return options;
}

CadOptions small_cad(ViewClockOptions clocks = {}) {
  CadOptions options;
  options.seed = 3;
  options.source_directory = STGF_KITTI_DIR;
  options.train_instances = 4;
  options.val_instances = 3;
  options.test_instances = 5;
  options.clocks = clocks;
  return options;
}

// The rows of each (scene, view, object) in time order.
using Stream = std::tuple<std::string, std::string, std::string>;
std::map<Stream, std::vector<const Measurement*>> streams_of(const BenchmarkSplit& split) {
  std::map<Stream, std::vector<const Measurement*>> streams;
  for (const Measurement& row : split.measurements) streams[{row.scene, row.view, row.object}].push_back(&row);
  for (auto& [stream, rows] : streams) {
    std::stable_sort(rows.begin(), rows.end(), [](const Measurement* a, const Measurement* b) { return a->time < b->time; });
  }
  return streams;
}

TruthFile truth_file_of(const BenchmarkSplit& split) {
  TruthFile file;
  file.path = "truth";
  file.rows = split.truth;
  file.lines.assign(split.truth.size(), 0);
  return file;
}

// Checks an asynchronous split against the synchronous one built with the same seed:
//   • the same rows, each one moved to its own time: row k of a (scene, view, object) in the one is row
//     k in the other, and z' − p(t') = z − p(t) to 1e-9 m (the noise, bias and misses kept exactly);
//   • R and the sensor position unchanged;
//   • the times of a (scene, view, object) increase by more than 1e-6 s; a message lies within
//     [t − 0.45 T, t + 1.45 T] of its frame time;
//   • all rows of a view at one frame share one time (one message);
//   • the truth has every measured (scene, t', object) and nothing else, with no two times of a
//     (scene, object) within 1e-6 s;
//   • rows sorted by (scene, time).
void expect_moved_with_their_objects(const BenchmarkSplit& synchronous, const BenchmarkSplit& moved, double period,
                                     const std::string& name) {
  SCOPED_TRACE(name);
  ASSERT_EQ(synchronous.measurements.size(), moved.measurements.size());
  const TruthIndex sync_truth(truth_file_of(synchronous));
  const TruthIndex moved_truth(truth_file_of(moved));
  const auto sync_streams = streams_of(synchronous);
  const auto moved_streams = streams_of(moved);
  ASSERT_EQ(sync_streams.size(), moved_streams.size());
  std::map<std::tuple<std::string, std::string, double>, double> message_time;  // (scene, view, t) → t'
  double largest_noise_change = 0.0;
  for (const auto& [stream, sync_rows] : sync_streams) {
    const std::vector<const Measurement*>& moved_rows = moved_streams.at(stream);
    ASSERT_EQ(sync_rows.size(), moved_rows.size());
    for (std::size_t k = 0; k < sync_rows.size(); ++k) {
      const Measurement& before = *sync_rows[k];
      const Measurement& after = *moved_rows[k];
      EXPECT_GE(after.time, before.time - 0.45 * period - 1e-6);
      EXPECT_LE(after.time, before.time + 1.45 * period + 1e-6);
      if (k > 0) {
        EXPECT_GT(after.time - moved_rows[k - 1]->time, 1e-6);
      }
      const auto p_before = sync_truth.find(before.scene, before.time, before.object);
      const auto p_after = moved_truth.find(after.scene, after.time, after.object);
      ASSERT_TRUE(p_before.has_value());
      ASSERT_TRUE(p_after.has_value()) << "no truth at the measured time " << after.time;
      const Vector3d noise_before = before.position.mean() - *p_before;
      const Vector3d noise_after = after.position.mean() - *p_after;
      largest_noise_change = std::max(largest_noise_change, (noise_after - noise_before).norm());
      EXPECT_EQ(after.position.covariance(), before.position.covariance());
      EXPECT_EQ(after.sensor_position, before.sensor_position);
      const auto [entry, inserted] = message_time.try_emplace({before.scene, before.view, before.time}, after.time);
      EXPECT_EQ(entry->second, after.time) << "two times in one message";
    }
  }
  EXPECT_LT(largest_noise_change, 1e-9);

  std::set<std::tuple<std::string, double, std::string>> measured;
  for (const Measurement& row : moved.measurements) measured.emplace(row.scene, row.time, row.object);
  EXPECT_EQ(moved.truth.size(), measured.size());
  std::map<std::pair<std::string, std::string>, std::vector<double>> truth_times;
  for (const TruthPoint& point : moved.truth) {
    EXPECT_TRUE(measured.count({point.scene, point.time, point.object})) << point.scene << " " << point.time;
    truth_times[{point.scene, point.object}].push_back(point.time);
  }
  for (auto& [key, times] : truth_times) {
    std::sort(times.begin(), times.end());
    for (std::size_t k = 1; k < times.size(); ++k) EXPECT_GT(times[k] - times[k - 1], 1e-6);
  }
  for (std::size_t k = 1; k < moved.measurements.size(); ++k) {
    const Measurement& a = moved.measurements[k - 1];
    const Measurement& b = moved.measurements[k];
    if (a.scene == b.scene) {
      EXPECT_LE(a.time, b.time);
    }
  }
}

void expect_moved_with_their_objects(const Benchmark& synchronous, const Benchmark& moved, double period) {
  const auto sync_splits = splits_of(synchronous);
  const auto moved_splits = splits_of(moved);
  for (std::size_t k = 0; k < sync_splits.size(); ++k)
    expect_moved_with_their_objects(*sync_splits[k].split, *moved_splits[k].split, period, sync_splits[k].name);
}

// ── Default output ──

// The bytes of a small build, recorded (64-bit FNV-1a) before the clock options existed: the
// defaults (synchronous, no latency) must not change a single byte.
TEST(ViewClocks, DefaultOutputIsByteIdenticalToTheOutputBeforeTheClocks) {
  const ScratchDirectory directory;
  write_benchmark_folder(directory / "synthetic", make_synthetic_benchmark(small_synthetic()));
  const std::map<std::string, std::uint64_t> synthetic = {
      {"benchmark.json", 0x3B6A8266CD9F90A7ULL},     {"train/measurements.csv", 0x0B01F27CAF84D2F9ULL},
      {"train/truth.csv", 0xBD4751D6D5E27918ULL},    {"val/measurements.csv", 0x063109D9C791BF9AULL},
      {"val/truth.csv", 0xDB7F63CE968ACEEAULL},      {"test/measurements.csv", 0xF32CBD7A31C09675ULL},
      {"test/truth.csv", 0x9924BAC80AFCE850ULL}};
  for (const auto& [file, hash] : synthetic)
    EXPECT_EQ(fnv1a64(file_bytes(fs::path(directory / "synthetic") / file)), hash) << "synthetic " << file;

  // mpl's benchmark.json names the source folder (an absolute path), so only its CSV files.
  write_benchmark_folder(directory / "mpl", make_mpl_benchmark(small_mpl()));
  const std::map<std::string, std::uint64_t> mpl = {
      {"train/measurements.csv", 0x58D97AB17DFA9BE3ULL}, {"train/truth.csv", 0x2EFDCFA7E91C38A7ULL},
      {"val/measurements.csv", 0x62D925B1493B45ACULL},   {"val/truth.csv", 0x86AA661371FEBF1CULL},
      {"test/measurements.csv", 0xD8D52F903D5FF0ECULL},  {"test/truth.csv", 0x7A86E943FECE2DFDULL}};
  for (const auto& [file, hash] : mpl)
    EXPECT_EQ(fnv1a64(file_bytes(fs::path(directory / "mpl") / file)), hash) << "mpl " << file;
}

TEST(ViewClocks, InactiveOptionsLeaveTheSplitAsItWas) {
  const Benchmark built = make_synthetic_benchmark(small_synthetic());
  BenchmarkSplit split = built.test;
  ViewClockOptions off;
  off.jitter_s = 0.5;  // not checked, not used: the clocks are off
  EXPECT_TRUE(apply_view_clocks(split, off, 0.1, RandomStream(3)).is_null());
  ASSERT_EQ(split.measurements.size(), built.test.measurements.size());
  for (std::size_t k = 0; k < split.measurements.size(); ++k) {
    EXPECT_EQ(split.measurements[k].time, built.test.measurements[k].time);
    EXPECT_EQ(split.measurements[k].position.mean(), built.test.measurements[k].position.mean());
    EXPECT_FALSE(split.measurements[k].arrival.has_value());
  }
  EXPECT_FALSE(built.description.contains("clocks"));
}

// ── Phases ──

TEST(ViewClocks, PhasesAreInOnePeriodAndComeFromTheDocumentedStreams) {
  // Without jitter t' = µs(t + φ): each view's phase is its time minus the frame time, to 0.5 µs.
  const SyntheticOptions options = small_synthetic(3, asynchronous(0.0));
  const Benchmark synchronous = make_synthetic_benchmark(small_synthetic(3));
  const Benchmark moved = make_synthetic_benchmark(options);
  const double period = 1.0 / options.rate_hz;
  const auto sync_streams = streams_of(synchronous.train);
  const auto moved_streams = streams_of(moved.train);
  std::set<double> phases;
  for (const auto& [stream, rows] : moved_streams) {
    const auto& [scene, view, object] = stream;
    const double expected = RandomStream(options.seed).child("clocks").child(scene).child(view).uniform(0.0, period);
    EXPECT_GE(expected, 0.0);
    EXPECT_LT(expected, period);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      EXPECT_NEAR(rows[k]->time - sync_streams.at(stream)[k]->time, expected, 1.5e-6) << scene << " " << view;
    }
    phases.insert(expected);
  }
  EXPECT_EQ(phases.size(), 4u);  // 2 scenes × 2 views, each its own phase
  const nlohmann::json& summary = moved.description.at("clocks").at("splits").at("train").at("phase_s");
  EXPECT_GE(summary.at("min").get<double>(), 0.0);
  EXPECT_LT(summary.at("max").get<double>(), period);
  EXPECT_EQ(summary.at("count").get<int>(), 4);
}

TEST(ViewClocks, SameSeedSameBytesAnotherSeedOtherPhases) {
  const ScratchDirectory directory;
  write_benchmark_folder(directory / "a", make_synthetic_benchmark(small_synthetic(5, asynchronous(0.002, 0.05))));
  write_benchmark_folder(directory / "b", make_synthetic_benchmark(small_synthetic(5, asynchronous(0.002, 0.05))));
  for (const std::string& file : kBenchmarkFiles) {
    const std::string a = file_bytes(fs::path(directory / "a") / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, file_bytes(fs::path(directory / "b") / file)) << file;
  }
  const Benchmark five = make_synthetic_benchmark(small_synthetic(5, asynchronous()));
  const Benchmark six = make_synthetic_benchmark(small_synthetic(6, asynchronous()));
  const auto phase_summary = [](const Benchmark& benchmark) {
    return benchmark.description.at("clocks").at("splits").at("test").at("phase_s");
  };
  EXPECT_NE(phase_summary(five), phase_summary(six));
}

TEST(ViewClocks, ClocksDoNotDisturbTheBuildersDraws) {
  // Turning the clocks on changes when rows are measured, never what the builder drew: the same rows,
  // noise and misses (checked in detail by the tests below); and the latency stream is separate from
  // the clock stream, so adding a latency keeps the times.
  const Benchmark clocks = make_synthetic_benchmark(small_synthetic(3, asynchronous()));
  const Benchmark clocks_and_latency = make_synthetic_benchmark(small_synthetic(3, asynchronous(0.002, 0.1)));
  ASSERT_EQ(clocks.test.measurements.size(), clocks_and_latency.test.measurements.size());
  for (std::size_t k = 0; k < clocks.test.measurements.size(); ++k) {
    EXPECT_EQ(clocks.test.measurements[k].time, clocks_and_latency.test.measurements[k].time);
    EXPECT_EQ(clocks.test.measurements[k].position.mean(), clocks_and_latency.test.measurements[k].position.mean());
  }
}

// ── Rows move with their objects ──

TEST(ViewClocks, SyntheticRowsMoveWithTheirObjects) {
  const Benchmark synchronous = make_synthetic_benchmark(small_synthetic());
  const Benchmark moved = make_synthetic_benchmark(small_synthetic(3, asynchronous(0.005)));
  expect_moved_with_their_objects(synchronous, moved, 0.1);
  // The walkers do not exist beyond their scene: every track end is extrapolated.
  const nlohmann::json& test = moved.description.at("clocks").at("splits").at("test");
  EXPECT_EQ(test.at("track_ends_from_recording").get<int>(), 0);
  EXPECT_EQ(test.at("track_ends_extrapolated").get<int>(), 2 * 3 * 2);
}

TEST(ViewClocks, MplRowsMoveWithTheirObjects) {
  const Benchmark synchronous = make_mpl_benchmark(small_mpl());
  const Benchmark moved = make_mpl_benchmark(small_mpl(asynchronous()));
  expect_moved_with_their_objects(synchronous, moved, 1.0 / 7.0);
  // PETS people are annotated beyond most windows: those ends come from the recording.
  EXPECT_GT(moved.description.at("clocks").at("splits").at("test").at("track_ends_from_recording").get<int>(), 0);
}

TEST(ViewClocks, EthUcyRowsMoveWithTheirObjects) {
  const Benchmark synchronous = make_ethucy_benchmark(small_ethucy());
  const Benchmark moved = make_ethucy_benchmark(small_ethucy(asynchronous(0.02)));
  expect_moved_with_their_objects(synchronous, moved, 0.4);
  EXPECT_GT(moved.description.at("clocks").at("splits").at("train").at("track_ends_from_recording").get<int>(), 0);
}

TEST(ViewClocks, CadRowsMoveWithTheirObjects) {
  if (!fs::is_directory(STGF_KITTI_DIR)) GTEST_SKIP() << "no KITTI data at " << STGF_KITTI_DIR;
  const Benchmark synchronous = make_cad_benchmark(small_cad());
  const Benchmark moved = make_cad_benchmark(small_cad(asynchronous()));
  expect_moved_with_their_objects(synchronous, moved, 0.1);
  EXPECT_GT(moved.description.at("clocks").at("splits").at("test").at("track_ends_from_recording").get<int>(), 0);
}

TEST(ViewClocks, AsynchronousFolderReadsBackAndEveryMeasurementHasItsTruth) {
  const ScratchDirectory directory;
  write_benchmark_folder(directory / "b", make_mpl_benchmark(small_mpl(asynchronous(0.002, 0.03))));
  for (const std::string split : {"train", "val", "test"}) {
    // The readers reject duplicate truth times and arrivals before t; check_truth_matches a measurement
    // without truth.
    const MeasurementFile measurements = read_measurements(fs::path(directory / "b") / split / "measurements.csv");
    const TruthFile truth = read_truth(fs::path(directory / "b") / split / "truth.csv");
    EXPECT_TRUE(measurements.has_arrival);
    EXPECT_NO_THROW(check_truth_matches(measurements, truth)) << split;
  }
}

// ── Track ends ──

// One scene, one view, one object accelerating along x: p = (0, 1, 4) at t = 0, 1, 2 (T = 1 s),
// measured without noise at each frame.
BenchmarkSplit accelerating_object() {
  BenchmarkSplit split;
  const Gaussian3 unit = Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity());
  for (int frame = 0; frame < 3; ++frame) {
    const Vector3d position(frame * frame, 0.0, 0.0);
    split.truth.push_back({"s", static_cast<double>(frame), "o", position});
    split.measurements.push_back({"s", static_cast<double>(frame), "v", "o",
                                  Gaussian3::from_covariance(position, unit.covariance()), std::nullopt, std::nullopt});
  }
  return split;
}

TEST(ViewClocks, BeyondTheLastFrameTheTrackIsExtrapolatedOrTakenFromTheRecording) {
  const double phase = RandomStream(1).child("clocks").child("s").child("v").uniform(0.0, 1.0);
  const double last_time = std::round((2.0 + phase) * 1e6) / 1e6;

  BenchmarkSplit extrapolated = accelerating_object();
  apply_view_clocks(extrapolated, asynchronous(0.0), 1.0, RandomStream(1));
  ASSERT_EQ(extrapolated.measurements.size(), 3u);
  EXPECT_EQ(extrapolated.measurements[2].time, last_time);
  // Linear from the last two frames (1 → 4): 4 + 3 (t − 2).
  EXPECT_NEAR(extrapolated.measurements[2].position.mean().x(), 4.0 + 3.0 * (last_time - 2.0), 1e-12);
  EXPECT_NEAR(extrapolated.truth.back().position.x(), 4.0 + 3.0 * (last_time - 2.0), 1e-12);
  // Inside the window: linear between the frames (0 → 1 for the first row).
  EXPECT_NEAR(extrapolated.measurements[0].position.mean().x(), extrapolated.measurements[0].time, 1e-12);

  // A recording that has the object at t = 3 (x = 9) and t = 4 (x = 16), and nothing before t = 0.
  std::vector<double> asked;
  const TrackBeyondWindow recording = [&](const std::string& scene, const std::string& object,
                                          double time) -> std::optional<Vector3d> {
    EXPECT_EQ(scene, "s");
    EXPECT_EQ(object, "o");
    asked.push_back(time);
    if (time > 2.5) return Vector3d(time * time, 0.0, 0.0);
    return std::nullopt;
  };
  BenchmarkSplit from_recording = accelerating_object();
  const nlohmann::json summary = apply_view_clocks(from_recording, asynchronous(0.0), 1.0, RandomStream(1), recording);
  EXPECT_EQ(asked, (std::vector<double>{-1.0, 3.0, 4.0}));
  // Linear between the last frame and the recording's next (4 → 9): 4 + 5 (t − 2).
  EXPECT_NEAR(from_recording.measurements[2].position.mean().x(), 4.0 + 5.0 * (last_time - 2.0), 1e-12);
  EXPECT_EQ(summary.at("track_ends_from_recording").get<int>(), 1);
  EXPECT_EQ(summary.at("track_ends_extrapolated").get<int>(), 1);
}

TEST(ViewClocks, DistinctTimesOfASceneAreAtLeastTwoMicrosecondsApart) {
  // Message times 1 µs apart (two of seven views firing within a microsecond: a few times in a few
  // hundred scenes) are merged, so that no two times of a scene fall within the 1e-6 s that makes them one step.
  const Benchmark moved = make_mpl_benchmark([] {
    MplOptions options = small_mpl(asynchronous());
    options.train_instances = 150;
    options.val_instances = 100;
    options.test_instances = 200;
    return options;
  }());
  int merged = 0;
  for (const auto& [name, split] : splits_of(moved)) {
    merged += moved.description.at("clocks").at("splits").at(name).at("merged_message_times").get<int>();
    std::map<std::string, std::set<double>> times;
    for (const Measurement& row : split->measurements) times[row.scene].insert(row.time);
    for (const auto& [scene, scene_times] : times) {
      double previous = -1.0;
      for (const double time : scene_times) {
        EXPECT_GT(time - previous, 1.9e-6) << name << " " << scene;
        previous = time;
      }
    }
  }
  EXPECT_GT(merged, 0) << "no message time was merged: the test does not test the merging";
}

// ── Latency ──

TEST(ViewClocks, ArrivalsAreWithinTheLatencyAndShareAMessage) {
  const double latency = 0.05;
  for (const ViewClockOptions& clocks : {latency_only(latency), asynchronous(0.002, latency)}) {
    const Benchmark benchmark = make_synthetic_benchmark(small_synthetic(3, clocks));
    std::map<std::tuple<std::string, std::string, double>, double> arrival_of_message;
    for (const auto& [name, split] : splits_of(benchmark)) {
      for (const Measurement& row : split->measurements) {
        ASSERT_TRUE(row.arrival.has_value());
        EXPECT_GE(*row.arrival, row.time);
        EXPECT_LT(*row.arrival, row.time + latency);
        const auto [entry, inserted] = arrival_of_message.try_emplace({row.scene, row.view, row.time}, *row.arrival);
        EXPECT_EQ(entry->second, *row.arrival);
      }
    }
  }
}

TEST(ViewClocks, LatencyAloneKeepsTimesPositionsAndTruth) {
  const Benchmark synchronous = make_synthetic_benchmark(small_synthetic());
  const Benchmark late = make_synthetic_benchmark(small_synthetic(3, latency_only(0.1)));
  ASSERT_EQ(synchronous.test.measurements.size(), late.test.measurements.size());
  for (std::size_t k = 0; k < late.test.measurements.size(); ++k) {
    EXPECT_EQ(late.test.measurements[k].time, synchronous.test.measurements[k].time);
    EXPECT_EQ(late.test.measurements[k].position.mean(), synchronous.test.measurements[k].position.mean());
  }
  ASSERT_EQ(synchronous.test.truth.size(), late.test.truth.size());
  for (std::size_t k = 0; k < late.test.truth.size(); ++k)
    EXPECT_EQ(late.test.truth[k].position, synchronous.test.truth[k].position);
  const nlohmann::json& clocks = late.description.at("clocks");
  EXPECT_EQ(clocks.at("asynchronous"), false);
  EXPECT_EQ(clocks.at("latency_s"), 0.1);
}

// ── Options ──

std::string message_of(const std::function<void()>& build) {
  try {
    build();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "no error";
}

TEST(ViewClocks, BadOptionsAreRejectedByName) {
  EXPECT_EQ(message_of([] { validate_synthetic_options(small_synthetic(3, asynchronous(-0.001))); }),
            "synthetic benchmark: jitter_s must be zero or positive and below a tenth of the frame period (0.01 s) "
            "(got -0.001)");
  EXPECT_THAT(message_of([] { validate_synthetic_options(small_synthetic(3, asynchronous(0.01))); }),
              HasSubstr("jitter_s must be zero or positive and below a tenth of the frame period (0.01 s) (got 0.01)"));
  EXPECT_THAT(message_of([] { validate_mpl_options(small_mpl(asynchronous(0.02))); }),
              HasSubstr("mpl benchmark: jitter_s must be zero or positive and below a tenth of the frame period"));
  EXPECT_THAT(message_of([] { validate_ethucy_options(small_ethucy(asynchronous(std::nan("")))); }),
              HasSubstr("ethucy benchmark: jitter_s"));
  EXPECT_THAT(message_of([] { validate_cad_options(small_cad(latency_only(-1.0))); }),
              HasSubstr("cad benchmark: latency_s must be zero or positive (got -1)"));
  EXPECT_THAT(message_of([] { validate_synthetic_options(small_synthetic(3, latency_only(INFINITY))); }),
              HasSubstr("latency_s must be zero or positive (got inf)"));
  // The jitter is not checked while the clocks are synchronous: a 100 Hz benchmark keeps its default.
  SyntheticOptions fast = small_synthetic();
  fast.rate_hz = 100.0;
  EXPECT_EQ(message_of([&] { validate_synthetic_options(fast); }), "no error");
  fast.clocks.asynchronous = true;
  EXPECT_THAT(message_of([&] { validate_synthetic_options(fast); }), HasSubstr("(0.001 s) (got 0.002)"));
}

TEST(ViewClocks, TwoRowsOfOneStreamInOneFrameAreRejected) {
  BenchmarkSplit split = accelerating_object();
  split.measurements.push_back(split.measurements.front());
  EXPECT_THAT(message_of([&] { apply_view_clocks(split, asynchronous(), 1.0, RandomStream(1)); }),
              HasSubstr("scene 's' has two rows of view 'v' and object 'o' at t 0"));
}

}  // namespace
}  // namespace stgf
