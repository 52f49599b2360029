// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/evaluation.hpp"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "stgf/io/evaluation_report.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

using ::testing::HasSubstr;

// Two steps; object o seen by v1 and v2 at t=0, by v1 only at t=1. Sensors 10 m away.
const std::string kMeasurements =
    "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,sensor_x,sensor_y,sensor_z\n"
    "s,0,v1,o,0,0,0,1,0,0,1,0,1,10,0,0\n"
    "s,0,v2,o,0,0,0,1,0,0,1,0,1,0,10,0\n"
    "s,1,v1,o,1,0,0,1,0,0,1,0,1,10,0,0\n";
const std::string kTruth = "scene,t,object,x,y,z\ns,0,o,0,0,0\ns,1,o,1,0,0\n";
const std::string kHeader = "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method\n";

// Method "a": errors 3 (cov 9·I → NEES 1), 4 (cov 4·I → NEES 4) at t=0, 1 at t=1 (cov I → NEES 1).
const std::string kMethodA = kHeader +
                             "s,0,v1,o,3,0,0,9,0,0,9,0,9,a\n"
                             "s,0,v2,o,0,4,0,4,0,0,4,0,4,a\n"
                             "s,1,v1,o,1,1,0,1,0,0,1,0,1,a\n";

std::string error_of(const std::vector<std::string>& estimate_texts, bool with_measurements = true) {
  try {
    std::vector<EstimateFile> estimates;
    for (std::size_t k = 0; k < estimate_texts.size(); ++k) {
      estimates.push_back(parse_estimates("e" + std::to_string(k) + ".csv", estimate_texts[k]));
    }
    const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
    evaluate(parse_truth("t.csv", kTruth), estimates, with_measurements ? &measurements : nullptr, 0);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(Evaluation, HandComputedScores) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const Evaluation evaluation =
      evaluate(parse_truth("t.csv", kTruth), {parse_estimates("e.csv", kMethodA)}, &measurements, 0);
  ASSERT_EQ(evaluation.methods.size(), 1u);
  const MethodScore& a = evaluation.methods[0];
  EXPECT_EQ(a.method, "a");
  EXPECT_EQ(a.overall.rows, 3u);
  EXPECT_DOUBLE_EQ(a.overall.displacement_error, (3.0 + 4.0 + 1.0) / 3);
  // Ranges: ‖(0,0,0) − (10,0,0)‖ = 10, ‖(0,0,0) − (0,10,0)‖ = 10, ‖(1,0,0) − (10,0,0)‖ = 9.
  EXPECT_DOUBLE_EQ(a.overall.relative_displacement_error, (0.3 + 0.4 + 1.0 / 9.0) / 3);
  EXPECT_DOUBLE_EQ(a.overall.nees_mean, 2.0);
  EXPECT_DOUBLE_EQ(a.overall.nees_share_in_95, 1.0);
  ASSERT_EQ(a.by_views.size(), 2u);
  EXPECT_EQ(a.by_views.at(2).rows, 2u);
  EXPECT_DOUBLE_EQ(a.by_views.at(2).displacement_error, 3.5);
  EXPECT_DOUBLE_EQ(a.by_views.at(1).displacement_error, 1.0);

  const std::string table = evaluation_markdown(evaluation);
  EXPECT_THAT(table, HasSubstr("| a | 3 | 2.6667 | 0.2704 | 2.00 | 1.000 |"));
  EXPECT_THAT(table, HasSubstr("| a | 1.0000 | 3.5000 |"));
  const nlohmann::json json = evaluation_json(evaluation);
  EXPECT_DOUBLE_EQ(json["methods"][0]["overall"]["nees_mean"].get<double>(), 2.0);
  EXPECT_EQ(json["methods"][0]["by_views"]["2"]["rows"].get<int>(), 2);
}

TEST(Evaluation, ErrorByVarianceBinsEachAxisByTheOctaveOfItsStatedVariance) {
  // Method a's errors along y: 0 (stated 9, octave 3), 4 (stated 4, octave 2), 1 (stated 1, octave 0).
  // Method b states 2 (octave 1) everywhere and is exact.
  const std::string method_b = kHeader +
                               "s,0,v1,o,0,0,0,2,0,0,2,0,2,b\n"
                               "s,0,v2,o,0,0,0,2,0,0,2,0,2,b\n"
                               "s,1,v1,o,1,0,0,2,0,0,2,0,2,b\n";
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const Evaluation evaluation = evaluate(parse_truth("t.csv", kTruth),
                                         {parse_estimates("a.csv", kMethodA), parse_estimates("b.csv", method_b)},
                                         &measurements, 0);
  const auto& y = evaluation.methods[0].by_variance[1];
  ASSERT_EQ(y.size(), 3u);
  EXPECT_EQ(y[0].octave, 0);
  EXPECT_DOUBLE_EQ(y[0].mean_squared_error, 1.0);
  EXPECT_EQ(y[1].octave, 2);
  EXPECT_DOUBLE_EQ(y[1].mean_squared_error, 16.0);
  EXPECT_EQ(y[2].octave, 3);
  EXPECT_DOUBLE_EQ(y[2].mean_variance, 9.0);

  const std::string table = error_by_variance_markdown(evaluation, 1);
  EXPECT_THAT(table, HasSubstr("| P_yy (m²) | a | b |"));
  EXPECT_THAT(table, HasSubstr("| 1.00e+00 – 2.00e+00 | 1.00 (1) | – |\n"
                               "| 2.00e+00 – 4.00e+00 | – | 0.00 (3) |\n"
                               "| 4.00e+00 – 8.00e+00 | 4.00 (1) | – |\n"
                               "| 8.00e+00 – 1.60e+01 | 0.00 (1) | – |\n"));
  EXPECT_THROW(error_by_variance_markdown(evaluation, 3), std::invalid_argument);

  const nlohmann::json bins = evaluation_json(evaluation)["methods"][0]["by_variance"]["y"];
  ASSERT_EQ(bins.size(), 3u);
  EXPECT_EQ(bins[1]["variance_from"].get<double>(), 4.0);
  EXPECT_EQ(bins[1]["variance_to"].get<double>(), 8.0);
  EXPECT_EQ(bins[1]["rows"].get<int>(), 1);
  EXPECT_EQ(bins[1]["mean_squared_error"].get<double>(), 16.0);
  // Scored rows only: from step 1 on, one row in each of a's axes.
  const Evaluation later =
      evaluate(parse_truth("t.csv", kTruth), {parse_estimates("a.csv", kMethodA)}, &measurements, 1);
  EXPECT_EQ(later.methods[0].by_variance[1].size(), 1u);
}

TEST(Evaluation, FromStepLeavesOutEarlyStepsForEveryMethod) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const Evaluation evaluation =
      evaluate(parse_truth("t.csv", kTruth), {parse_estimates("e.csv", kMethodA)}, &measurements, 1);
  EXPECT_EQ(evaluation.rows_excluded, 2u);
  EXPECT_EQ(evaluation.methods[0].overall.rows, 1u);
  EXPECT_DOUBLE_EQ(evaluation.methods[0].overall.displacement_error, 1.0);
}

