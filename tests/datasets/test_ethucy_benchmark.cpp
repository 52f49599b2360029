// SPDX-License-Identifier: Apache-2.0
// The ETH/UCY reader (datasets/eth_ucy.hpp) and the ethucy benchmark (datasets/ethucy_benchmark.hpp).
//
// The reader runs on the real files shipped in data/eth_ucy (data/README.md) and is checked against
// their known statistics (the table below). The benchmark tests build small benchmarks from those
// files; the statistical checks use fixed seeds and tolerances of 5 standard errors, so they are
// deterministic and still fail when the model is wrong.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/eth_ucy.hpp"
#include "stgf/datasets/ethucy_benchmark.hpp"
#include "stgf/io/input_error.hpp"
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

const std::string kEthUcyDirectory = STGF_DATA_DIR "/eth_ucy";

// ── Helpers ──

// The eight files, read once for all tests.
const std::vector<EthUcyFile>& real_files() {
  static const std::vector<EthUcyFile> files = read_eth_ucy_folder(kEthUcyDirectory);
  return files;
}

const EthUcyFile& real_file(const std::string& file_name) {
  for (const EthUcyFile& file : real_files()) {
    if (file.file_name == file_name) return file;
  }
  throw std::logic_error("no file " + file_name);
}

Recording parse_text(const std::string& text, int frame_step = kEthUcyFrameStep) {
  std::istringstream in(text);
  return parse_eth_ucy(in, "bad.txt", "bad", "bad", frame_step);
}

