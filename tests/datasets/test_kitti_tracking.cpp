// SPDX-License-Identifier: Apache-2.0
// KITTI tracking readers and the world-frame conversion (datasets/kitti_tracking.hpp).
//
// The data are not in the repository (licence); the tests that need them skip when STGF_KITTI_DIR
// does not exist. The reader tests on small hand-written files always run.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "stgf/datasets/kitti_tracking.hpp"
#include "stgf/io/input_error.hpp"
#include "support/input_errors.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using testing::expect_input_error;
using testing::ScratchDirectory;

const char* const kKittiDirectory = STGF_KITTI_DIR;
const std::string kDerivedDirectory = std::string(STGF_SHARED_DATA_DIR) + "/kitti_tracking/derived";
const std::vector<std::string> kSequences = {"0002", "0003", "0004", "0005", "0006",
                                             "0008", "0010", "0011", "0018", "0020"};

#define SKIP_WITHOUT_KITTI()                                                                        \
  do {                                                                                              \
    if (!fs::is_directory(kKittiDirectory)) GTEST_SKIP() << "no KITTI data at " << kKittiDirectory; \
  } while (false)

// Splits a CSV line at commas (the derived files have no quotes).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  return fields;
}

const std::string kGoodLabel = "0 3 Car 0 1 -1.5 100.0 150.0 200.0 250.0 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n";
const std::string kGoodOxts =
    "49.0 8.4 115.0 0.01 0.02 1.5 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 4 8 4 4 0\n";
std::string good_calibration(bool colons = true) {
  const std::string c = colons ? ":" : "";
  const std::string p = " 700 0 600 0 0 700 170 0 0 0 1 0\n";
  return "P0" + c + p + "P1" + c + p + "P2" + c + p + "P3" + c + p + "R_rect" + c +
         " 0.9999 0.0098 -0.0074 -0.0099 0.9999 -0.0043 0.0074 0.0044 0.9999\n" + "Tr_velo_cam" + c +
         " 0.0075 -0.9999 -0.0006 -0.0041 0.0148 0.0007 -0.9999 -0.0763 0.9999 0.0075 0.0148 -0.2718\n" +
         "Tr_imu_velo" + c +
         " 0.9999 0.0008 -0.0020 -0.8087 -0.0008 0.9999 -0.0148 0.3196 0.0020 0.0148 0.9999 -0.7997\n";
}

// ── Affine maps and the Mercator pose (no data needed) ──

TEST(KittiTracking, AffineInverseUndoesTheMap) {
  AffineTransform3 map;
  map.linear << 0.9, -0.3, 0.1, 0.2, 1.1, -0.4, 0.05, 0.3, 0.8;
  map.translation << 12.0, -3.5, 0.7;
  const AffineTransform3 back = inverse(map);
  for (const Vector3d& point :
       {Vector3d(1.0, 2.0, 3.0), Vector3d(-40.0, 7.5, 0.25), Vector3d::Zero().eval()}) {
    EXPECT_LT((back.apply(map.apply(point)) - point).norm(), 1e-12);
    EXPECT_LT((compose(map, back).apply(point) - point).norm(), 1e-12);
  }
  EXPECT_EQ(map.apply_linear(Vector3d(1.0, 0.0, 0.0)), Vector3d(map.linear.col(0)));
  AffineTransform3 singular;
  singular.linear.setZero();
  EXPECT_THROW(inverse(singular), std::invalid_argument);
}