TEST(Evaluation, FromTimeOnSynchronousDataLeavesOutWhatFromStepDoes) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const TruthFile truth = parse_truth("t.csv", kTruth);
  const std::vector<EstimateFile> estimates = {parse_estimates("e.csv", kMethodA)};
  // Steps at 0 and 1 s: from 1 s (the second step's time; within 1e-6 s counts as reached) and
  // from 0.5 s both leave out the first step, like --from-step 1.
  for (const double from_time : {0.5, 1.0, 1.0000009}) {
    const Evaluation evaluation = evaluate(truth, estimates, &measurements, ScoringStart{0, from_time});
    EXPECT_EQ(evaluation.rows_excluded, 2u) << from_time;
    EXPECT_EQ(evaluation.from_time_s, from_time);
    EXPECT_EQ(evaluation.methods[0].overall.rows, 1u) << from_time;
    EXPECT_DOUBLE_EQ(evaluation.methods[0].overall.displacement_error, 1.0) << from_time;
  }
  EXPECT_EQ(evaluate(truth, estimates, &measurements, ScoringStart{0, 0.0}).rows_excluded, 0u);
  EXPECT_EQ(evaluate(truth, estimates, &measurements, ScoringStart{0, 1.1}).rows_excluded, 3u);
  EXPECT_EQ(evaluation_json(evaluate(truth, estimates, &measurements, ScoringStart{0, 0.5}))["from_time_s"], 0.5);
}