// The InputError message of parsing `text`, or "" when it parses.
std::string parse_error(const std::string& text) {
  try {
    parse_text(text);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::size_t row_count(const Recording& recording) {
  std::size_t rows = 0;
  for (const auto& [frame, objects] : recording.frames) rows += objects.size();
  return rows;
}

std::size_t pedestrian_count(const Recording& recording) {
  std::set<std::string> ids;
  for (const auto& [frame, objects] : recording.frames) {
    for (const auto& [id, position] : objects) ids.insert(id);
  }
  return ids.size();
}

// A small benchmark: few instances, the shortest instances allowed.
EthUcyOptions small_options() {
  EthUcyOptions options;
  options.seed = 7;
  options.source_directory = kEthUcyDirectory;
  options.train_instances = 40;
  options.val_instances = 20;
  options.test_instances = 30;
  options.steps = 8;
  options.views = 3;
  return options;
}

// "students001-5" → "students001": the recording an object id comes from.
std::string recording_of(const std::string& object) { return object.substr(0, object.rfind('-')); }

// Frame index of a time t = f / 2.5 Hz (exact multiples of 0.4 s up to rounding).
int frame_of(double time) { return static_cast<int>(std::lround(time * kEthUcyRateHz)); }

int view_index(const std::string& view) { return std::stoi(view.substr(3)); }

// "ethucy-train-0007"
std::string scene_name(const std::string& split, int index) {
  std::ostringstream name;
  name << "ethucy-" << split << "-" << std::setw(4) << std::setfill('0') << index;
  return name.str();
}

// ── Reader ──

// Rows, pedestrians, time steps and frame range (divided by 10) of each file as copied (data/README.md).
TEST(EthUcyReader, ReadsTheRealFilesAsSourcesDescribes) {
  struct Expected {
    std::string file;
    std::size_t rows, pedestrians, frames;
    int first_frame, last_frame;
  };
  const std::vector<Expected> table = {
      {"biwi_eth.txt", 5492, 360, 876, 78, 1238},    {"biwi_hotel.txt", 6543, 389, 1168, 0, 1806},
      {"crowds_zara01.txt", 5153, 148, 872, 0, 901}, {"crowds_zara02.txt", 9722, 204, 1052, 1, 1052},
      {"crowds_zara03.txt", 5005, 137, 754, 0, 753}, {"students001.txt", 21813, 415, 444, 0, 443},
      {"students003.txt", 17953, 434, 541, 0, 540},  {"uni_examples.txt", 2747, 118, 734, 0, 741},
  };
  ASSERT_EQ(real_files().size(), table.size());
  for (const Expected& expected : table) {
    const Recording& recording = real_file(expected.file).recording;
    EXPECT_EQ(row_count(recording), expected.rows) << expected.file;
    EXPECT_EQ(pedestrian_count(recording), expected.pedestrians) << expected.file;
    EXPECT_EQ(recording.frames.size(), expected.frames) << expected.file;
    EXPECT_EQ(recording.frames.begin()->first, expected.first_frame) << expected.file;
    EXPECT_EQ(recording.frames.rbegin()->first, expected.last_frame) << expected.file;
    EXPECT_EQ(recording.rate_hz, 2.5);
  }
  // First lines of biwi_eth.txt: "780 1.0 8.46 3.59", "800 2.0 13.64 5.8"; of students001.txt:
  // "0.0 1.0 11.238836854 3.7469588555".
  const Recording& eth = real_file("biwi_eth.txt").recording;
  EXPECT_EQ(eth.name, "biwi_eth");
  EXPECT_EQ(eth.frames.at(78).at("eth-1"), Vector3d(8.46, 3.59, 0.0));
  EXPECT_EQ(eth.frames.at(80).at("eth-2"), Vector3d(13.64, 5.8, 0.0));
  EXPECT_EQ(real_file("students001.txt").recording.frames.at(0).at("students001-1"),
            Vector3d(11.238836854, 3.7469588555, 0.0));
  EXPECT_EQ(real_file("crowds_zara01.txt").recording.frames.begin()->second.begin()->first.substr(0, 7),
            "zara01-");
}

TEST(EthUcyReader, AcceptsFloatsIntegersSpacesTabsAndBlankLines) {
  const Recording recording =
      parse_text("780.0\t1.0\t8.46\t3.59\n\n  790 1   -9.5e-1  3.7\r\n800\t12.0\t1\t2\n");
  ASSERT_EQ(recording.frames.size(), 3u);
  EXPECT_EQ(recording.frames.at(78).at("bad-1"), Vector3d(8.46, 3.59, 0.0));
  EXPECT_EQ(recording.frames.at(79).at("bad-1"), Vector3d(-0.95, 3.7, 0.0));
  EXPECT_EQ(recording.frames.at(80).at("bad-12"), Vector3d(1.0, 2.0, 0.0));
}

TEST(EthUcyReader, FrameStepIsAnArgument) {
  const Recording recording = parse_text("0 1 0 0\n6 1 1 0\n12 1 2 0\n", 6);
  EXPECT_EQ(recording.frames.size(), 3u);
  EXPECT_EQ(recording.frames.at(2).at("bad-1").x(), 2.0);
  EXPECT_EQ(parse_error("0 1 0 0\n6 1 1 0\n"), "bad.txt:2: frame 6 is not a multiple of the frame step 10");
}

TEST(EthUcyReader, BadLinesStopWithFileAndLine) {
  const std::string good = "10 1 0.5 0.5\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {good + "20 1 0.5\n", "bad.txt:2: expected 4 fields (frame pedestrian x y), found 3"},
      {good + "20 1 0.5 0.5 9\n", "bad.txt:2: expected 4 fields (frame pedestrian x y), found 5"},
      {good + "\n20 one 0.5 0.5\n", "bad.txt:3: pedestrian id is not a number: 'one'"},
      {good + "20 1 0.5x 0.5\n", "bad.txt:2: x is not a number: '0.5x'"},
      {good + "20 1 0.5 nan\n", "bad.txt:2: y is not finite: 'nan'"},
      {good + "20 1 inf 0.5\n", "bad.txt:2: x is not finite: 'inf'"},
      {good + "25 1 0.5 0.5\n", "bad.txt:2: frame 25 is not a multiple of the frame step 10"},
      {good + "20.5 1 0.5 0.5\n", "bad.txt:2: frame is not a whole number: '20.5'"},
      {good + "20 1.5 0.5 0.5\n", "bad.txt:2: pedestrian id is not a whole number: '1.5'"},
      {good + "20 -1 0.5 0.5\n", "bad.txt:2: pedestrian id -1 is negative"},
      {good + "20 2 0 0\n10.0 1.0 0.7 0.7\n",
       "bad.txt:3: pedestrian 1 appears twice in frame 10 (first on line 1)"},
      {"", "bad.txt: no samples (expected lines: frame pedestrian x y)"},
      {"\n \n", "bad.txt: no samples (expected lines: frame pedestrian x y)"},
  };
  for (const auto& [text, message] : cases) EXPECT_EQ(parse_error(text), message) << text;
  EXPECT_EQ(parse_error(good), "");
}

TEST(EthUcyReader, MissingFileIsAnInputError) {
  try {
    read_eth_ucy_file(kEthUcyDirectory + "/no_such_file.txt");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.line(), 0);
    EXPECT_NE(std::string(error.what()).find("no_such_file.txt: cannot open"), std::string::npos);
  }
  EXPECT_THROW(read_eth_ucy_folder(kEthUcyDirectory + "/missing"), InputError);
}

