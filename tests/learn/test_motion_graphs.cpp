// SPDX-License-Identifier: Apache-2.0
// The motion graphs of a measurement list (model/motion_graphs.hpp): hand-built cases whose graphs
// are written out in full, and a synthetic benchmark checked against a brute-force reference.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "stgf/core/multi_view_update.hpp"
#include "stgf/datasets/synthetic.hpp"
#include "stgf/io/truth_file.hpp"
#include "stgf/model/motion_graphs.hpp"

namespace stgf {
namespace {

// ── Helpers ──

Matrix3d diagonal(double xx, double yy, double zz) { return Vector3d(xx, yy, zz).asDiagonal(); }

Measurement row(const std::string& scene, double time, const std::string& view, const std::string& object,
                const Vector3d& position, const Matrix3d& covariance = Matrix3d::Identity()) {
  return Measurement{scene,       time, view, object, Gaussian3::from_covariance(position, covariance),
                     std::nullopt};
}

// A position that tells rows apart: (step, view number, object number).
Vector3d marker(double step, double view, double object) { return Vector3d(step, view, object); }

TruthIndex truth_index(const std::vector<TruthPoint>& points) {
  TruthFile file;
  file.path = "truth.csv";
  file.rows = points;
  file.lines.assign(points.size(), 0);
  return TruthIndex(file);
}

// The true position of an object in the hand-built cases: a function of time and name.
Vector3d true_position_at(double time, const std::string& object) {
  return Vector3d(10.0 * time, static_cast<double>(object.size()), -time);
}

std::vector<TruthPoint> truth_at(const std::string& scene, std::vector<double> times,
                                 const std::vector<std::string>& objects) {
  std::vector<TruthPoint> points;
  for (double time : times) {
    for (const std::string& object : objects) {
      points.push_back(TruthPoint{scene, time, object, true_position_at(time, object)});
    }
  }
  return points;
}

const ObjectHistory& history_of(const MotionGraphSet& set, std::size_t row) {
  const GraphObjectIndex index = set.predictor_of_row.at(row).value();
  return set.graphs.at(index.graph).objects.at(index.object);
}

// "scene/view@target_time", for comparing graph lists.
std::string graph_key(const MotionGraph& graph) {
  std::ostringstream key;
  key << graph.scene << '/' << graph.view << '@' << graph.target_time;
  return key.str();
}

// The message of the std::invalid_argument that `call` throws, or "" when it throws nothing.
template <class Call>
std::string invalid_argument_message(Call&& call) {
  try {
    call();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

std::vector<std::string> object_names(const MotionGraph& graph) {
  std::vector<std::string> names;
  for (const ObjectHistory& object : graph.objects) names.push_back(object.object);
  return names;
}

void expect_same_graphs(const std::vector<MotionGraph>& a, const std::vector<MotionGraph>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t g = 0; g < a.size(); ++g) {
    EXPECT_EQ(a[g].scene, b[g].scene);
    EXPECT_EQ(a[g].view, b[g].view);
    EXPECT_EQ(a[g].target_time, b[g].target_time);
    ASSERT_EQ(a[g].objects.size(), b[g].objects.size());
    for (std::size_t i = 0; i < a[g].objects.size(); ++i) {
      EXPECT_EQ(a[g].objects[i].object, b[g].objects[i].object);
      EXPECT_EQ(a[g].objects[i].times, b[g].objects[i].times);
      EXPECT_EQ(a[g].objects[i].positions, b[g].objects[i].positions);
    }
  }
}

// ── kRawView ──

// Scene "s", steps 0.0 … 0.3. View v1 sees a at every step; v2 sees a at steps 1 and 3 and b at 0, 1.
std::vector<Measurement> two_view_scene() {
  return {
      row("s", 0.0, "v1", "a", marker(0, 1, 1)), row("s", 0.0, "v2", "b", marker(0, 2, 2)),
      row("s", 0.1, "v1", "a", marker(1, 1, 1)), row("s", 0.1, "v2", "a", marker(1, 2, 1)),
      row("s", 0.1, "v2", "b", marker(1, 2, 2)), row("s", 0.2, "v1", "a", marker(2, 1, 1)),
      row("s", 0.3, "v1", "a", marker(3, 1, 1)), row("s", 0.3, "v2", "a", marker(3, 2, 1)),
  };
}

TEST(MotionGraphsRawView, HistoriesAreTheViewsOwnPastMeasurementsOldestFirst) {
  const std::vector<Measurement> rows = two_view_scene();
  const MotionGraphSet set = make_motion_graph_set(rows, HistorySource::kRawView, 8);

  // 0.1: v1 (a), v2 (b; a is v2's first sighting). 0.2: v1 (a). 0.3: v1 (a), v2 (a: seen by v2 at 0.1).
  ASSERT_EQ(set.graphs.size(), 5u);
  const std::vector<std::string> expected = {"s/v1@0.1", "s/v2@0.1", "s/v1@0.2", "s/v1@0.3", "s/v2@0.3"};
  for (std::size_t g = 0; g < expected.size(); ++g) EXPECT_EQ(graph_key(set.graphs[g]), expected[g]);
  EXPECT_EQ(object_names(set.graphs[1]), std::vector<std::string>{"b"});

  const ObjectHistory& a_v1 = history_of(set, 6);  // v1 sees a at 0.3
  EXPECT_EQ(a_v1.object, "a");
  EXPECT_EQ(a_v1.positions, (std::vector<Vector3d>{marker(0, 1, 1), marker(1, 1, 1), marker(2, 1, 1)}));
  EXPECT_EQ(a_v1.times, (std::vector<double>{0.0, 0.1, 0.2}));

  const ObjectHistory& a_v2 = history_of(set, 7);  // v2 sees a at 0.3: only its own sighting at 0.1
  EXPECT_EQ(a_v2.positions, std::vector<Vector3d>{marker(1, 2, 1)});
  EXPECT_EQ(a_v2.times, std::vector<double>{0.1});
}

TEST(MotionGraphsRawView, FirstSightingOfEachViewHasNoGraphObject) {
  const std::vector<Measurement> rows = two_view_scene();
  const MotionGraphSet set = make_motion_graph_set(rows, HistorySource::kRawView, 8);
  ASSERT_EQ(set.predictor_of_row.size(), rows.size());
  // Rows 0 and 1 are step 0; row 3 is v2's first sighting of a, although v1 saw a before.
  EXPECT_FALSE(set.predictor_of_row[0]);
  EXPECT_FALSE(set.predictor_of_row[1]);
  EXPECT_FALSE(set.predictor_of_row[3]);
  EXPECT_EQ(set.predictor_of_row[2], (GraphObjectIndex{0, 0}));
  EXPECT_EQ(set.predictor_of_row[4], (GraphObjectIndex{1, 0}));
  EXPECT_EQ(set.predictor_of_row[5], (GraphObjectIndex{2, 0}));
  EXPECT_EQ(set.predictor_of_row[6], (GraphObjectIndex{3, 0}));
  EXPECT_EQ(set.predictor_of_row[7], (GraphObjectIndex{4, 0}));
  // Every graph object is the predictor of exactly one row, and of a row of its view and object.
  std::size_t graph_objects = 0;
  for (const MotionGraph& graph : set.graphs) graph_objects += graph.objects.size();
  std::set<std::pair<std::size_t, std::size_t>> seen;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (!set.predictor_of_row[k]) continue;
    const GraphObjectIndex index = *set.predictor_of_row[k];
    EXPECT_TRUE(seen.insert({index.graph, index.object}).second);
    EXPECT_EQ(set.graphs[index.graph].view, rows[k].view);
    EXPECT_EQ(set.graphs[index.graph].objects[index.object].object, rows[k].object);
    EXPECT_EQ(set.graphs[index.graph].target_time, rows[k].time);
  }
  EXPECT_EQ(seen.size(), graph_objects);
}

TEST(MotionGraphsRawView, LatestCovarianceIsTheRofTheLatestMeasurement) {
  std::vector<Measurement> rows = {row("s", 0.0, "v", "a", marker(0, 0, 0), diagonal(1, 2, 3)),
                                   row("s", 0.1, "v", "a", marker(1, 0, 0), diagonal(4, 5, 6)),
                                   row("s", 0.2, "v", "a", marker(2, 0, 0), diagonal(7, 8, 9))};
  const MotionGraphSet set = make_motion_graph_set(rows, HistorySource::kRawView, 8);
  ASSERT_EQ(set.latest_covariances.size(), 2u);
  EXPECT_EQ(set.latest_covariances[0], std::vector<Matrix3d>{diagonal(1, 2, 3)});
  EXPECT_EQ(set.latest_covariances[1], std::vector<Matrix3d>{diagonal(4, 5, 6)});

  const TruthIndex truth = truth_index(truth_at("s", {0.0, 0.1, 0.2}, {"a"}));
  const std::vector<TrainingGraph> training = make_training_graphs(rows, truth, HistorySource::kRawView, 8);
  ASSERT_EQ(training.size(), 2u);
  EXPECT_EQ(training[1].history_covariances[0],
            (std::vector<Matrix3d>{diagonal(1, 2, 3), diagonal(4, 5, 6)}));
}

// ── Both sources ──

class MotionGraphsBothSources : public ::testing::TestWithParam<HistorySource> {};

INSTANTIATE_TEST_SUITE_P(Sources, MotionGraphsBothSources,
                         ::testing::Values(HistorySource::kRawView, HistorySource::kFused),
                         [](const ::testing::TestParamInfo<HistorySource>& source) {
                           return source.param == HistorySource::kRawView ? std::string("RawView")
                                                                          : std::string("Fused");
                         });

// One view, one object, seen at steps 0 … 5 at times 0, 0.1, … 0.5; position (step, 0, 0).
std::vector<Measurement> six_steps() {
  std::vector<Measurement> rows;
  for (int step = 0; step < 6; ++step) rows.push_back(row("s", 0.1 * step, "v", "a", marker(step, 0, 0)));
  return rows;
}

TEST_P(MotionGraphsBothSources, HistoryIsTruncatedToTheLastHistoryLengthPositions) {
  const std::vector<Measurement> rows = six_steps();
  for (int history_length : {1, 3, 5, 9}) {
    SCOPED_TRACE(history_length);
    const MotionGraphSet set = make_motion_graph_set(rows, GetParam(), history_length);
    ASSERT_EQ(set.graphs.size(), 5u);
    for (std::size_t step = 1; step < 6; ++step) {
      const ObjectHistory& history = history_of(set, step);
      const std::size_t expected_length = std::min<std::size_t>(step, history_length);
      ASSERT_EQ(history.positions.size(), expected_length);
      ASSERT_EQ(history.times.size(), expected_length);
      for (std::size_t k = 0; k < expected_length; ++k) {
        const std::size_t from_step = step - expected_length + k;
        EXPECT_EQ(history.positions[k], marker(static_cast<double>(from_step), 0, 0));
        EXPECT_EQ(history.times[k], rows[from_step].time);
      }
    }
  }
}

TEST_P(MotionGraphsBothSources, MissedStepsLeaveAGapWithTheRealTimes) {
  // Uneven times; a is missed at 0.25 and 0.5 (b keeps those steps alive), then seen again at 0.9.
  const std::vector<Measurement> rows = {
      row("s", 0.0, "v", "a", marker(0, 0, 1)), row("s", 0.0, "v", "b", marker(0, 0, 2)),
      row("s", 0.1, "v", "a", marker(1, 0, 1)), row("s", 0.25, "v", "b", marker(2, 0, 2)),
      row("s", 0.5, "v", "b", marker(3, 0, 2)), row("s", 0.9, "v", "a", marker(4, 0, 1)),
  };
  const MotionGraphSet set = make_motion_graph_set(rows, GetParam(), 8);
  const ObjectHistory& a = history_of(set, 5);
  EXPECT_EQ(a.positions, (std::vector<Vector3d>{marker(0, 0, 1), marker(1, 0, 1)}));
  EXPECT_EQ(a.times, (std::vector<double>{0.0, 0.1}));
  const GraphObjectIndex index = *set.predictor_of_row[5];
  EXPECT_EQ(set.graphs[index.graph].target_time, 0.9);
  EXPECT_EQ(object_names(set.graphs[index.graph]), std::vector<std::string>{"a"});  // b not seen at 0.9
  const ObjectHistory& b = history_of(set, 4);
  EXPECT_EQ(b.times, (std::vector<double>{0.0, 0.25}));
}

// With a maximum gap, a track whose last entry is older than it starts again: no graph object at
// that step (like a first sighting), and the next history begins after the gap.
TEST_P(MotionGraphsBothSources, GapLongerThanMaxGapStartsTheTrackAgain) {
  const std::vector<Measurement> rows = {
      row("s", 0.0, "v", "a", marker(0, 0, 1)), row("s", 0.1, "v", "a", marker(1, 0, 1)),
      row("s", 0.2, "v", "b", marker(2, 0, 2)), row("s", 0.4, "v", "a", marker(3, 0, 1)),  // 0.3 s: kept
      row("s", 1.0, "v", "a", marker(4, 0, 1)),                                             // 0.6 s: restarts
      row("s", 1.1, "v", "a", marker(5, 0, 1)),
  };
  const MotionGraphSet whole = make_motion_graph_set(rows, GetParam(), 8);
  EXPECT_EQ(whole.restarted_tracks, 0u);
  EXPECT_TRUE(whole.predictor_of_row[4].has_value());
  const MotionGraphSet set = make_motion_graph_set(rows, GetParam(), 8, 0.5);
  EXPECT_EQ(set.restarted_tracks, 1u);
  EXPECT_EQ(history_of(set, 3).times, (std::vector<double>{0.0, 0.1}));
  EXPECT_FALSE(set.predictor_of_row[4].has_value());
  EXPECT_EQ(history_of(set, 5).times, (std::vector<double>{1.0}));
}

TEST_P(MotionGraphsBothSources, TimesAreStepTimesAndStrictlyIncreaseUpToTheTarget) {
  // Rows of one step spread over less than 1e-6 s: every time in a graph is the step's earliest time.
  const std::vector<Measurement> rows = {
      row("s", 1.0 + 4e-7, "v1", "a", marker(0, 1, 1)), row("s", 1.0, "v2", "a", marker(0, 2, 1)),
      row("s", 1.0 + 2e-6, "v1", "a", marker(1, 1, 1)), row("s", 1.0 + 2.5e-6, "v2", "a", marker(1, 2, 1)),
      row("s", 1.1, "v2", "a", marker(2, 2, 1)),        row("s", 1.1 + 9e-7, "v1", "a", marker(2, 1, 1)),
  };
  const MotionGraphSet set = make_motion_graph_set(rows, GetParam(), 8);
  ASSERT_FALSE(set.graphs.empty());
  for (const MotionGraph& graph : set.graphs) {
    EXPECT_TRUE(graph.target_time == 1.0 + 2e-6 || graph.target_time == 1.1) << graph.target_time;
    for (const ObjectHistory& object : graph.objects) {
      ASSERT_EQ(object.times.size(), object.positions.size());
      ASSERT_FALSE(object.times.empty());
      EXPECT_EQ(object.times.front(), 1.0);
      for (std::size_t k = 1; k < object.times.size(); ++k) EXPECT_LT(object.times[k - 1], object.times[k]);
      EXPECT_LT(object.times.back(), graph.target_time);
    }
  }
}

TEST_P(MotionGraphsBothSources, GraphsAndObjectsComeInADeterministicOrder) {
  // Scene "b" appears first; rows of a step are not sorted by view or object; "a" is listed out of time
  // order.
  const std::vector<Measurement> rows = {
      row("b", 0.0, "w", "y", marker(0, 1, 1)), row("b", 0.0, "u", "x", marker(0, 2, 2)),
      row("a", 0.5, "u", "q", marker(1, 2, 3)), row("b", 0.1, "w", "x", marker(1, 1, 2)),
      row("b", 0.1, "u", "x", marker(1, 2, 2)), row("b", 0.1, "w", "y", marker(1, 1, 1)),
      row("a", 0.0, "u", "q", marker(0, 2, 3)), row("b", 0.0, "w", "x", marker(0, 1, 2)),
  };
  const MotionGraphSet set = make_motion_graph_set(rows, GetParam(), 8);
  if (GetParam() == HistorySource::kRawView) {
    // b@0.1: views in order of first appearance at the step (w, then u); objects likewise.
    ASSERT_EQ(set.graphs.size(), 3u);
    EXPECT_EQ(graph_key(set.graphs[0]), "b/w@0.1");
    EXPECT_EQ(object_names(set.graphs[0]), (std::vector<std::string>{"x", "y"}));
    EXPECT_EQ(graph_key(set.graphs[1]), "b/u@0.1");
    EXPECT_EQ(object_names(set.graphs[1]), std::vector<std::string>{"x"});
    EXPECT_EQ(graph_key(set.graphs[2]), "a/u@0.5");
  } else {
    ASSERT_EQ(set.graphs.size(), 2u);
    EXPECT_EQ(graph_key(set.graphs[0]), "b/@0.1");
    EXPECT_EQ(object_names(set.graphs[0]), (std::vector<std::string>{"x", "y"}));
    EXPECT_EQ(set.predictor_of_row[3], set.predictor_of_row[4]);  // x at b@0.1, from both views
    EXPECT_EQ(graph_key(set.graphs[1]), "a/@0.5");
  }
  expect_same_graphs(set.graphs, make_motion_graph_set(rows, GetParam(), 8).graphs);
  expect_same_graphs(set.graphs, make_motion_graphs(rows, GetParam(), 8));
}

TEST_P(MotionGraphsBothSources, TargetsAndTrueHistoriesAreTheTruthAtTheGraphsTimes) {
  const std::vector<Measurement> rows = two_view_scene();
  // Truth times off by less than the step tolerance still match.
  std::vector<TruthPoint> points = truth_at("s", {0.0, 0.1, 0.2, 0.3}, {"a", "b"});
  for (TruthPoint& point : points) point.time += 5e-7;
  const TruthIndex truth = truth_index(points);

  const std::vector<TrainingGraph> training = make_training_graphs(rows, truth, GetParam(), 2);
  const std::vector<MotionGraph> graphs = make_motion_graphs(rows, GetParam(), 2);
  ASSERT_EQ(training.size(), graphs.size());
  std::vector<MotionGraph> training_graphs;
  for (const TrainingGraph& graph : training) training_graphs.push_back(graph.graph);
  expect_same_graphs(training_graphs, graphs);

  std::size_t objects = 0;
  for (const TrainingGraph& graph : training) {
    ASSERT_EQ(graph.targets.size(), graph.graph.objects.size());
    ASSERT_EQ(graph.true_histories.size(), graph.graph.objects.size());
    ASSERT_EQ(graph.history_covariances.size(), graph.graph.objects.size());
    for (std::size_t i = 0; i < graph.graph.objects.size(); ++i) {
      const ObjectHistory& history = graph.graph.objects[i];
      EXPECT_EQ(graph.targets[i], true_position_at(graph.graph.target_time, history.object));
      ASSERT_EQ(graph.true_histories[i].size(), history.times.size());
      ASSERT_EQ(graph.history_covariances[i].size(), history.times.size());
      for (std::size_t k = 0; k < history.times.size(); ++k) {
        EXPECT_EQ(graph.true_histories[i][k], true_position_at(history.times[k], history.object));
        // Every R is I: one measurement for kRawView, I / (views that saw it) for kFused.
        const double views =
            GetParam() == HistorySource::kRawView
                ? 1.0
                : static_cast<double>(std::count_if(rows.begin(), rows.end(), [&](const Measurement& m) {
                    return m.object == history.object && m.time == history.times[k];
                  }));
        EXPECT_LT((graph.history_covariances[i][k] - Matrix3d::Identity() / views).norm(), 1e-15);
      }
      ++objects;
    }
  }
  EXPECT_GT(objects, 0u);
}

// Without truth, each object's target is what was measured of it at the target time: the step's
// fused position (kFused) or the view's own measurement (kRawView), with its covariance.
TEST_P(MotionGraphsBothSources, MeasuredTargetsAreWhatWasMeasuredAtTheTargetTime) {
  const std::vector<Measurement> rows = two_view_scene();
  const std::vector<TrainingGraph> training = make_measured_training_graphs(rows, GetParam(), 2);
  std::vector<MotionGraph> training_graphs;
  for (const TrainingGraph& graph : training) training_graphs.push_back(graph.graph);
  expect_same_graphs(training_graphs, make_motion_graphs(rows, GetParam(), 2));
  std::size_t objects = 0;
  for (const TrainingGraph& graph : training) {
    ASSERT_EQ(graph.targets.size(), graph.graph.objects.size());
    ASSERT_EQ(graph.target_covariances.size(), graph.graph.objects.size());
    ASSERT_EQ(graph.history_covariances.size(), graph.graph.objects.size());
    EXPECT_TRUE(graph.true_histories.empty());
    for (std::size_t i = 0; i < graph.graph.objects.size(); ++i) {
      std::vector<Gaussian3> measured;
      for (const Measurement& m : rows) {
        const bool same_view = GetParam() == HistorySource::kFused || m.view == graph.graph.view;
        if (m.object == graph.graph.objects[i].object && m.time == graph.graph.target_time && same_view) {
          measured.push_back(m.position);
        }
      }
      ASSERT_FALSE(measured.empty());
      const Gaussian3 expected = information_weighted_mean(measured);
      EXPECT_LT((graph.targets[i] - expected.mean()).norm(), 1e-12);
      EXPECT_LT((graph.target_covariances[i] - expected.covariance()).norm(), 1e-12);
      ++objects;
    }
  }
  EXPECT_GT(objects, 0u);
}

TEST_P(MotionGraphsBothSources, MissingTruthThrowsNamingSceneTimeAndObject) {
  const std::vector<Measurement> rows = two_view_scene();
  std::vector<TruthPoint> points = truth_at("s", {0.0, 0.1, 0.2, 0.3}, {"a", "b"});
  // Without b at 0.0 (a history position of b at 0.1).
  std::erase_if(points, [](const TruthPoint& point) { return point.object == "b" && point.time == 0.0; });
  const std::string message =
      invalid_argument_message([&] { make_training_graphs(rows, truth_index(points), GetParam(), 8); });
  EXPECT_NE(message.find("scene 's', t 0, object 'b'"), std::string::npos) << message;
  // Without a at 0.3 (a target).
  points = truth_at("s", {0.0, 0.1, 0.2, 0.3}, {"a", "b"});
  std::erase_if(points, [](const TruthPoint& point) { return point.object == "a" && point.time == 0.3; });
  const std::string target_message =
      invalid_argument_message([&] { make_training_graphs(rows, truth_index(points), GetParam(), 8); });
  EXPECT_NE(target_message.find("scene 's', t 0.3, object 'a'"), std::string::npos) << target_message;
}

TEST_P(MotionGraphsBothSources, TruthIsNeededOnlyWhereAGraphUsesIt) {
  // c is seen once: it is in no graph and needs no truth.
  std::vector<Measurement> rows = six_steps();
  rows.push_back(row("s", 0.2, "v", "c", marker(2, 0, 3)));
  const TruthIndex truth = truth_index(truth_at("s", {0.0, 0.1, 0.2, 0.3, 0.4, 0.5}, {"a"}));
  EXPECT_EQ(make_training_graphs(rows, truth, GetParam(), 3).size(), 5u);
}

TEST_P(MotionGraphsBothSources, RejectsBadInput) {
  const std::vector<Measurement> rows = six_steps();
  EXPECT_THROW(make_motion_graph_set(rows, GetParam(), 0), std::invalid_argument);
  std::vector<Measurement> duplicated = rows;
  duplicated.push_back(row("s", 0.2 + 5e-7, "v", "a", marker(9, 9, 9)));
  const std::string message =
      invalid_argument_message([&] { make_motion_graph_set(duplicated, GetParam(), 8); });
  EXPECT_NE(message.find("scene 's'"), std::string::npos) << message;
  EXPECT_NE(message.find("view 'v'"), std::string::npos) << message;
  EXPECT_NE(message.find("object 'a'"), std::string::npos) << message;
  EXPECT_TRUE(make_motion_graph_set({}, GetParam(), 8).graphs.empty());
}

// ── kFused ──

TEST(MotionGraphsFused, HistoryIsTheInformationWeightedMeanOfEachStepsMeasurements) {
  // Two views with different anisotropic R; a is seen by both at 0.0, by v2 only at 0.1, by both at 0.2.
  const Matrix3d r1 = (Matrix3d() << 2.0, 0.3, 0.1, 0.3, 1.0, 0.2, 0.1, 0.2, 0.5).finished();
  const Matrix3d r2 = diagonal(0.2, 3.0, 1.5);
  const std::vector<Measurement> rows = {
      row("s", 0.0, "v1", "a", Vector3d(1.0, 2.0, 3.0), r1),
      row("s", 0.0, "v2", "a", Vector3d(1.5, 1.0, 2.0), r2),
      row("s", 0.1, "v2", "a", Vector3d(2.0, 2.5, 3.5), r2),
      row("s", 0.2, "v2", "a", Vector3d(3.0, 3.0, 3.0), r2),
      row("s", 0.2, "v1", "a", Vector3d(2.5, 3.5, 4.0), r1),
      row("s", 0.3, "v1", "a", Vector3d(0.0, 0.0, 0.0), r1),
  };
  const MotionGraphSet set = make_motion_graph_set(rows, HistorySource::kFused, 8);
  ASSERT_EQ(set.graphs.size(), 3u);
  for (const MotionGraph& graph : set.graphs) EXPECT_EQ(graph.view, "");

  const std::vector<Gaussian3> at_0 = {rows[0].position, rows[1].position};
  const std::vector<Gaussian3> at_2 = {rows[3].position, rows[4].position};
  const std::vector<Gaussian3> fused = {information_weighted_mean(at_0), rows[2].position,
                                        information_weighted_mean(at_2)};
  // The fusion is not a plain average (guards against a test that cannot fail).
  EXPECT_GT((fused[0].mean() - 0.5 * (rows[0].position.mean() + rows[1].position.mean())).norm(), 0.1);

  const ObjectHistory& history = history_of(set, 5);
  ASSERT_EQ(history.positions.size(), 3u);
  EXPECT_EQ(history.times, (std::vector<double>{0.0, 0.1, 0.2}));
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_LT((history.positions[k] - fused[k].mean()).norm(), 1e-12) << k;
  }
  EXPECT_LT((set.latest_covariances[2][0] - fused[2].covariance()).norm(), 1e-12);

