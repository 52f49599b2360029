// SPDX-License-Identifier: Apache-2.0
#pragma once
// KITTI tracking (Geiger, Lenz, Urtasun, CVPR 2012): readers for the label, oxts and calib files
// of one training sequence, and the conversion of its labelled 3D boxes and its GPS/IMU poses into
// one world frame (DESIGN §5; the files and their terms: data/README.md). The files are read with this code
// only; the `derived/` CSVs beside them serve to check it (tests/datasets/test_kitti_tracking.cpp).
//
// ── Files ────────────────────────────────────────────────────────────────────────────────────────
// DIR/label/NNNN.txt   one box per line, 17 space-separated values:
//                        frame track_id type truncated occluded alpha
//                        bbox_left bbox_top bbox_right bbox_bottom  h w l  x y z  rotation_y
//                      (x, y, z) is the bottom centre of the box in the rectified reference camera
//                      frame (x right, y down, z forward; m), h w l its size (m), rotation_y its yaw
//                      about the camera's y axis (rad). Type DontCare (track_id −1) marks image
//                      regions without a box: those rows are checked for 17 values, skipped and
//                      counted. Other types: Car Van Truck Pedestrian Person_sitting Cyclist Tram Misc.
// DIR/oxts/NNNN.txt    one row per frame (row f is frame f), 30 values; the first six are
//                        lat lon alt roll pitch yaw   (deg, deg, m, rad, rad, rad)
// DIR/calib/NNNN.txt   "KEY v1 v2 ..." per line, the key with or without a trailing colon:
//                        P0 P1 P2 P3                3×4 projection matrices, row-major
//                        R_rect (or R0_rect)        3×3 rectifying rotation of the reference camera
//                        Tr_velo_cam (Tr_velo_to_cam)  3×4 [R t]: Velodyne → unrectified camera 0
//                        Tr_imu_velo (Tr_imu_to_velo)  3×4 [R t]: IMU → Velodyne
//                      Other keys are ignored; blank lines are skipped.
// Any malformed line (wrong number of values, a value that is not a finite number or integer, an
// unknown type, a duplicate (frame, track_id), a frame without its oxts row, a missing or repeated
// calib key) throws InputError "FILE:LINE: what is wrong" (line 0: the file as a whole).
//
// ── World frame (the KITTI devkit's convertOxtsToPose) ─────────────────────────────────────────────
// With er = 6378137 m and the Mercator scale s = cos(lat₀) of frame 0's latitude, frame f's IMU pose
// in Mercator coordinates is
//   t_f = ( s·lon·π·er/180,  s·er·ln tan((90 + lat)·π/360),  alt )
//   R_f = Rz(yaw) Ry(pitch) Rx(roll)
//   T_f = [R_f t_f]                      (IMU frame → Mercator frame)
// and the world frame is the IMU frame at frame 0 (x forward, y left, z up; m):
//   pose_f = T₀⁻¹ · T_f                  (IMU frame at f → world)
// A point in the rectified reference camera frame maps to the IMU frame and to the world by
//   camera_to_imu = Tr_imu_velo⁻¹ · Tr_velo_cam⁻¹ · R_rect⁻¹
//   p_world = pose_f · camera_to_imu · p_cam
// (4×4 homogeneous products; R_rect is padded to [R_rect 0; 0 1]). The inverses are general affine
// inverses, A⁻¹ = [M⁻¹ −M⁻¹t], M⁻¹ from the adjugate, since the calibration matrices are only
// nearly orthonormal.
//   ego position   the translation of pose_f (the IMU in the world)
//   ego yaw        atan2(pose_f(1,0), pose_f(0,0))
//   camera         pose_f · camera_to_imu · 0, the reference camera's centre
//   object heading the box's forward axis d_cam = (cos ry, 0, −sin ry) in the camera frame (the
//                  devkit's box corners use x_obj → (cos ry, 0, −sin ry)), mapped as a direction:
//                  d_world = linear(pose_f · camera_to_imu) · d_cam; world yaw = atan2(d_y, d_x).
//
// All arithmetic that feeds the world positions is spelled out in a fixed order and uses
// stgf::portable for ln, sin and cos (datasets/random.hpp), so the positions — and every benchmark
// built on them — are the same bits on every IEEE 754 platform. The yaw angles use std::atan2 and are
// for reporting only; builders use the heading vectors.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/datasets/recording.hpp"

namespace stgf {

// y = linear · x + translation (a 3×4 matrix [linear translation]).
struct AffineTransform3 {
  Matrix3d linear = Matrix3d::Identity();
  Vector3d translation = Vector3d::Zero();