TEST(EthUcyScenes, TableIsTheStandardLeaveOneOutSplit) {
  std::map<std::string, std::vector<std::string>> scenes;
  for (const EthUcyScene& scene : eth_ucy_scenes()) scenes[scene.name] = scene.files;
  const std::map<std::string, std::vector<std::string>> expected = {
      {"eth", {"biwi_eth.txt"}},
      {"hotel", {"biwi_hotel.txt"}},
      {"univ", {"students001.txt", "students003.txt"}},
      {"zara1", {"crowds_zara01.txt"}},
      {"zara2", {"crowds_zara02.txt"}},
  };
  EXPECT_EQ(scenes, expected);
  EXPECT_EQ(eth_ucy_training_only_files(),
            (std::vector<std::string>{"crowds_zara03.txt", "uni_examples.txt"}));
  // Together they are exactly the files of the folder.
  std::set<std::string> listed(eth_ucy_training_only_files().begin(), eth_ucy_training_only_files().end());
  for (const auto& [name, files] : expected) listed.insert(files.begin(), files.end());
  std::set<std::string> in_folder;
  for (const auto& entry : fs::directory_iterator(kEthUcyDirectory))
    in_folder.insert(entry.path().filename().string());
  EXPECT_EQ(listed, in_folder);
  EXPECT_EQ(eth_ucy_short_name("biwi_hotel"), "hotel");
  EXPECT_EQ(eth_ucy_short_name("crowds_zara03"), "zara03");
  EXPECT_EQ(eth_ucy_short_name("uni_examples"), "uni_examples");
}

// ── Benchmark ──

TEST(EthUcyOptions, OutOfRangeOptionsAreRejected) {
  EXPECT_NO_THROW(validate_ethucy_options(EthUcyOptions{}));
  const auto rejected = [](auto change) {
    EthUcyOptions options;
    change(options);
    EXPECT_THROW(validate_ethucy_options(options), std::invalid_argument);
  };
  rejected([](EthUcyOptions& o) { o.test_scene = "zara3"; });
  rejected([](EthUcyOptions& o) { o.steps = 7; });
  rejected([](EthUcyOptions& o) { o.train_instances = -1; });
  rejected([](EthUcyOptions& o) { o.min_objects = 0; });
  rejected([](EthUcyOptions& o) { o.max_objects = 1; });  // below min_objects = 2
  rejected([](EthUcyOptions& o) { o.val_fraction = 1.0; });
  rejected([](EthUcyOptions& o) { o.views = 0; });
  rejected([](EthUcyOptions& o) { o.max_sensor_height_m = 2.0; });
  rejected([](EthUcyOptions& o) { o.range_noise_m = 0.0; });
  rejected([](EthUcyOptions& o) { o.detection_probability_far = 0.99; });
  rejected([](EthUcyOptions& o) { o.registration_bias_m = -0.01; });
  rejected([](EthUcyOptions& o) { o.cross_noise_per_m = std::nan(""); });
}

