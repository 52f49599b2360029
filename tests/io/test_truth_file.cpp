// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/truth_file.hpp"

#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"
#include "stgf/io/measurement_file.hpp"

namespace stgf {
namespace {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(TruthFile, FindsTruthWithinTheStepTolerance) {
  const TruthFile truth = parse_truth("t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,2,3\ns,0.2,o,4,5,6\n");
  const TruthIndex index(truth);
  EXPECT_EQ(*index.find("s", 0.1 + 5e-7, "o"), Vector3d(1, 2, 3));
  EXPECT_EQ(*index.find("s", 0.2, "o"), Vector3d(4, 5, 6));
  EXPECT_FALSE(index.find("s", 0.15, "o"));
  EXPECT_FALSE(index.find("s", 0.1, "other"));
  EXPECT_TRUE(index.has_scene("s"));
  EXPECT_FALSE(index.has_scene("x"));
}

TEST(TruthFile, MissingColumn) {
  EXPECT_EQ(error_of([] { parse_truth("t.csv", "scene,t,object,x,y\n"); }), "t.csv:1: missing column 'z'");
}

TEST(TruthFile, DuplicateRow) {
  EXPECT_EQ(error_of([] { parse_truth("t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,2,3\ns,0.1,o,1,2,3\n"); }),
            "t.csv:3: duplicate row for scene 's', t 0.1, object 'o' (first at line 2)");
}

TEST(TruthFile, NonFinite) {
  EXPECT_EQ(error_of([] { parse_truth("t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,-inf,3\n"); }),
            "t.csv:2: column 'y': '-inf' is not finite");
}

const std::string kMeasurements =
    "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz\n"
    "s,0.1,v,o,1,2,3,1,0,0,1,0,1\n"
    "s,0.2,v,o,1,2,3,1,0,0,1,0,1\n";

TEST(TruthFile, MeasurementWithoutTruth) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const TruthFile truth = parse_truth("t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,2,3\n");
  EXPECT_EQ(error_of([&] { check_truth_matches(measurements, truth); }),
            "m.csv:3: no truth for scene 's', t 0.2, object 'o' in t.csv");
}

TEST(TruthFile, TruthSceneWithoutMeasurements) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const TruthFile truth =
      parse_truth("t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,2,3\ns,0.2,o,1,2,3\nother,0.1,o,1,2,3\n");
  EXPECT_EQ(error_of([&] { check_truth_matches(measurements, truth); }),
            "t.csv:4: scene 'other' has no measurements in m.csv");
}

TEST(TruthFile, UnmeasuredTruthRowsOfMeasuredScenesAreFine) {
  const MeasurementFile measurements = parse_measurements("m.csv", kMeasurements);
  const TruthFile truth =
      parse_truth("t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,2,3\ns,0.2,o,1,2,3\ns,0.2,hidden,1,2,3\n");
  EXPECT_EQ(error_of([&] { check_truth_matches(measurements, truth); }), "no error");
}

// Scene by scene: each scene's rows with their lines, the whole reader's checks, and a scene that
// comes back named at its line.
TEST(TruthSceneReader, ReadsOneSceneAtATime) {
  TruthSceneReader reader = TruthSceneReader::from_text(
      "t.csv", "scene,t,object,x,y,z\ns,0.1,o,1,2,3\ns,0.2,o,1,2,4\nr,0.1,o,5,6,7\n");
  TruthFile scene;
  ASSERT_TRUE(reader.read(scene));
  EXPECT_EQ(scene.path, "t.csv");
  ASSERT_EQ(scene.rows.size(), 2u);
  EXPECT_EQ(scene.lines, (std::vector<int>{2, 3}));
  EXPECT_EQ(scene.rows[1].position, Vector3d(1, 2, 4));
  ASSERT_TRUE(reader.read(scene));
  EXPECT_EQ(scene.rows.size(), 1u);
  EXPECT_EQ(scene.rows[0].scene, "r");
  EXPECT_EQ(scene.lines, std::vector<int>{4});
  EXPECT_FALSE(reader.read(scene));
}

TEST(TruthSceneReader, RejectsWhatTheWholeReaderRejectsAndScenesThatComeBack) {
  const auto scene_by_scene = [](const std::string& text) {
    return error_of([&] {
      TruthSceneReader reader = TruthSceneReader::from_text("t.csv", text);
      TruthFile scene;
      while (reader.read(scene)) {
      }
    });
  };
  for (const std::string text : {"scene,t,object,x,y\n", "scene,t,object,x,y,z\ns,0,o,1,2,3\nr,0,o,1,x,3\n",
                                 "scene,t,object,x,y,z\ns,0,o,1,2,3\nr,0,o,1,2,3\nr,0.0000001,o,1,2,3\n"}) {
    EXPECT_NE(error_of([&] { parse_truth("t.csv", text); }), "no error") << text;
    EXPECT_EQ(scene_by_scene(text), error_of([&] { parse_truth("t.csv", text); })) << text;
  }
  EXPECT_EQ(scene_by_scene("scene,t,object,x,y,z\ns,0,o,1,2,3\nr,0,o,1,2,3\ns,1,o,1,2,3\n").substr(0, 74),
            "t.csv:4: scene 's' appears again after other scenes (its rows ended at lin");
}

}  // namespace
}  // namespace stgf