  const TruthIndex truth = truth_index(truth_at("s", {0.0, 0.1, 0.2, 0.3}, {"a"}));
  const std::vector<TrainingGraph> training = make_training_graphs(rows, truth, HistorySource::kFused, 8);
  ASSERT_EQ(training.size(), 3u);
  ASSERT_EQ(training[2].history_covariances[0].size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_LT((training[2].history_covariances[0][k] - fused[k].covariance()).norm(), 1e-12) << k;
  }
  // Both rows of a at 0.2 are predicted by the same graph object.
  EXPECT_EQ(set.predictor_of_row[3], set.predictor_of_row[4]);
  ASSERT_TRUE(set.predictor_of_row[3]);
  EXPECT_EQ(history_of(set, 3).times, (std::vector<double>{0.0, 0.1}));
}

TEST(MotionGraphsFused, ObjectsSeenByAnyViewBeforeHaveAHistoryFirstSightingsDoNot) {
  // a: v1 at 0.0, v2 at 0.1 (history from v1's sighting); b: first seen at 0.1 by both views.
  const std::vector<Measurement> rows = {
      row("s", 0.0, "v1", "a", marker(0, 1, 1)),
      row("s", 0.1, "v2", "b", marker(1, 2, 2)),
      row("s", 0.1, "v2", "a", marker(1, 2, 1)),
      row("s", 0.1, "v1", "b", marker(1, 1, 2)),
  };
  const MotionGraphSet set = make_motion_graph_set(rows, HistorySource::kFused, 8);
  ASSERT_EQ(set.graphs.size(), 1u);
  EXPECT_EQ(object_names(set.graphs[0]), std::vector<std::string>{"a"});
  EXPECT_FALSE(set.predictor_of_row[0]);
  EXPECT_FALSE(set.predictor_of_row[1]);
  EXPECT_EQ(set.predictor_of_row[2], (GraphObjectIndex{0, 0}));
  EXPECT_FALSE(set.predictor_of_row[3]);
  EXPECT_EQ(set.graphs[0].objects[0].positions, std::vector<Vector3d>{marker(0, 1, 1)});
}

// ── A synthetic benchmark against a brute-force reference ──

SyntheticOptions small_synthetic_options() {
  SyntheticOptions options;
  options.seed = 7;
  options.scenes = 3;
  options.objects = 5;
  options.views = 3;
  options.steps = 12;
  options.max_range_m = 40.0;  // objects are often missed by every view: gaps and late first sightings
  options.detection_probability_far = 0.3;
  return options;
}

// The reference: for row k, the rows of the same scene (and view, for kRawView) and object at earlier
// steps, by brute force over all rows.
struct Reference {
  std::vector<double> times;
  std::vector<Vector3d> positions;
};

Reference reference_history(const std::vector<Measurement>& rows, std::size_t k, HistorySource source,
                            std::size_t history_length) {
  std::map<double, std::vector<Gaussian3>> earlier;  // synthetic rows of a step share one time
  for (const Measurement& other : rows) {
    if (other.scene != rows[k].scene || other.object != rows[k].object) continue;
    if (source == HistorySource::kRawView && other.view != rows[k].view) continue;
    if (other.time < rows[k].time - kSameStepTolerance) earlier[other.time].push_back(other.position);
  }
  Reference reference;
  for (const auto& [time, measurements] : earlier) {
    reference.times.push_back(time);
    reference.positions.push_back(information_weighted_mean(measurements).mean());
  }
  const std::size_t drop = reference.times.size() - std::min(reference.times.size(), history_length);
  reference.times.erase(reference.times.begin(), reference.times.begin() + static_cast<std::ptrdiff_t>(drop));
  reference.positions.erase(reference.positions.begin(),
                            reference.positions.begin() + static_cast<std::ptrdiff_t>(drop));
  return reference;
}

TEST_P(MotionGraphsBothSources, SyntheticBenchmarkMatchesABruteForceReference) {
  const Benchmark benchmark = make_synthetic_benchmark(small_synthetic_options());
  const std::vector<Measurement>& rows = benchmark.test.measurements;
  constexpr int kHistoryLength = 4;
  const MotionGraphSet set = make_motion_graph_set(rows, GetParam(), kHistoryLength);
  ASSERT_EQ(set.predictor_of_row.size(), rows.size());

  std::size_t first_sightings = 0, gaps = 0, truncated = 0;
  std::set<std::pair<std::size_t, std::size_t>> predictors;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    SCOPED_TRACE(::testing::Message() << "row " << k << ": " << rows[k].scene << " t " << rows[k].time
                                      << " view " << rows[k].view << " object " << rows[k].object);
    const Reference reference = reference_history(rows, k, GetParam(), kHistoryLength);
    if (reference.times.empty()) {
      EXPECT_FALSE(set.predictor_of_row[k]);
      ++first_sightings;
      continue;
    }
    ASSERT_TRUE(set.predictor_of_row[k]);
    const GraphObjectIndex index = *set.predictor_of_row[k];
    predictors.insert({index.graph, index.object});
    const MotionGraph& graph = set.graphs[index.graph];
    EXPECT_EQ(graph.scene, rows[k].scene);
    EXPECT_EQ(graph.view, GetParam() == HistorySource::kRawView ? rows[k].view : std::string());
    EXPECT_EQ(graph.target_time, rows[k].time);
    const ObjectHistory& history = graph.objects[index.object];
    EXPECT_EQ(history.object, rows[k].object);
    EXPECT_EQ(history.times, reference.times);
    ASSERT_EQ(history.positions.size(), reference.positions.size());
    for (std::size_t j = 0; j < reference.positions.size(); ++j) {
      EXPECT_LT((history.positions[j] - reference.positions[j]).norm(), 1e-12);
    }
    if (reference.times.size() == kHistoryLength) ++truncated;
    for (std::size_t j = 1; j < history.times.size(); ++j) {
      if (history.times[j] - history.times[j - 1] > 0.15) ++gaps;  // 10 Hz: a missed step
    }
  }
  // The benchmark exercises what this test claims to check.
  EXPECT_GT(first_sightings, 0u);
  EXPECT_GT(gaps, 0u);
  EXPECT_GT(truncated, 0u);
  EXPECT_LT(first_sightings, rows.size() / 4);
  // Graphs hold nothing but the predictors of rows, ordered by scene, then time.
  std::size_t graph_objects = 0;
  for (const MotionGraph& graph : set.graphs) graph_objects += graph.objects.size();
  EXPECT_EQ(predictors.size(), graph_objects);
  for (std::size_t g = 1; g < set.graphs.size(); ++g) {
    if (set.graphs[g].scene == set.graphs[g - 1].scene) {
      EXPECT_GE(set.graphs[g].target_time, set.graphs[g - 1].target_time);
    }
  }

  // The training graphs of the benchmark's truth: targets are the truth at the rows' times.
  TruthFile truth_file;
  truth_file.rows = benchmark.test.truth;
  const TruthIndex truth(truth_file);
  const std::vector<TrainingGraph> training = make_training_graphs(rows, truth, GetParam(), kHistoryLength);
  ASSERT_EQ(training.size(), set.graphs.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (!set.predictor_of_row[k]) continue;
    const GraphObjectIndex index = *set.predictor_of_row[k];
    EXPECT_EQ(training[index.graph].targets[index.object],
              *truth.find(rows[k].scene, rows[k].time, rows[k].object));
  }
}

}  // namespace
}  // namespace stgf