TEST(EthUcyBenchmark, SameSeedSameFilesOtherSeedOtherMeasurements) {
  const EthUcyOptions options = small_options();
  ScratchDirectory scratch;
  write_benchmark_folder(scratch / "a", make_ethucy_benchmark(options));
  write_benchmark_folder(scratch / "b", make_ethucy_benchmark(options, real_files()));
  for (const std::string& name : kBenchmarkFiles) {
    const std::string bytes = file_bytes(scratch / ("a/" + name));
    EXPECT_GT(bytes.size(), 100u) << name;
    EXPECT_EQ(bytes, file_bytes(scratch / ("b/" + name))) << name;
  }
  EthUcyOptions other = options;
  other.seed = 8;
  const Benchmark first = make_ethucy_benchmark(options, real_files());
  const Benchmark second = make_ethucy_benchmark(other, real_files());
  ASSERT_FALSE(first.test.measurements.empty());
  ASSERT_FALSE(second.test.measurements.empty());
  EXPECT_NE(first.test.measurements[0].position.mean(), second.test.measurements[0].position.mean());
}

// Every split has the requested instances, each `steps` consecutive frames of one recording with
// min_objects … max_objects pedestrians, all present with a truth row at every step; measurements only
// of those, from cam0 … cam{V−1} with their sensor positions, sorted.
TEST(EthUcyBenchmark, CountsMatchTheRequestedShape) {
  EthUcyOptions options = small_options();
  options.min_objects = 3;
  options.max_objects = 5;
  options.views = 4;
  const Benchmark benchmark = make_ethucy_benchmark(options, real_files());
  const auto& splits_json = benchmark.description.at("splits");
  for (const auto& [name, split, requested] : {std::tuple{"train", &benchmark.train, options.train_instances},
                                               std::tuple{"val", &benchmark.val, options.val_instances},
                                               std::tuple{"test", &benchmark.test, options.test_instances}}) {
    SCOPED_TRACE(name);
    std::map<std::string, std::map<int, std::set<std::string>>> objects;  // scene → frame → objects
    for (const TruthPoint& point : split->truth) {
      EXPECT_NEAR(point.time * kEthUcyRateHz, frame_of(point.time), 1e-9);
      EXPECT_TRUE(objects[point.scene][frame_of(point.time)].insert(point.object).second);
    }
    ASSERT_EQ(static_cast<int>(objects.size()), requested);
    EXPECT_EQ(splits_json.at(name).at("instances"), requested);
    int index = 0;
    for (const auto& [scene, frames] : objects) {
      EXPECT_EQ(scene, scene_name(name, index++));
      ASSERT_EQ(static_cast<int>(frames.size()), options.steps) << scene;
      EXPECT_EQ(frames.rbegin()->first - frames.begin()->first, options.steps - 1) << scene;
      const std::set<std::string>& first = frames.begin()->second;
      EXPECT_GE(static_cast<int>(first.size()), options.min_objects) << scene;
      EXPECT_LE(static_cast<int>(first.size()), options.max_objects) << scene;
      const std::string recording = recording_of(*first.begin());
      for (const auto& [frame, here] : frames) {
        EXPECT_EQ(here, first) << scene << " frame " << frame;
        for (const std::string& object : here) EXPECT_EQ(recording_of(object), recording);
      }
    }
    for (std::size_t row = 0; row < split->measurements.size(); ++row) {
      const Measurement& measurement = split->measurements[row];
      EXPECT_TRUE(objects.at(measurement.scene).at(frame_of(measurement.time)).count(measurement.object));
      ASSERT_TRUE(measurement.sensor_position.has_value());
      EXPECT_GE(view_index(measurement.view), 0);
      EXPECT_LT(view_index(measurement.view), options.views);
      if (row > 0) {
        const Measurement& previous = split->measurements[row - 1];
        EXPECT_LT(std::tuple(previous.scene, previous.time, view_index(previous.view), previous.object),
                  std::tuple(measurement.scene, measurement.time, view_index(measurement.view),
                             measurement.object));
      }
    }
    // With 4 views and P_d ≥ 0.7 most (pedestrian, step) pairs are measured several times.
    EXPECT_GT(split->measurements.size(), 2 * split->truth.size());
  }
  const nlohmann::json counts = count_split(benchmark.test);
  EXPECT_EQ(counts.at("scenes"), options.test_instances);
  EXPECT_EQ(counts.at("steps"), options.test_instances * options.steps);
}