TEST(KittiTracking, MercatorPoseByHand) {
  // On the equator the scale is 1, one degree of longitude is er·π/180 = 111319.49 m, and
  // ln tan(π/4) = 0.
  KittiOxts oxts;
  oxts.latitude_deg = 0.0;
  oxts.longitude_deg = 1.0;
  oxts.altitude_m = 5.0;
  oxts.yaw_rad = portable::kPi / 2.0;
  const AffineTransform3 pose = kitti_mercator_pose(oxts, kitti_mercator_scale(0.0));
  EXPECT_NEAR(pose.translation.x(), 111319.49079327357, 1e-6);
  EXPECT_NEAR(pose.translation.y(), 0.0, 1e-6);
  EXPECT_DOUBLE_EQ(pose.translation.z(), 5.0);
  // Yaw π/2 turns the IMU's forward axis to +y.
  EXPECT_LT((pose.linear.col(0) - Vector3d(0.0, 1.0, 0.0)).norm(), 1e-12);
  EXPECT_NEAR(kitti_mercator_scale(60.0), 0.5, 1e-12);
  // 1° north of the equator: er·ln tan(45.5°) = 111325.14 m (the Mercator stretch).
  oxts.latitude_deg = 1.0;
  EXPECT_NEAR(kitti_mercator_pose(oxts, 1.0).translation.y(),
              6378137.0 * std::log(std::tan((90.0 + 1.0) * portable::kPi / 360.0)), 1e-6);
  // Roll, pitch, yaw compose as Rz(yaw) Ry(pitch) Rx(roll): pitch alone tips the x axis down.
  KittiOxts pitched;
  pitched.pitch_rad = 0.1;
  EXPECT_LT(
      (kitti_mercator_pose(pitched, 1.0).linear.col(0) - Vector3d(std::cos(0.1), 0.0, -std::sin(0.1))).norm(),
      1e-12);
}

// ── Readers on hand-written files ──

TEST(KittiTracking, LabelReaderKeepsBoxesAndCountsDontCare) {
  const ScratchDirectory scratch;
  const std::string path = scratch.write(
      "label.txt", kGoodLabel + "0 -1 DontCare -1 -1 -10 1 2 3 4 -1 -1 -1 -1000 -1000 -1000 -10\n\n" +
                       "1 7 Pedestrian 1 2 0.5 10 20 30 40 1.8 0.6 0.9 3.0 1.6 12.5 0.25\r\n");
  const KittiLabelFile file = read_kitti_labels(path);
  ASSERT_EQ(file.labels.size(), 2u);
  EXPECT_EQ(file.dont_care_rows, 1);
  const KittiLabel& car = file.labels[0];
  EXPECT_EQ(car.line, 1);
  EXPECT_EQ(car.frame, 0);
  EXPECT_EQ(car.track_id, 3);
  EXPECT_EQ(car.type, "Car");
  EXPECT_EQ(car.occluded, 1);
  EXPECT_DOUBLE_EQ(car.image_box[2], 200.0);
  EXPECT_DOUBLE_EQ(car.length_m, 4.0);
  EXPECT_EQ(car.camera_position, Vector3d(-2.0, 1.7, 20.0));
  EXPECT_DOUBLE_EQ(car.rotation_y, -1.57);
  const KittiLabel& walker = file.labels[1];
  EXPECT_EQ(walker.line, 4);  // after the DontCare row and a blank line; CRLF accepted
  EXPECT_EQ(walker.type, "Pedestrian");
  EXPECT_DOUBLE_EQ(walker.rotation_y, 0.25);
}

TEST(KittiTracking, MalformedLabelLinesNameFileAndLine) {
  const ScratchDirectory scratch;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0 4 Car 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 20.0\n", "expected 17 values"},
      {"x 4 Car 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n", "frame 'x' is not an integer"},
      {"0 4 Car 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 nan -1.57\n", "not a finite number"},
      {"0 4 Bus 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n", "unknown type 'Bus'"},
      {"0 3 Van 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n",
       "a second box for track 3 in frame 0"},
      {"0 4 Car 0 0 -1.5 100 150 200 250 1.5 0 4.0 -2.0 1.7 20.0 -1.57\n", "must be positive"},
      {"0 -2 Car 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n", "track_id -2 is negative"},
      {"0 4 DontCare -1 -1 -10 1 2 3 4 -1 -1 -1 -1000 -1000 -1000\n", "expected 17 values"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string path = scratch.write("label" + std::to_string(k) + ".txt", kGoodLabel + cases[k].first);
    const std::string message = expect_input_error([&] { read_kitti_labels(path); }, path, 2);
    EXPECT_NE(message.find(cases[k].second), std::string::npos) << message;
  }
  expect_input_error([&] { read_kitti_labels(scratch / "absent.txt"); }, scratch / "absent.txt", 0);
}

