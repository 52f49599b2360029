// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/kitti_tracking.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "stgf/datasets/random.hpp"
#include "stgf/datasets/text_input.hpp"
#include "stgf/io/input_error.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

constexpr double kEarthRadiusM = 6378137.0;  // er of the devkit's Mercator projection
constexpr double kPi = portable::kPi;

// ── Reading lines and fields ──

// Parses one field of `path`:`line`; `what` names it in the message.
class FieldParser {
 public:
  FieldParser(const std::string& path, int line) : path_(path), line_(line) {}

  int line() const { return line_; }

  double number(std::string_view field, std::string_view what) const {
    const std::optional<double> value = parse_finite_number(field);
    if (!value) fail(fmt::format("{} '{}' is not a finite number", what, field));
    return *value;
  }

  int integer(std::string_view field, std::string_view what) const {
    const std::optional<int> value = parse_integer(field);
    if (!value) fail(fmt::format("{} '{}' is not an integer", what, field));
    return *value;
  }

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path_, line_, what); }

 private:
  const std::string& path_;
  int line_;
};

// Calls row(fields, parse) for every line of `path` that has fields (separated by spaces and tabs;
// the line end is LF or CRLF), with `parse` located at that line. InputError (line 0) when the file
// cannot be opened.
template <typename Row>
void for_each_row(const std::string& path, Row row) {
  std::ifstream input = open_text_file(path);
  std::string line;
  int line_number = 0;
  while (std::getline(input, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string_view> fields = split_fields(line, " \t");
    if (fields.empty()) continue;
    row(fields, FieldParser(path, line_number));
  }
}

// ── Small matrix arithmetic in a fixed order ──

Matrix3d multiply(const Matrix3d& a, const Matrix3d& b) {
  Matrix3d product;
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      product(row, column) = a(row, 0) * b(0, column) + a(row, 1) * b(1, column) + a(row, 2) * b(2, column);
    }
  }
  return product;
}

Vector3d multiply(const Matrix3d& a, const Vector3d& v) {
  Vector3d product;
  for (int row = 0; row < 3; ++row) product(row) = a(row, 0) * v(0) + a(row, 1) * v(1) + a(row, 2) * v(2);
  return product;
}

// Rz(yaw) Ry(pitch) Rx(roll).
Matrix3d rotation_from_roll_pitch_yaw(double roll, double pitch, double yaw) {
  const portable::SineCosine x = portable::sin_cos(roll);
  const portable::SineCosine y = portable::sin_cos(pitch);
  const portable::SineCosine z = portable::sin_cos(yaw);
  Matrix3d about_x;
  about_x << 1.0, 0.0, 0.0, 0.0, x.cosine, -x.sine, 0.0, x.sine, x.cosine;
  Matrix3d about_y;
  about_y << y.cosine, 0.0, y.sine, 0.0, 1.0, 0.0, -y.sine, 0.0, y.cosine;
  Matrix3d about_z;
  about_z << z.cosine, -z.sine, 0.0, z.sine, z.cosine, 0.0, 0.0, 0.0, 1.0;
  return multiply(about_z, multiply(about_y, about_x));
}

// ── Label types ──

constexpr std::string_view kDontCare = "DontCare";
const std::set<std::string, std::less<>>& known_types() {
  static const std::set<std::string, std::less<>> types = {
      "Car", "Van", "Truck", "Pedestrian", "Person_sitting", "Cyclist", "Tram", "Misc"};
  return types;
}

// ── Calibration keys ──

struct CalibrationKey {
  std::string_view canonical;
  int values;
};

// Canonical key and number of values for a key as spelled in the file (colon already removed), or
// nullptr for keys this reader ignores.
const CalibrationKey* calibration_key(std::string_view key) {
  static const std::map<std::string_view, CalibrationKey, std::less<>> keys = {
      {"P0", {"P0", 12}},
      {"P1", {"P1", 12}},
      {"P2", {"P2", 12}},
      {"P3", {"P3", 12}},
      {"R_rect", {"R_rect", 9}},
      {"R0_rect", {"R_rect", 9}},
      {"Tr_velo_cam", {"Tr_velo_cam", 12}},
      {"Tr_velo_to_cam", {"Tr_velo_cam", 12}},
      {"Tr_imu_velo", {"Tr_imu_velo", 12}},
      {"Tr_imu_to_velo", {"Tr_imu_velo", 12}},
  };
  const auto it = keys.find(key);
  return it == keys.end() ? nullptr : &it->second;
}