// test_instances = 0: one instance per eligible window of the test scene, each window once.
TEST(EthUcyBenchmark, ZeroInstancesMeansEveryWindowOnce) {
  EthUcyOptions options = small_options();
  options.test_scene = "hotel";
  options.test_instances = 0;
  options.steps = 12;
  const Benchmark benchmark = make_ethucy_benchmark(options, real_files());
  const nlohmann::json& test = benchmark.description.at("splits").at("test");
  const std::size_t windows =
      windows_with_objects(real_file("biwi_hotel.txt").recording, 0, 1807, 12, 2).size();
  EXPECT_EQ(windows, 614u);  // see EthUcyOptions
  EXPECT_EQ(test.at("eligible_windows"), windows);
  EXPECT_EQ(test.at("instances"), windows);
  std::map<std::string, int> first_frame;
  for (const TruthPoint& point : benchmark.test.truth) {
    const auto [it, inserted] = first_frame.try_emplace(point.scene, frame_of(point.time));
    if (!inserted) it->second = std::min(it->second, frame_of(point.time));
  }
  std::set<int> distinct;
  for (const auto& [scene, frame] : first_frame) distinct.insert(frame);
  EXPECT_EQ(distinct.size(), windows);  // no window twice
}

// The test split holds only the test scene's recordings; train and val never do, and use every
// other file including the training-only ones.
TEST(EthUcyBenchmark, TestSceneIsHeldOut) {
  const std::map<std::string, std::set<std::string>> test_recordings = {
      {"eth", {"eth"}},      {"hotel", {"hotel"}},  {"univ", {"students001", "students003"}},
      {"zara1", {"zara01"}}, {"zara2", {"zara02"}},
  };
  const std::set<std::string> all = {"eth",    "hotel",  "students001", "students003",
                                     "zara01", "zara02", "zara03",      "uni_examples"};
  for (const auto& [scene, held_out] : test_recordings) {
    SCOPED_TRACE(scene);
    EthUcyOptions options = small_options();
    options.test_scene = scene;
    options.train_instances = 300;  // enough to reach every training file
    const Benchmark benchmark = make_ethucy_benchmark(options, real_files());
    std::set<std::string> in_test, in_training;
    for (const TruthPoint& point : benchmark.test.truth) in_test.insert(recording_of(point.object));
    for (const BenchmarkSplit* split : {&benchmark.train, &benchmark.val}) {
      for (const TruthPoint& point : split->truth) in_training.insert(recording_of(point.object));
      for (const Measurement& measurement : split->measurements) {
        EXPECT_FALSE(held_out.count(recording_of(measurement.object))) << measurement.object;
      }
    }
    for (const Measurement& measurement : benchmark.test.measurements) {
      EXPECT_TRUE(held_out.count(recording_of(measurement.object))) << measurement.object;
    }
    EXPECT_EQ(in_test, held_out);
    std::set<std::string> expected_training;
    std::set_difference(all.begin(), all.end(), held_out.begin(), held_out.end(),
                        std::inserter(expected_training, expected_training.end()));
    EXPECT_EQ(in_training, expected_training);
    EXPECT_EQ(benchmark.description.at("splits").at("test").at("recordings").size(), held_out.size());
  }
}