TEST(KittiTracking, MalformedOxtsLinesNameFileAndLine) {
  const ScratchDirectory scratch;
  const std::string good = scratch.write("good.txt", kGoodOxts + kGoodOxts);
  const std::vector<KittiOxts> rows = read_kitti_oxts(good);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_DOUBLE_EQ(rows[1].latitude_deg, 49.0);
  EXPECT_DOUBLE_EQ(rows[1].yaw_rad, 1.5);
  EXPECT_DOUBLE_EQ(rows[1].values[29], 0.0);
  EXPECT_EQ(rows[1].line, 2);

  const std::vector<std::pair<std::string, std::string>> cases = {
      {"49.0 8.4 115.0 0.01 0.02 1.5 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 4 8 4\n",
       "expected 30 values"},
      {"49.0 8.4 high 0.01 0.02 1.5 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 4 8 4 4 0\n",
       "value 3 'high'"},
      {"95.0 8.4 115.0 0.01 0.02 1.5 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 4 8 4 4 0\n",
       "latitude 95"},
      {"49.0 8.4 115.0 0.01 0.02 inf 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 4 8 4 4 0\n",
       "value 6 'inf'"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string path = scratch.write("oxts" + std::to_string(k) + ".txt", kGoodOxts + cases[k].first);
    const std::string message = expect_input_error([&] { read_kitti_oxts(path); }, path, 2);
    EXPECT_NE(message.find(cases[k].second), std::string::npos) << message;
  }
  const std::string empty = scratch.write("empty.txt", "\n");
  expect_input_error([&] { read_kitti_oxts(empty); }, empty, 0);
}

TEST(KittiTracking, CalibrationKeysWithAndWithoutColons) {
  const ScratchDirectory scratch;
  const KittiCalibration with = read_kitti_calibration(scratch.write("with.txt", good_calibration(true)));
  const KittiCalibration without =
      read_kitti_calibration(scratch.write("without.txt", good_calibration(false)));
  // The object-detection spellings, an extra key and a blank line.
  std::string other = good_calibration(true);
  other.replace(other.find("R_rect:"), 7, "R0_rect:");
  other.replace(other.find("Tr_velo_cam:"), 12, "Tr_velo_to_cam:");
  other.replace(other.find("Tr_imu_velo:"), 12, "Tr_imu_to_velo:");
  const KittiCalibration detection =
      read_kitti_calibration(scratch.write("detection.txt", other + "\nTr_cam_to_road: 1 2 3\n"));
  for (const KittiCalibration* calibration : {&without, &detection}) {
    EXPECT_EQ(calibration->rectification, with.rectification);
    EXPECT_EQ(calibration->velodyne_to_camera.linear, with.velodyne_to_camera.linear);
    EXPECT_EQ(calibration->imu_to_velodyne.translation, with.imu_to_velodyne.translation);
    EXPECT_EQ(calibration->projection[2], with.projection[2]);
  }
  EXPECT_DOUBLE_EQ(with.projection[0](1, 2), 170.0);
  EXPECT_DOUBLE_EQ(with.velodyne_to_camera.translation.y(), -0.0763);
  EXPECT_DOUBLE_EQ(with.imu_to_velodyne.linear(1, 2), -0.0148);
  // camera_to_imu undoes R_rect, Tr_velo_cam and Tr_imu_velo in turn.
  const Vector3d in_imu(3.0, -1.0, 0.5);
  AffineTransform3 rectify;
  rectify.linear = with.rectification;
  const Vector3d in_camera = rectify.apply(with.velodyne_to_camera.apply(with.imu_to_velodyne.apply(in_imu)));
  EXPECT_LT((with.camera_to_imu().apply(in_camera) - in_imu).norm(), 1e-12);
}

TEST(KittiTracking, MalformedCalibrationNamesFileAndLine) {
  const ScratchDirectory scratch;
  const std::string good = good_calibration(true);
  std::string short_row = good;
  short_row.replace(short_row.find(" 0.9999 0.0098"), 7, "");  // R_rect (line 5) loses a value
  std::string word = good;
  word.replace(word.find("-0.8087"), 7, "minus");  // Tr_imu_velo, line 7
  std::string missing = good.substr(0, good.find("Tr_imu_velo"));
  const std::vector<std::tuple<std::string, int, std::string>> cases = {
      {short_row, 5, "R_rect needs 9 values, found 8"},
      {word, 7, "'minus' is not a finite number"},
      {good + "P2: 1 2 3 4 5 6 7 8 9 10 11 12\n", 8, "P2 given a second time"},
      {missing, 0, "missing Tr_imu_velo"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& [text, line, reason] = cases[k];
    const std::string path = scratch.write("calib" + std::to_string(k) + ".txt", text);
    const std::string message = expect_input_error([&] { read_kitti_calibration(path); }, path, line);
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

TEST(KittiTracking, SequenceFromHandWrittenFiles) {
  const ScratchDirectory scratch;
  scratch.write("calib/0001.txt", good_calibration());
  scratch.write("oxts/0001.txt", kGoodOxts + kGoodOxts);
  const std::string label_path = scratch.write(
      "label/0001.txt",
      kGoodLabel + "1 3 Car 0 1 -1.5 100.0 150.0 200.0 250.0 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n");
  const KittiSequence sequence = load_kitti_sequence(scratch.path(), "0001");
  ASSERT_EQ(sequence.frames.size(), 2u);
  EXPECT_EQ(sequence.labelled_boxes, 2);
  // Two identical oxts rows: the IMU stands still at the origin of the world frame.
  for (const KittiFrame& frame : sequence.frames) {
    EXPECT_LT(frame.ego_position.norm(), 1e-9);
    EXPECT_LT((frame.imu_pose.linear - Matrix3d::Identity()).norm(), 1e-12);
    ASSERT_EQ(frame.objects.size(), 1u);
    const KittiObject& car = frame.objects[0];
    EXPECT_LT((car.world_position - sequence.camera_to_imu.apply(Vector3d(-2.0, 1.7, 20.0))).norm(), 1e-12);
    // rotation_y = −π/2 faces the camera's z axis (forward), i.e. about the IMU's x axis.
    EXPECT_GT(car.world_heading.x(), 0.99);
    EXPECT_NEAR(car.world_heading.norm(), 1.0, 1e-12);
  }
  // A box in a frame without an oxts row.
  scratch.write("label/0001.txt",
                kGoodLabel + "2 3 Car 0 0 -1.5 100 150 200 250 1.5 1.6 4.0 -2.0 1.7 20.0 -1.57\n");
  const std::string message =
      expect_input_error([&] { load_kitti_sequence(scratch.path(), "0001"); }, label_path, 2);
  EXPECT_NE(message.find("frame 2 has no oxts row"), std::string::npos) << message;
}

// ── The real sequences ──

TEST(KittiTracking, WorldPositionsMatchTheDerivedFiles) {
  SKIP_WITHOUT_KITTI();
  if (!fs::is_directory(kDerivedDirectory)) GTEST_SKIP() << "no derived files at " << kDerivedDirectory;
  for (const std::string& name : kSequences) {
    SCOPED_TRACE(name);
    const KittiSequence sequence = load_kitti_sequence(kKittiDirectory, name);
    std::map<std::pair<int, int>, const KittiObject*> boxes;
    for (const KittiFrame& frame : sequence.frames) {
      for (const KittiObject& object : frame.objects) boxes[{frame.frame, object.track_id}] = &object;
    }

    // frame,track_id,type,truncated,occluded,x_m,y_m,z_m
    std::ifstream objects(kDerivedDirectory + "/" + name + "_objects_world.csv");
    ASSERT_TRUE(objects) << name;
    std::string line;
    std::getline(objects, line);
    ASSERT_EQ(line, "frame,track_id,type,truncated,occluded,x_m,y_m,z_m");
    std::size_t rows = 0;
    double worst = 0.0;
    while (std::getline(objects, line)) {
      const std::vector<std::string> field = csv_fields(line);
      ASSERT_EQ(field.size(), 8u) << line;
      const auto it = boxes.find({std::stoi(field[0]), std::stoi(field[1])});
      ASSERT_NE(it, boxes.end()) << line;
      EXPECT_EQ(it->second->type, field[2]);
      const Vector3d expected(std::stod(field[5]), std::stod(field[6]), std::stod(field[7]));
      worst = std::max(worst, (it->second->world_position - expected).cwiseAbs().maxCoeff());
      ++rows;
    }
    EXPECT_EQ(rows, boxes.size());
    EXPECT_EQ(static_cast<int>(rows), sequence.labelled_boxes);
    EXPECT_LT(worst, 1e-3);  // the files have 3 decimals: 0.5 mm of rounding

    // frame,x_m,y_m,z_m,yaw_rad
    std::ifstream ego(kDerivedDirectory + "/" + name + "_ego_world.csv");
    ASSERT_TRUE(ego) << name;
    std::getline(ego, line);
    ASSERT_EQ(line, "frame,x_m,y_m,z_m,yaw_rad");
    std::size_t frames = 0;
    double worst_position = 0.0;
    double worst_yaw = 0.0;
    while (std::getline(ego, line)) {
      const std::vector<std::string> field = csv_fields(line);
      ASSERT_EQ(field.size(), 5u) << line;
      const auto frame = static_cast<std::size_t>(std::stoi(field[0]));
      ASSERT_LT(frame, sequence.frames.size());
      const Vector3d expected(std::stod(field[1]), std::stod(field[2]), std::stod(field[3]));
      worst_position =
          std::max(worst_position, (sequence.frames[frame].ego_position - expected).cwiseAbs().maxCoeff());
      worst_yaw = std::max(worst_yaw, std::abs(sequence.frames[frame].ego_yaw - std::stod(field[4])));
      ++frames;
    }
    EXPECT_EQ(frames, sequence.frames.size());
    EXPECT_LT(worst_position, 1e-3);
    EXPECT_LT(worst_yaw, 1e-4);  // 5 decimals in the file
  }
}

// Parked cars the ego drives past: in the camera frame each sweeps tens of metres (from far ahead
// to beside the ego), in the world frame it must stay put. Found by inspection of all ten sequences
// (tracks of ≥ 20 frames whose camera-frame position moves > 10 m while the world position does
// not), choosing long ones with the largest sweeps:
//   0004-20 Car, 46 frames, camera z 64.7 → 2.6 m
//   0005-7  Car, 54 frames, camera z 77.0 → 23.9 m
//   0010-7  Car, 50 frames, camera z 73.6 → 2.2 m
//   0011-44 Car, 181 frames, camera z 76.9 → 4.5 m
//   0020-25 Van, 95 frames, camera z 74.6 → 5.5 m
// Their world RMS spread is 0.11–0.26 m (label jitter and GPS/IMU drift), camera-frame sweep 53–72 m.
TEST(KittiTracking, ParkedCarsStayPutInTheWorldFrame) {
  SKIP_WITHOUT_KITTI();
  const std::vector<std::pair<std::string, int>> parked = {
      {"0004", 20}, {"0005", 7}, {"0010", 7}, {"0011", 44}, {"0020", 25}};
  for (const auto& [name, track] : parked) {
    SCOPED_TRACE(name + "-" + std::to_string(track));
    const KittiSequence sequence = load_kitti_sequence(kKittiDirectory, name);
    std::vector<Vector3d> world;
    std::vector<Vector3d> camera;
    for (const KittiFrame& frame : sequence.frames) {
      for (const KittiObject& object : frame.objects) {
        if (object.track_id != track) continue;
        world.push_back(object.world_position);
        camera.push_back(object.camera_position);
      }
    }
    ASSERT_GE(world.size(), 40u);
    Vector3d mean = Vector3d::Zero();
    for (const Vector3d& position : world) mean += position;
    mean /= static_cast<double>(world.size());
    double squared = 0.0;
    for (const Vector3d& position : world) squared += (position - mean).squaredNorm();
    const double world_spread = std::sqrt(squared / static_cast<double>(world.size()));
    double camera_sweep = 0.0;
    for (const Vector3d& position : camera)
      camera_sweep = std::max(camera_sweep, (position - camera.front()).norm());
    EXPECT_GT(camera_sweep, 40.0);  // the ego really drives past it
    EXPECT_LT(world_spread, 0.3);   // and it stays put in the world frame
  }
}

// The world heading from rotation_y (d_cam = (cos ry, 0, −sin ry)) must point where moving cars go:
// compared with their displacement over 1 s when that is over 5 m (> 18 km/h).
TEST(KittiTracking, LabelHeadingPointsWhereCarsDrive) {
  SKIP_WITHOUT_KITTI();
  int compared = 0;
  int agreeing = 0;
  int reversed = 0;
  for (const std::string& name : kSequences) {
    const KittiSequence sequence = load_kitti_sequence(kKittiDirectory, name);
    std::map<std::pair<int, int>, const KittiObject*> boxes;
    for (const KittiFrame& frame : sequence.frames) {
      for (const KittiObject& object : frame.objects) boxes[{frame.frame, object.track_id}] = &object;
    }
    for (const auto& [key, object] : boxes) {
      if (object->type != "Car" && object->type != "Van" && object->type != "Truck") continue;
      const auto later = boxes.find({key.first + 10, key.second});
      if (later == boxes.end()) continue;
      Vector3d motion = later->second->world_position - object->world_position;
      motion.z() = 0.0;
      if (motion.norm() < 5.0) continue;
      Vector3d heading = object->world_heading;
      heading.z() = 0.0;
      const double cosine = motion.normalized().dot(heading.normalized());
      ++compared;
      if (cosine > std::cos(15.0 * portable::kPi / 180.0)) ++agreeing;
      if (cosine < 0.0) ++reversed;
    }
  }
  ASSERT_GT(compared, 1000);
  EXPECT_GT(agreeing, 0.95 * compared);  // measured: 98%
  EXPECT_EQ(reversed, 0);
}

TEST(KittiTracking, RecordingHasEveryFrameAndSequenceTrackIds) {
  SKIP_WITHOUT_KITTI();
  const KittiSequence sequence = load_kitti_sequence(kKittiDirectory, "0004");
  EXPECT_EQ(sequence.frames.size(), 314u);
  EXPECT_EQ(sequence.dont_care_rows, 899);  // rows of type DontCare in label/0004.txt
  EXPECT_EQ(sequence.labelled_boxes, 1113);
  // Frame 0 defines the world: the IMU is at the origin with no rotation.
  EXPECT_LT(sequence.frames[0].ego_position.norm(), 1e-9);
  EXPECT_LT((sequence.frames[0].imu_pose.linear - Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT((sequence.frames[0].camera_position - sequence.camera_to_imu.translation).norm(), 1e-12);

  const Recording recording = kitti_recording(sequence);
  EXPECT_EQ(recording.name, "kitti-0004");
  EXPECT_DOUBLE_EQ(recording.rate_hz, 10.0);
  ASSERT_EQ(recording.frames.size(), sequence.frames.size());
  std::size_t positions = 0;
  for (const KittiFrame& frame : sequence.frames) {
    const auto& objects = recording.frames.at(frame.frame);
    EXPECT_EQ(objects.size(), frame.objects.size());
    for (const KittiObject& object : frame.objects) {
      EXPECT_EQ(objects.at("0004-" + std::to_string(object.track_id)), object.world_position);
      ++positions;
    }
  }
  EXPECT_EQ(static_cast<int>(positions), sequence.labelled_boxes);
  EXPECT_EQ(kitti_object_id("0004", 12), "0004-12");
}

}  // namespace
}  // namespace stgf