  Vector3d apply(const Vector3d& point) const;             // linear · point + translation
  Vector3d apply_linear(const Vector3d& direction) const;  // linear · direction
};
// outer ∘ inner: x ↦ outer(inner(x)).
AffineTransform3 compose(const AffineTransform3& outer, const AffineTransform3& inner);
// The inverse map; std::invalid_argument when the linear part is singular (|det| < 1e-12).
AffineTransform3 inverse(const AffineTransform3& transform);

// ── Label files ──

struct KittiLabel {
  int line = 0;  // 1-based line in the label file
  int frame = 0;
  int track_id = 0;
  std::string type;  // never "DontCare"
  int truncated = 0;
  int occluded = 0;
  double alpha = 0.0;
  std::array<double, 4> image_box{};  // left, top, right, bottom (px)
  double height_m = 0.0;
  double width_m = 0.0;
  double length_m = 0.0;
  Vector3d camera_position = Vector3d::Zero();  // bottom centre, rectified reference camera frame (m)
  double rotation_y = 0.0;                      // rad
};

struct KittiLabelFile {
  std::vector<KittiLabel> labels;  // in file order, DontCare rows left out
  int dont_care_rows = 0;          // DontCare rows skipped
};

// Reads label/NNNN.txt (see the header comment). Throws InputError.
KittiLabelFile read_kitti_labels(const std::string& path);

// ── Oxts files ──

struct KittiOxts {
  int line = 0;
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;
  std::array<double, 30> values{};  // the whole row, including the six above
};

// Reads oxts/NNNN.txt: one row per frame. Throws InputError (also for an empty file and for a
// latitude outside (−90, 90) or a longitude outside [−180, 180]).
std::vector<KittiOxts> read_kitti_oxts(const std::string& path);

// T_f = [Rz(yaw) Ry(pitch) Rx(roll) | t_f] in Mercator coordinates with scale s = cos(lat₀)
// (see the header comment).
AffineTransform3 kitti_mercator_pose(const KittiOxts& oxts, double mercator_scale);
// s = cos(latitude · π/180).
double kitti_mercator_scale(double latitude_deg);

// ── Calibration files ──

struct KittiCalibration {
  std::array<Eigen::Matrix<double, 3, 4>, 4> projection{};  // P0..P3
  Matrix3d rectification = Matrix3d::Identity();            // R_rect
  AffineTransform3 velodyne_to_camera;                      // Tr_velo_cam
  AffineTransform3 imu_to_velodyne;                         // Tr_imu_velo

  // Tr_imu_velo⁻¹ · Tr_velo_cam⁻¹ · R_rect⁻¹: rectified reference camera frame → IMU frame.
  AffineTransform3 camera_to_imu() const;
};

// Reads calib/NNNN.txt (see the header comment). Throws InputError.
KittiCalibration read_kitti_calibration(const std::string& path);

// ── A whole sequence in the world frame ──

struct KittiObject {
  int track_id = 0;
  std::string type;
  int truncated = 0;
  int occluded = 0;
  double height_m = 0.0;
  double width_m = 0.0;
  double length_m = 0.0;
  Vector3d camera_position = Vector3d::Zero();  // as labelled (rectified reference camera frame)
  double rotation_y = 0.0;                      // as labelled
  Vector3d world_position = Vector3d::Zero();   // bottom centre in the world frame (m)
  Vector3d world_heading = Vector3d::Zero();    // unit forward axis of the box in the world frame
  double world_yaw = 0.0;                       // atan2 of world_heading's y and x (rad)
  int label_line = 0;                           // where it came from
};

struct KittiFrame {
  int frame = 0;
  AffineTransform3 imu_pose;                    // pose_f: IMU frame → world
  Vector3d ego_position = Vector3d::Zero();     // the IMU in the world (m)
  double ego_yaw = 0.0;                         // atan2(pose_f(1,0), pose_f(0,0)) (rad)
  Vector3d ego_heading = Vector3d::Zero();      // pose_f's x axis (IMU forward) in the world, unit
  Vector3d camera_position = Vector3d::Zero();  // the reference camera's centre in the world (m)
  std::vector<KittiObject> objects;             // labelled boxes of this frame, by track id
};

struct KittiSequence {
  std::string name;  // "0004"
  double rate_hz = 10.0;
  std::string label_path;
  std::string oxts_path;
  std::string calibration_path;
  KittiCalibration calibration;
  AffineTransform3 camera_to_imu;
  std::vector<KittiFrame> frames;  // frames[f].frame == f, one per oxts row
  int dont_care_rows = 0;          // DontCare label rows skipped
  int labelled_boxes = 0;          // label rows kept
};

// Loads DIR/label/NAME.txt, DIR/oxts/NAME.txt and DIR/calib/NAME.txt and converts every box to the
// world frame. Throws InputError for bad or missing files.
KittiSequence load_kitti_sequence(const std::string& directory, const std::string& name);

// The id of a track in stgf files: "<sequence>-<track_id>", e.g. "0004-12".
std::string kitti_object_id(const std::string& sequence, int track_id);

// The world-frame bottom centres of every labelled box as a Recording named "kitti-<name>" at the
// sequence's rate, with ids from kitti_object_id. Every frame of the sequence is present (possibly
// with no objects), so windows never stop at a frame without boxes.
Recording kitti_recording(const KittiSequence& sequence);

}  // namespace stgf