AffineTransform3 affine_from_row_major(const std::vector<double>& values) {
  AffineTransform3 transform;
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column)
      transform.linear(row, column) = values[static_cast<std::size_t>(4 * row + column)];
    transform.translation(row) = values[static_cast<std::size_t>(4 * row + 3)];
  }
  return transform;
}

}  // namespace

// ── Affine maps ──

Vector3d AffineTransform3::apply(const Vector3d& point) const {
  Vector3d result;
  for (int row = 0; row < 3; ++row) {
    result(row) = (linear(row, 0) * point(0) + linear(row, 1) * point(1) + linear(row, 2) * point(2)) +
                  translation(row);
  }
  return result;
}

Vector3d AffineTransform3::apply_linear(const Vector3d& direction) const {
  return multiply(linear, direction);
}

AffineTransform3 compose(const AffineTransform3& outer, const AffineTransform3& inner) {
  AffineTransform3 result;
  result.linear = multiply(outer.linear, inner.linear);
  result.translation = outer.apply(inner.translation);
  return result;
}

AffineTransform3 inverse(const AffineTransform3& transform) {
  const Matrix3d& m = transform.linear;
  // Adjugate (transposed cofactors) and determinant by the first row.
  Matrix3d adjugate;
  adjugate(0, 0) = m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1);
  adjugate(0, 1) = m(0, 2) * m(2, 1) - m(0, 1) * m(2, 2);
  adjugate(0, 2) = m(0, 1) * m(1, 2) - m(0, 2) * m(1, 1);
  adjugate(1, 0) = m(1, 2) * m(2, 0) - m(1, 0) * m(2, 2);
  adjugate(1, 1) = m(0, 0) * m(2, 2) - m(0, 2) * m(2, 0);
  adjugate(1, 2) = m(0, 2) * m(1, 0) - m(0, 0) * m(1, 2);
  adjugate(2, 0) = m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0);
  adjugate(2, 1) = m(0, 1) * m(2, 0) - m(0, 0) * m(2, 1);
  adjugate(2, 2) = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  const double determinant = m(0, 0) * adjugate(0, 0) + m(0, 1) * adjugate(1, 0) + m(0, 2) * adjugate(2, 0);
  if (!(std::abs(determinant) >= 1e-12)) {
    throw std::invalid_argument(fmt::format("inverse: singular linear part (determinant {})", determinant));
  }
  AffineTransform3 result;
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column)
      result.linear(row, column) = adjugate(row, column) / determinant;
  }
  const Vector3d moved = multiply(result.linear, transform.translation);
  result.translation = -moved;
  return result;
}

// ── Labels ──

KittiLabelFile read_kitti_labels(const std::string& path) {
  KittiLabelFile file;
  std::set<std::pair<int, int>> seen;  // (frame, track_id)
  for_each_row(path, [&](const std::vector<std::string_view>& fields, const FieldParser& parse) {
    if (fields.size() != 17) {
      parse.fail(
          fmt::format("expected 17 values (frame track_id type truncated occluded alpha bbox×4 h w l x y z "
                      "rotation_y), found {}",
                      fields.size()));
    }
    KittiLabel label;
    label.line = parse.line();
    label.frame = parse.integer(fields[0], "frame");
    if (label.frame < 0) parse.fail(fmt::format("frame {} is negative", label.frame));
    label.track_id = parse.integer(fields[1], "track_id");
    label.type = std::string(fields[2]);
    if (label.type == kDontCare) {
      ++file.dont_care_rows;
      return;
    }
    if (known_types().count(label.type) == 0) {
      parse.fail(
          fmt::format("unknown type '{}' (expected Car, Van, Truck, Pedestrian, Person_sitting, Cyclist, "
                      "Tram, Misc or DontCare)",
                      label.type));
    }
    if (label.track_id < 0) parse.fail(fmt::format("track_id {} is negative", label.track_id));
    label.truncated = parse.integer(fields[3], "truncated");
    label.occluded = parse.integer(fields[4], "occluded");
    label.alpha = parse.number(fields[5], "alpha");
    for (int k = 0; k < 4; ++k) {
      label.image_box[static_cast<std::size_t>(k)] =
          parse.number(fields[static_cast<std::size_t>(6 + k)], "bbox");
    }
    label.height_m = parse.number(fields[10], "h");
    label.width_m = parse.number(fields[11], "w");
    label.length_m = parse.number(fields[12], "l");
    if (!(label.height_m > 0.0 && label.width_m > 0.0 && label.length_m > 0.0)) {
      parse.fail(fmt::format("box size h w l = {} {} {} must be positive", label.height_m, label.width_m,
                             label.length_m));
    }
    for (int axis = 0; axis < 3; ++axis) {
      label.camera_position(axis) = parse.number(fields[static_cast<std::size_t>(13 + axis)], "x y z");
    }
    label.rotation_y = parse.number(fields[16], "rotation_y");
    if (!seen.insert({label.frame, label.track_id}).second) {
      parse.fail(fmt::format("a second box for track {} in frame {}", label.track_id, label.frame));
    }
    file.labels.push_back(std::move(label));
  });
  return file;
}

