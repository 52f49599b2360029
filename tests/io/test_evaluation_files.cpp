// SPDX-License-Identifier: Apache-2.0
// `stgf eval` on files: read scene by scene when they are grouped by scene in one order, with the
// numbers of evaluate() on the whole files, bit for bit; else read whole, with the same numbers and
// the same errors as always.

#include "stgf/io/evaluation_files.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "stgf/io/evaluation_report.hpp"
#include "stgf/io/input_error.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

using testing::ScratchDirectory;
using ::testing::HasSubstr;

// Four scenes of two objects seen by up to three views over six steps; the numbers vary enough that
// adding them up in another order would change the last bits. Views have sensors (REL-DE).
struct Files {
  std::string measurements = "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,sensor_x,sensor_y,sensor_z\n";
  std::string truth = "scene,t,object,x,y,z\n";
  std::string estimates_ab = "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method\n";
  std::string estimates_c = estimates_ab;
};

std::string number(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

Files make_files(const std::vector<std::string>& scenes, const std::string& extra_truth_scene = "") {
  Files files;
  int n = 0;
  for (const std::string& scene : scenes) {
    if (scene == extra_truth_scene) continue;
    for (int step = 0; step < 6; ++step) {
      const double t = 0.1 * step + 0.013 * static_cast<double>(scene.size());
      for (int object = 0; object < 2; ++object) {
        const std::string o = "o" + std::to_string(object);
        const double x = 0.37 * step + object, y = std::sin(0.3 * step + object);
        files.truth += scene + "," + number(t) + "," + o + "," + number(x) + "," + number(y) + ",0\n";
        for (int view = 0; view < 3; ++view) {
          if ((step + view + object) % 4 == 3) continue;  // missed
          ++n;
          const std::string key = scene + "," + number(t) + ",v" + std::to_string(view) + "," + o + ",";
          const double e = 0.01 * std::sin(1.7 * n), f = 0.01 * std::cos(2.3 * n);
          const std::string sensor = "," + number(10.0 * view) + "," + number(-5.0 + view) + ",3\n";
          files.measurements += key + number(x + e) + "," + number(y + f) + ",0.01,0.0004,0,0,0.0004,0,0.0001" + sensor;
          files.estimates_ab += key + number(x + 0.5 * e) + "," + number(y - f) + ",0," + number(0.0003 + 0.0001 * (n % 3)) +
                                ",0.00001,0,0.0003,0,0.0001,a\n";
          files.estimates_ab += key + number(x - f) + "," + number(y + e) + ",0.001,0.0002,0,0,0.0002,0,0.0001,b\n";
          files.estimates_c += key + number(x + e * f) + "," + number(y) + ",0,0.0001,0,0,0.0001,0,0.0001,c\n";
        }
      }
    }
  }
  if (!extra_truth_scene.empty()) files.truth += extra_truth_scene + ",0,o0,0,0,0\n";
  return files;
}

struct Written {
  std::string truth, measurements;
  std::vector<std::string> estimates;
};

Written write(const ScratchDirectory& directory, const Files& files) {
  return {directory.write("t.csv", files.truth), directory.write("m.csv", files.measurements),
          {directory.write("ab.csv", files.estimates_ab), directory.write("c.csv", files.estimates_c)}};
}

// evaluate() on the files read whole: what `stgf eval` gave before it read files scene by scene.
Evaluation whole(const Written& files, bool with_measurements, const ScoringStart& start) {
  std::vector<EstimateFile> estimates;
  for (const std::string& path : files.estimates) estimates.push_back(read_estimates(path));
  const MeasurementFile measurements = read_measurements(files.measurements);
  return evaluate(read_truth(files.truth), estimates, with_measurements ? &measurements : nullptr, start);
}

std::string error_of(const auto& evaluate_somehow) {
  try {
    evaluate_somehow();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(EvaluationFiles, SceneBySceneGivesTheWholeFilesNumbersBitForBit) {
  const ScratchDirectory directory;
  const Written files = write(directory, make_files({"s0", "s11", "s2", "s333"}));
  for (const ScoringStart start : {ScoringStart{0, 0.0}, ScoringStart{2, 0.0}, ScoringStart{0, 0.25}}) {
    for (const bool with_measurements : {true, false}) {
      std::string read_whole_because = "not set";
      const Evaluation streamed = evaluate_files(files.truth, files.estimates, with_measurements ? files.measurements : "",
                                                 start, &read_whole_because);
      EXPECT_EQ(read_whole_because, "");
      const Evaluation expected = whole(files, with_measurements, start);
      ASSERT_EQ(streamed.methods.size(), 3u);
      EXPECT_EQ(evaluation_json(streamed).dump(), evaluation_json(expected).dump());
      EXPECT_EQ(evaluation_markdown(streamed), evaluation_markdown(expected));
      EXPECT_GT(streamed.methods[0].overall.rows, 0u);
    }
  }
}

// Without measurements the truth may hold scenes no estimate has; they are read (and checked) and
// passed over.
TEST(EvaluationFiles, WithoutMeasurementsTruthScenesBetweenArePassedOver) {
  const ScratchDirectory directory;
  Files files = make_files({"s0", "s1", "s2"});
  files.truth = "scene,t,object,x,y,z\nextra,0,o0,1,2,3\n" + files.truth.substr(files.truth.find('\n') + 1);
  const Written written = write(directory, files);
  std::string read_whole_because;
  const Evaluation streamed = evaluate_files(written.truth, written.estimates, "", {}, &read_whole_because);
  EXPECT_EQ(read_whole_because, "");
  EXPECT_EQ(evaluation_json(streamed).dump(), evaluation_json(whole(written, false, {})).dump());
  // With measurements, a truth scene without measurements is an error, which the whole files report.
  EXPECT_EQ(error_of([&] { evaluate_files(written.truth, written.estimates, written.measurements, {}); }),
            error_of([&] { whole(written, true, {}); }));
  EXPECT_THAT(error_of([&] { evaluate_files(written.truth, written.estimates, written.measurements, {}); }),
              HasSubstr("scene 'extra' has no measurements"));
}

// Files in another scene order, or not grouped, are read whole: the same numbers, and why.
TEST(EvaluationFiles, FilesInAnotherOrderAreReadWholeWithTheSameNumbers) {
  const ScratchDirectory directory;
  Files files = make_files({"s0", "s1", "s2"});
  const Files reordered = make_files({"s2", "s0", "s1"});
  files.truth = reordered.truth;
  const Written written = write(directory, files);
  std::string read_whole_because;
  const Evaluation evaluation = evaluate_files(written.truth, written.estimates, written.measurements, {}, &read_whole_because);
  EXPECT_THAT(read_whole_because, HasSubstr("does not have scene 's0' next"));
  EXPECT_EQ(evaluation_json(evaluation).dump(), evaluation_json(whole(written, true, {})).dump());

  // Rows of one scene split by another scene's: read whole too. The first row of s0 goes to the end.
  Files split = make_files({"s0", "s1"});
  const std::size_t first_row = split.estimates_c.find('\n') + 1;
  const std::size_t second_row = split.estimates_c.find('\n', first_row) + 1;
  split.estimates_c = split.estimates_c.substr(0, first_row) + split.estimates_c.substr(second_row) +
                      split.estimates_c.substr(first_row, second_row - first_row);
  const Written split_written = write(directory, split);
  const Evaluation split_evaluation =
      evaluate_files(split_written.truth, split_written.estimates, split_written.measurements, {}, &read_whole_because);
  EXPECT_NE(read_whole_because, "");
  EXPECT_EQ(evaluation_json(split_evaluation).dump(), evaluation_json(whole(split_written, true, {})).dump());

  // A truth scene no estimate has, in two parts: found when the truth's end is read.
  Files extra = make_files({"s0", "s1"});
  extra.truth += "extra,0,o0,0,0,0\ns0,9,o0,0,0,0\nextra,1,o0,0,0,0\n";
  const Written extra_written = write(directory, extra);
  const Evaluation extra_evaluation =
      evaluate_files(extra_written.truth, extra_written.estimates, "", {}, &read_whole_because);
  EXPECT_THAT(read_whole_because, HasSubstr("appears again after other scenes"));
  EXPECT_EQ(evaluation_json(extra_evaluation).dump(), evaluation_json(whole(extra_written, false, {})).dump());
}

// What evaluate() rejects is reported as it always was, wherever the scene.
TEST(EvaluationFiles, ProblemsAreReportedAsFromTheWholeFiles) {
  const ScratchDirectory directory;
  const Files good = make_files({"s0", "s1", "s2"});
  std::vector<Files> bad(3, good);
  // A missing estimate in the last scene.
  bad[0].estimates_c.erase(bad[0].estimates_c.rfind("s2,"));
  bad[0].estimates_c += "\n";
  // An estimate without a measurement.
  bad[1].estimates_ab += "s1,9.5,v0,o0,0,0,0,1,0,0,1,0,1,a\n";
  // A measurement without truth in the second scene.
  bad[2].truth.erase(bad[2].truth.find("s1,"), bad[2].truth.find('\n', bad[2].truth.find("s1,")) - bad[2].truth.find("s1,") + 1);
  for (const Files& files : bad) {
    const Written written = write(directory, files);
    const std::string expected = error_of([&] { whole(written, true, {}); });
    EXPECT_NE(expected, "no error");
    EXPECT_EQ(error_of([&] { evaluate_files(written.truth, written.estimates, written.measurements, {}); }), expected);
  }
}

}  // namespace
}  // namespace stgf