// Within every recording, every val frame comes after every train frame, and val holds the last
// 15% of the recording's frame range.
TEST(EthUcyBenchmark, TrainAndValAreDisjointInTime) {
  EthUcyOptions options = small_options();
  options.train_instances = 400;
  options.val_instances = 200;
  const Benchmark benchmark = make_ethucy_benchmark(options, real_files());
  std::map<std::string, std::pair<int, int>> train_range, val_range;  // recording → (first, last) frame
  const auto extend = [](std::map<std::string, std::pair<int, int>>& ranges, const BenchmarkSplit& split) {
    for (const TruthPoint& point : split.truth) {
      const int frame = frame_of(point.time);
      const auto [it, inserted] = ranges.try_emplace(recording_of(point.object), frame, frame);
      it->second = {std::min(it->second.first, frame), std::max(it->second.second, frame)};
    }
  };
  extend(train_range, benchmark.train);
  extend(val_range, benchmark.val);
  EXPECT_GE(val_range.size(), 5u);
  for (const auto& [recording, val] : val_range) {
    ASSERT_TRUE(train_range.count(recording)) << recording;
    EXPECT_LT(train_range.at(recording).second, val.first) << recording;
  }
  // The boundary of biwi_hotel (frames 0–1806, n = 1807): B = 1807 − round(0.15 · 1807) = 1536.
  for (const auto& part : benchmark.description.at("splits").at("val").at("recordings")) {
    if (part.at("recording") == "biwi_hotel") {
      EXPECT_EQ(part.at("first_frame"), 1536);
    }
  }
  for (const auto& part : benchmark.description.at("splits").at("train").at("recordings")) {
    if (part.at("recording") == "biwi_hotel") {
      EXPECT_EQ(part.at("last_frame"), 1535);
    }
  }
}

// Cameras stand outside each recording's bounding box at 3–8 m.
TEST(EthUcyBenchmark, CamerasStandAroundEachScene) {
  const EthUcyOptions options = small_options();
  for (const EthUcyFile& file : real_files()) {
    const std::vector<SyntheticView> views = place_ethucy_views(options, file.recording);
    ASSERT_EQ(static_cast<int>(views.size()), options.views);
    double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
    for (const auto& [frame, objects] : file.recording.frames) {
      for (const auto& [id, p] : objects) {
        x_min = std::min(x_min, p.x()), x_max = std::max(x_max, p.x());
        y_min = std::min(y_min, p.y()), y_max = std::max(y_max, p.y());
      }
    }
    for (std::size_t k = 0; k < views.size(); ++k) {
      const Vector3d& s = views[k].sensor_position;
      EXPECT_EQ(views[k].id, "cam" + std::to_string(k));
      EXPECT_TRUE(s.x() < x_min || s.x() > x_max || s.y() < y_min || s.y() > y_max) << file.file_name;
      EXPECT_GE(s.z(), 3.0);
      EXPECT_LE(s.z(), 8.0);
    }
  }
}

// Without the registration bias the errors are N(0, R): the NEES of the raw measurements is χ²₃,
// mean 3, variance 6, so the sample mean of N of them is within 5·√(6/N) of 3.
TEST(EthUcyBenchmark, UnbiasedErrorsHaveNeesThree) {
  EthUcyOptions options = small_options();
  options.registration_bias_m = 0.0;
  options.train_instances = 300;
  const Benchmark benchmark = make_ethucy_benchmark(options, real_files());
  std::vector<double> nees = raw_nees(benchmark.train);
  const std::vector<double> test_nees = raw_nees(benchmark.test);
  nees.insert(nees.end(), test_nees.begin(), test_nees.end());
  const auto count = static_cast<double>(nees.size());
  ASSERT_GT(count, 20000.0);
  EXPECT_NEAR(mean_of(nees), 3.0, 5.0 * std::sqrt(6.0 / count));
  // Share inside the χ²₃ 95% quantile 7.8147: binomial, 5 standard errors.
  double inside = 0.0;
  for (const double value : nees) inside += value <= 7.814727903251178 ? 1.0 : 0.0;
  EXPECT_NEAR(inside / count, 0.95, 5.0 * std::sqrt(0.95 * 0.05 / count));
}