// ── Oxts ──

std::vector<KittiOxts> read_kitti_oxts(const std::string& path) {
  std::vector<KittiOxts> rows;
  for_each_row(path, [&](const std::vector<std::string_view>& fields, const FieldParser& parse) {
    if (fields.size() != 30) {
      parse.fail(fmt::format("expected 30 values (lat lon alt roll pitch yaw ...), found {}", fields.size()));
    }
    KittiOxts row;
    row.line = parse.line();
    for (std::size_t k = 0; k < 30; ++k)
      row.values[k] = parse.number(fields[k], fmt::format("value {}", k + 1));
    row.latitude_deg = row.values[0];
    row.longitude_deg = row.values[1];
    row.altitude_m = row.values[2];
    row.roll_rad = row.values[3];
    row.pitch_rad = row.values[4];
    row.yaw_rad = row.values[5];
    if (!(std::abs(row.latitude_deg) < 90.0)) {
      parse.fail(fmt::format("latitude {} is outside (-90, 90)", row.latitude_deg));
    }
    if (!(std::abs(row.longitude_deg) <= 180.0)) {
      parse.fail(fmt::format("longitude {} is outside [-180, 180]", row.longitude_deg));
    }
    rows.push_back(row);
  });
  if (rows.empty()) throw InputError(path, 0, "no oxts rows");
  return rows;
}

double kitti_mercator_scale(double latitude_deg) {
  return portable::sin_cos(latitude_deg * kPi / 180.0).cosine;
}

AffineTransform3 kitti_mercator_pose(const KittiOxts& oxts, double mercator_scale) {
  AffineTransform3 pose;
  pose.translation(0) = mercator_scale * oxts.longitude_deg * kPi * kEarthRadiusM / 180.0;
  const portable::SineCosine half = portable::sin_cos((90.0 + oxts.latitude_deg) * kPi / 360.0);
  pose.translation(1) = mercator_scale * kEarthRadiusM * portable::log(half.sine / half.cosine);
  pose.translation(2) = oxts.altitude_m;
  pose.linear = rotation_from_roll_pitch_yaw(oxts.roll_rad, oxts.pitch_rad, oxts.yaw_rad);
  return pose;
}

// ── Calibration ──

AffineTransform3 KittiCalibration::camera_to_imu() const {
  AffineTransform3 rectify;
  rectify.linear = rectification;
  return compose(inverse(imu_to_velodyne), compose(inverse(velodyne_to_camera), inverse(rectify)));
}

KittiCalibration read_kitti_calibration(const std::string& path) {
  std::map<std::string_view, std::vector<double>> found;  // canonical key → values
  for_each_row(path, [&](const std::vector<std::string_view>& fields, const FieldParser& parse) {
    std::string_view key = fields[0];
    if (!key.empty() && key.back() == ':') key.remove_suffix(1);
    const CalibrationKey* known = calibration_key(key);
    if (known == nullptr) return;
    if (static_cast<int>(fields.size()) - 1 != known->values) {
      parse.fail(fmt::format("{} needs {} values, found {}", key, known->values, fields.size() - 1));
    }
    if (found.count(known->canonical) != 0)
      parse.fail(fmt::format("{} given a second time", known->canonical));
    std::vector<double> values;
    for (std::size_t k = 1; k < fields.size(); ++k) {
      values.push_back(parse.number(fields[k], fmt::format("{} value {}", key, k)));
    }
    found.emplace(known->canonical, std::move(values));
  });
  for (const std::string_view key : {"P0", "P1", "P2", "P3", "R_rect", "Tr_velo_cam", "Tr_imu_velo"}) {
    if (found.count(key) == 0) throw InputError(path, 0, fmt::format("missing {}", key));
  }
  KittiCalibration calibration;
  for (int camera = 0; camera < 4; ++camera) {
    const std::vector<double>& values = found.at(fmt::format("P{}", camera));
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 4; ++column) {
        calibration.projection[static_cast<std::size_t>(camera)](row, column) =
            values[static_cast<std::size_t>(4 * row + column)];
      }
    }
  }
  const std::vector<double>& rectification = found.at("R_rect");
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      calibration.rectification(row, column) = rectification[static_cast<std::size_t>(3 * row + column)];
    }
  }
  calibration.velodyne_to_camera = affine_from_row_major(found.at("Tr_velo_cam"));
  calibration.imu_to_velodyne = affine_from_row_major(found.at("Tr_imu_velo"));
  try {
    (void)calibration.camera_to_imu();
  } catch (const std::invalid_argument& singular) {
    throw InputError(
        path, 0, fmt::format("R_rect, Tr_velo_cam or Tr_imu_velo is not invertible ({})", singular.what()));
  }
  return calibration;
}