TEST(Evaluation, FromTimeCountsSecondsNotDistinctTimesOnAsynchronousData) {
  // Two views on their own clocks (v2 30 ms after v1), two frames 1 s apart, in two scenes whose
  // first times differ: every view adds its own times, so --from-step 1 would leave out only v1's
  // first row, while --from-time 1 leaves out each scene's whole first frame.
  const std::string measurements_text =
      "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz\n"
      "a,0,v1,o,0,0,0,1,0,0,1,0,1\n"
      "a,0.03,v2,o,0,0,0,1,0,0,1,0,1\n"
      "a,1,v1,o,1,0,0,1,0,0,1,0,1\n"
      "a,1.03,v2,o,1,0,0,1,0,0,1,0,1\n"
      "b,5,v1,o,0,0,0,1,0,0,1,0,1\n"
      "b,5.03,v2,o,0,0,0,1,0,0,1,0,1\n"
      "b,6,v1,o,1,0,0,1,0,0,1,0,1\n";
  const std::string truth_text =
      "scene,t,object,x,y,z\na,0,o,0,0,0\na,0.03,o,0,0,0\na,1,o,1,0,0\na,1.03,o,1,0,0\n"
      "b,5,o,0,0,0\nb,5.03,o,0,0,0\nb,6,o,1,0,0\n";
  // Errors: 10 m in each first frame, 1 m after.
  const std::string estimates_text = kHeader +
                                     "a,0,v1,o,10,0,0,1,0,0,1,0,1,a\n"
                                     "a,0.03,v2,o,10,0,0,1,0,0,1,0,1,a\n"
                                     "a,1,v1,o,2,0,0,1,0,0,1,0,1,a\n"
                                     "a,1.03,v2,o,2,0,0,1,0,0,1,0,1,a\n"
                                     "b,5,v1,o,10,0,0,1,0,0,1,0,1,a\n"
                                     "b,5.03,v2,o,10,0,0,1,0,0,1,0,1,a\n"
                                     "b,6,v1,o,2,0,0,1,0,0,1,0,1,a\n";
  const MeasurementFile measurements = parse_measurements("m.csv", measurements_text);
  const TruthFile truth = parse_truth("t.csv", truth_text);
  const std::vector<EstimateFile> estimates = {parse_estimates("e.csv", estimates_text)};

  const Evaluation by_time = evaluate(truth, estimates, &measurements, ScoringStart{0, 1.0});
  EXPECT_EQ(by_time.rows_excluded, 4u);
  EXPECT_EQ(by_time.methods[0].overall.rows, 3u);
  EXPECT_DOUBLE_EQ(by_time.methods[0].overall.displacement_error, 1.0);

  const Evaluation by_step = evaluate(truth, estimates, &measurements, ScoringStart{1, 0.0});
  EXPECT_EQ(by_step.rows_excluded, 2u);
  EXPECT_EQ(by_step.methods[0].overall.rows, 5u);
}

TEST(Evaluation, FromStepAndFromTimeExcludeEachOther) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const TruthFile truth = parse_truth("t.csv", kTruth);
  const std::vector<EstimateFile> estimates = {parse_estimates("e.csv", kMethodA)};
  const auto message_of = [&](const ScoringStart& start) -> std::string {
    try {
      evaluate(truth, estimates, &measurements, start);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "no error";
  };
  EXPECT_EQ(message_of({1, 0.5}), "--from-step and --from-time exclude each other: give one of them");
  EXPECT_EQ(message_of({0, -0.1}), "--from-time must be a finite number of seconds >= 0 (got -0.1)");
  EXPECT_THAT(message_of({0, std::nan("")}), HasSubstr("--from-time must be a finite number"));
}

TEST(Evaluation, WithoutMeasurementsTheFirstMethodFixesTheRowsAndNoRelativeError) {
  const Evaluation evaluation =
      evaluate(parse_truth("t.csv", kTruth), {parse_estimates("e.csv", kMethodA)}, nullptr, 0);
  EXPECT_EQ(evaluation.methods[0].overall.rows, 3u);
  EXPECT_TRUE(std::isnan(evaluation.methods[0].overall.relative_displacement_error));
  EXPECT_EQ(evaluation.methods[0].by_views.at(2).rows, 2u);
}

TEST(Evaluation, MissingEstimateIsAnError) {
  EXPECT_EQ(error_of({kHeader + "s,0,v1,o,3,0,0,9,0,0,9,0,9,b\ns,1,v1,o,1,1,0,1,0,0,1,0,1,b\n"}),
            "e0.csv: method 'b' has no estimate for the row at m.csv:3");
}

TEST(Evaluation, EstimateWithoutMeasurementIsAnError) {
  EXPECT_EQ(error_of({kMethodA + "s,1,v2,o,1,1,0,1,0,0,1,0,1,a\n"}),
            "e0.csv:5: estimate for scene 's', t 1, view 'v2', object 'o' has no matching measurement in m.csv");
}

TEST(Evaluation, MethodsMustCoverTheSameRowsWithoutMeasurements) {
  EXPECT_EQ(error_of({kMethodA, kHeader + "s,0,v1,o,3,0,0,9,0,0,9,0,9,b\n"}, false),
            "e1.csv: method 'b' has no estimate for the row at e0.csv:3");
}

TEST(Evaluation, SameMethodInTwoFilesIsAnError) {
  EXPECT_EQ(error_of({kMethodA, kMethodA}), "e1.csv:2: method 'a' already comes from e0.csv");
}

TEST(Evaluation, EstimateWithoutTruthIsAnError) {
  const std::string no_truth_row = kHeader + "s,0,v1,o,3,0,0,9,0,0,9,0,9,a\n";
  try {
    evaluate(parse_truth("t.csv", "scene,t,object,x,y,z\ns,1,o,1,0,0\n"), {parse_estimates("e.csv", no_truth_row)},
             nullptr, 0);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "e.csv:2: no truth for scene 's', t 0, object 'o' in t.csv");
  }
}

}  // namespace
}  // namespace stgf