// The bias is one horizontal shift per instance and camera, not in R: with the same seed, switching it
// on moves every measurement of a (scene, camera) by the same (b_x, b_y, 0) and changes nothing else.
TEST(EthUcyBenchmark, BiasIsOneShiftPerInstanceAndCamera) {
  EthUcyOptions options = small_options();
  options.registration_bias_m = 0.0;
  const Benchmark unbiased = make_ethucy_benchmark(options, real_files());
  options.registration_bias_m = 0.05;
  const Benchmark biased = make_ethucy_benchmark(options, real_files());
  ASSERT_EQ(unbiased.train.measurements.size(), biased.train.measurements.size());
  std::map<std::pair<std::string, std::string>, Vector3d> shift;
  for (std::size_t row = 0; row < biased.train.measurements.size(); ++row) {
    const Measurement& a = unbiased.train.measurements[row];
    const Measurement& b = biased.train.measurements[row];
    ASSERT_EQ(std::tie(a.scene, a.time, a.view, a.object), std::tie(b.scene, b.time, b.view, b.object));
    EXPECT_EQ(a.position.covariance(), b.position.covariance());
    const Vector3d difference = b.position.mean() - a.position.mean();
    const auto [it, inserted] = shift.try_emplace({a.scene, a.view}, difference);
    EXPECT_NEAR((difference - it->second).norm(), 0.0, 1e-9);
    EXPECT_EQ(difference.z(), 0.0);
  }
  // The shifts are N(0, σ_b²) per axis: their mean square is σ_b² within 5 standard errors (2σ_b⁴/n).
  double sum_of_squares = 0.0;
  for (const auto& [key, difference] : shift)
    sum_of_squares += difference.x() * difference.x() + difference.y() * difference.y();
  const double n = 2.0 * static_cast<double>(shift.size());
  EXPECT_NEAR(sum_of_squares / n, 0.05 * 0.05, 5.0 * std::sqrt(2.0 / n) * 0.05 * 0.05);
}

// With the default registration bias the NEES against the written R is clearly above 3: it rises by
// E[bᵀR⁻¹b] = σ_b² E[(R⁻¹)_xx + (R⁻¹)_yy] (computed from the written R's).
TEST(EthUcyBenchmark, DefaultBiasRaisesNees) {
  EthUcyOptions options = small_options();
  ASSERT_GT(options.registration_bias_m, 0.0);
  options.train_instances = 300;
  const Benchmark benchmark = make_ethucy_benchmark(options, real_files());
  const std::vector<double> nees = raw_nees(benchmark.train);
  double expected_rise = 0.0;
  for (const Measurement& measurement : benchmark.train.measurements) {
    const Matrix3d& information = measurement.position.information();
    expected_rise += information(0, 0) + information(1, 1);
  }
  const auto count = static_cast<double>(nees.size());
  expected_rise *= options.registration_bias_m * options.registration_bias_m / count;
  const double rise = mean_of(nees) - 3.0;
  std::cout << "mean NEES with bias " << options.registration_bias_m << " m: " << mean_of(nees)
            << " (expected rise " << expected_rise << ", N = " << nees.size() << ")\n";
  EXPECT_GT(rise, 5.0 * std::sqrt(6.0 / count));
  EXPECT_GT(rise, 0.5 * expected_rise);
  EXPECT_LT(rise, 1.5 * expected_rise);
}

// Default size: how long making and writing takes, and the rows of each split (run by hand:
// --gtest_also_run_disabled_tests --gtest_filter='EthUcy*Default*').
TEST(EthUcyBenchmark, DISABLED_DefaultSizeTiming) {
  EthUcyOptions options;
  options.source_directory = kEthUcyDirectory;
  ScratchDirectory scratch;
  const auto start = std::chrono::steady_clock::now();
  const Benchmark benchmark = make_ethucy_benchmark(options);
  const auto made = std::chrono::steady_clock::now();
  write_benchmark_folder(scratch / "ethucy", benchmark);
  const auto written = std::chrono::steady_clock::now();
  std::cout << "make " << std::chrono::duration<double>(made - start).count() << " s, write "
            << std::chrono::duration<double>(written - made).count() << " s\n";
  const nlohmann::json description = nlohmann::json::parse(file_bytes(scratch / "ethucy/benchmark.json"));
  std::cout << description.at("counts").dump(1) << "\n";
  for (const auto& [name, split] : description.at("splits").items()) {
    for (const auto& part : split.at("recordings")) {
      std::cout << name << " " << part.at("recording") << " frames " << part.at("first_frame") << "-"
                << part.at("last_frame") << " windows " << part.at("eligible_windows") << " instances "
                << part.at("instances") << "\n";
    }
  }
}

}  // namespace
}  // namespace stgf