// ── Sequences ──

KittiSequence load_kitti_sequence(const std::string& directory, const std::string& name) {
  namespace fs = std::filesystem;
  KittiSequence sequence;
  sequence.name = name;
  sequence.label_path = (fs::path(directory) / "label" / (name + ".txt")).string();
  sequence.oxts_path = (fs::path(directory) / "oxts" / (name + ".txt")).string();
  sequence.calibration_path = (fs::path(directory) / "calib" / (name + ".txt")).string();

  sequence.calibration = read_kitti_calibration(sequence.calibration_path);
  sequence.camera_to_imu = sequence.calibration.camera_to_imu();
  const std::vector<KittiOxts> oxts = read_kitti_oxts(sequence.oxts_path);
  KittiLabelFile labels = read_kitti_labels(sequence.label_path);
  sequence.dont_care_rows = labels.dont_care_rows;
  sequence.labelled_boxes = static_cast<int>(labels.labels.size());

  // World poses: pose_f = T₀⁻¹ · T_f.
  const double scale = kitti_mercator_scale(oxts.front().latitude_deg);
  const AffineTransform3 world_from_mercator = inverse(kitti_mercator_pose(oxts.front(), scale));
  sequence.frames.resize(oxts.size());
  for (std::size_t f = 0; f < oxts.size(); ++f) {
    KittiFrame& frame = sequence.frames[f];
    frame.frame = static_cast<int>(f);
    frame.imu_pose = compose(world_from_mercator, kitti_mercator_pose(oxts[f], scale));
    frame.ego_position = frame.imu_pose.translation;
    frame.ego_yaw = std::atan2(frame.imu_pose.linear(1, 0), frame.imu_pose.linear(0, 0));
    frame.ego_heading = frame.imu_pose.linear.col(0);
    frame.camera_position = compose(frame.imu_pose, sequence.camera_to_imu).translation;
  }

  for (KittiLabel& label : labels.labels) {
    if (label.frame >= static_cast<int>(oxts.size())) {
      throw InputError(sequence.label_path, label.line,
                       fmt::format("frame {} has no oxts row ({} has {} rows)", label.frame,
                                   sequence.oxts_path, oxts.size()));
    }
    KittiFrame& frame = sequence.frames[static_cast<std::size_t>(label.frame)];
    const AffineTransform3 camera_to_world = compose(frame.imu_pose, sequence.camera_to_imu);
    KittiObject object;
    object.track_id = label.track_id;
    object.type = std::move(label.type);
    object.truncated = label.truncated;
    object.occluded = label.occluded;
    object.height_m = label.height_m;
    object.width_m = label.width_m;
    object.length_m = label.length_m;
    object.camera_position = label.camera_position;
    object.rotation_y = label.rotation_y;
    object.world_position = camera_to_world.apply(label.camera_position);
    const portable::SineCosine yaw = portable::sin_cos(label.rotation_y);
    const Vector3d forward = camera_to_world.apply_linear(Vector3d(yaw.cosine, 0.0, -yaw.sine));
    object.world_heading =
        forward / std::sqrt(forward(0) * forward(0) + forward(1) * forward(1) + forward(2) * forward(2));
    object.world_yaw = std::atan2(object.world_heading(1), object.world_heading(0));
    object.label_line = label.line;
    frame.objects.push_back(std::move(object));
  }
  for (KittiFrame& frame : sequence.frames) {
    std::sort(frame.objects.begin(), frame.objects.end(),
              [](const KittiObject& a, const KittiObject& b) { return a.track_id < b.track_id; });
  }
  return sequence;
}

std::string kitti_object_id(const std::string& sequence, int track_id) {
  return fmt::format("{}-{}", sequence, track_id);
}

Recording kitti_recording(const KittiSequence& sequence) {
  Recording recording;
  recording.name = "kitti-" + sequence.name;
  recording.rate_hz = sequence.rate_hz;
  for (const KittiFrame& frame : sequence.frames) {
    std::map<std::string, Vector3d>& objects = recording.frames[frame.frame];
    for (const KittiObject& object : frame.objects) {
      objects.emplace(kitti_object_id(sequence.name, object.track_id), object.world_position);
    }
  }
  return recording;
}

}  // namespace stgf
