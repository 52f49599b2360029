// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/tsai_camera.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "stgf/datasets/random.hpp"
#include "stgf/datasets/xml_file.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

constexpr int kMaxDistortionIterations = 100;
constexpr double kDistortionTolerance = 1e-15;  // relative Newton step at which the solve stops

// M v, summed left to right.
Vector3d multiply(const Matrix3d& matrix, const Vector3d& vector) {
  Vector3d result;
  for (int row = 0; row < 3; ++row) {
    result(row) = matrix(row, 0) * vector(0) + matrix(row, 1) * vector(1) + matrix(row, 2) * vector(2);
  }
  return result;
}

// Mᵀ v, summed left to right.
Vector3d multiply_transposed(const Matrix3d& matrix, const Vector3d& vector) {
  Vector3d result;
  for (int column = 0; column < 3; ++column) {
    result(column) =
        matrix(0, column) * vector(0) + matrix(1, column) * vector(1) + matrix(2, column) * vector(2);
  }
  return result;
}

// A B, each entry summed left to right.
Matrix3d multiply(const Matrix3d& left, const Matrix3d& right) {
  Matrix3d result;
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      result(row, column) =
          left(row, 0) * right(0, column) + left(row, 1) * right(1, column) + left(row, 2) * right(2, column);
    }
  }
  return result;
}

Matrix2d multiply(const Matrix2d& left, const Matrix2d& right) {
  Matrix2d result;
  for (int row = 0; row < 2; ++row) {
    for (int column = 0; column < 2; ++column) {
      result(row, column) = left(row, 0) * right(0, column) + left(row, 1) * right(1, column);
    }
  }
  return result;
}

void require(bool holds, std::string_view camera, std::string_view what) {
  if (!holds) throw std::invalid_argument(fmt::format("Tsai camera {}: {}", camera, what));
}

}  // namespace

Matrix3d tsai_rotation(double rx_rad, double ry_rad, double rz_rad) {
  const portable::SineCosine a = portable::sin_cos(rx_rad);
  const portable::SineCosine b = portable::sin_cos(ry_rad);
  const portable::SineCosine g = portable::sin_cos(rz_rad);
  const double sa = a.sine, ca = a.cosine, sb = b.sine, cb = b.cosine, sg = g.sine, cg = g.cosine;
  Matrix3d rotation;
  rotation << cb * cg, cg * sa * sb - ca * sg, sa * sg + ca * cg * sb,  //
      cb * sg, sa * sb * sg + ca * cg, ca * sb * sg - cg * sa,          //
      -sb, cb * sa, ca * cb;
  return rotation;
}

// ── TsaiCamera ──

TsaiCamera::TsaiCamera(std::string name, const TsaiGeometry& geometry, const TsaiIntrinsic& intrinsic,
                       const TsaiExtrinsic& extrinsic)
    : name_(std::move(name)),
      geometry_(geometry),
      intrinsic_(intrinsic),
      extrinsic_(extrinsic),
      rotation_(tsai_rotation(extrinsic.rx_rad, extrinsic.ry_rad, extrinsic.rz_rad)),
      translation_(extrinsic.tx_m, extrinsic.ty_m, extrinsic.tz_m) {
  centre_ = -multiply_transposed(rotation_, translation_);
  validate();
}

TsaiCamera::TsaiCamera(std::string name, const TsaiGeometry& geometry, const TsaiIntrinsic& intrinsic,
                       const Matrix3d& rotation, const Vector3d& translation)
    : name_(std::move(name)),
      geometry_(geometry),
      intrinsic_(intrinsic),
      rotation_(rotation),
      translation_(translation) {
  centre_ = -multiply_transposed(rotation_, translation_);
  // The angles of R (see the header comment); informational only.
  extrinsic_.tx_m = translation.x();
  extrinsic_.ty_m = translation.y();
  extrinsic_.tz_m = translation.z();
  extrinsic_.ry_rad = std::asin(std::clamp(-rotation(2, 0), -1.0, 1.0));
  extrinsic_.rx_rad = std::atan2(rotation(2, 1), rotation(2, 2));
  extrinsic_.rz_rad = std::atan2(rotation(1, 0), rotation(0, 0));
  validate();
}

void TsaiCamera::validate() const {
  require(
      geometry_.width_px > 0 && geometry_.height_px > 0, name_,
      fmt::format("the image size must be positive (got {}×{})", geometry_.width_px, geometry_.height_px));
  const auto positive = [&](double value, std::string_view what) {
    require(std::isfinite(value) && value > 0.0, name_,
            fmt::format("{} must be positive (got {})", what, value));
  };
  const auto finite = [&](double value, std::string_view what) {
    require(std::isfinite(value), name_, fmt::format("{} must be finite (got {})", what, value));
  };
  positive(geometry_.dpx_mm, "dpx");
  positive(geometry_.dpy_mm, "dpy");
  finite(geometry_.ncx, "ncx");
  finite(geometry_.nfx, "nfx");
  finite(geometry_.dx_mm, "dx");
  finite(geometry_.dy_mm, "dy");
  positive(intrinsic_.focal_mm, "focal");
  positive(intrinsic_.sx, "sx");
  finite(intrinsic_.kappa1_per_mm2, "kappa1");
  finite(intrinsic_.cx_px, "cx");
  finite(intrinsic_.cy_px, "cy");
  require(rotation_.allFinite() && translation_.allFinite(), name_,
          "the rotation and translation must be finite");
}

Vector3d TsaiCamera::camera_coordinates(const Vector3d& world_point) const {
  return multiply(rotation_, world_point) + translation_;
}

Vector2d TsaiCamera::distorted_sensor_point(const Vector2d& pixel) const {
  return Vector2d(geometry_.dpx_mm * (pixel.x() - intrinsic_.cx_px) / intrinsic_.sx,
                  geometry_.dpy_mm * (pixel.y() - intrinsic_.cy_px));
}

Vector2d TsaiCamera::undistorted_sensor_point(const Vector2d& distorted) const {
  const double radius_squared = distorted.x() * distorted.x() + distorted.y() * distorted.y();
  const double factor = 1.0 + intrinsic_.kappa1_per_mm2 * radius_squared;
  return Vector2d(factor * distorted.x(), factor * distorted.y());
}

std::optional<Vector2d> TsaiCamera::distorted_from_undistorted(const Vector2d& undistorted) const {
  const double kappa = intrinsic_.kappa1_per_mm2;
  const double undistorted_radius =
      std::sqrt(undistorted.x() * undistorted.x() + undistorted.y() * undistorted.y());
  if (undistorted_radius == 0.0 || kappa == 0.0) return undistorted;
  double fold_radius = std::numeric_limits<double>::infinity();  // r*: where g stops increasing
  if (kappa < 0.0) {
    fold_radius = 1.0 / std::sqrt(-3.0 * kappa);
    if (undistorted_radius > (2.0 / 3.0) * fold_radius) return std::nullopt;
  }
  // Newton on g(r) = r + κ r³ − r_u from r = r_u (monotone, see the header comment).
  double radius = undistorted_radius;
  for (int iteration = 0; iteration < kMaxDistortionIterations; ++iteration) {
    const double radius_squared = radius * radius;
    const double residual = radius + kappa * (radius_squared * radius) - undistorted_radius;
    const double slope = 1.0 + 3.0 * kappa * radius_squared;
    const double step = residual / slope;
    radius -= step;
    if (std::abs(step) <= kDistortionTolerance * radius) break;
  }
  if (!(radius >= 0.0 && radius < fold_radius)) return std::nullopt;
  const double scale = radius / undistorted_radius;
  return Vector2d(scale * undistorted.x(), scale * undistorted.y());
}

CameraProjection TsaiCamera::project(const Vector3d& world_point) const {
  const Vector3d camera = camera_coordinates(world_point);
  CameraProjection projection;
  projection.depth_m = camera.z();
  projection.in_front = camera.z() > 0.0;
  if (!projection.in_front) return projection;
  const Vector2d undistorted(intrinsic_.focal_mm * camera.x() / camera.z(),
                             intrinsic_.focal_mm * camera.y() / camera.z());
  const std::optional<Vector2d> distorted = distorted_from_undistorted(undistorted);
  projection.in_domain = distorted.has_value();
  if (!projection.in_domain) return projection;
  projection.pixel = Vector2d(intrinsic_.sx * distorted->x() / geometry_.dpx_mm + intrinsic_.cx_px,
                              distorted->y() / geometry_.dpy_mm + intrinsic_.cy_px);
  return projection;
}

bool TsaiCamera::is_inside_image(const Vector2d& pixel) const {
  return pixel.x() >= 0.0 && pixel.x() < geometry_.width_px && pixel.y() >= 0.0 &&
         pixel.y() < geometry_.height_px;
}

bool TsaiCamera::sees(const Vector3d& world_point) const {
  const CameraProjection projection = project(world_point);
  return projection.valid() && is_inside_image(projection.pixel);
}

std::optional<Vector3d> TsaiCamera::back_project_to_ground(const Vector2d& pixel,
                                                           double ground_height_m) const {
  const Vector2d undistorted = undistorted_sensor_point(distorted_sensor_point(pixel));
  const Vector3d direction =
      multiply_transposed(rotation_, Vector3d(undistorted.x(), undistorted.y(), intrinsic_.focal_mm));
  if (direction.z() == 0.0) return std::nullopt;
  const double distance = (ground_height_m - centre_.z()) / direction.z();  // λ
  if (!(distance > 0.0) || !std::isfinite(distance)) return std::nullopt;
  return Vector3d(centre_.x() + distance * direction.x(), centre_.y() + distance * direction.y(),
                  ground_height_m);
}

Matrix2d TsaiCamera::ground_jacobian(const Vector2d& pixel, double ground_height_m) const {
  const double kappa = intrinsic_.kappa1_per_mm2;
  const Vector2d distorted = distorted_sensor_point(pixel);
  const double xd = distorted.x();
  const double yd = distorted.y();
  const double radius_squared = xd * xd + yd * yd;
  const double factor = 1.0 + kappa * radius_squared;

  Matrix2d pixel_part = Matrix2d::Zero();  // ∂(X_d, Y_d)/∂(u, v)
  pixel_part(0, 0) = geometry_.dpx_mm / intrinsic_.sx;
  pixel_part(1, 1) = geometry_.dpy_mm;

  Matrix2d undistort_part;  // ∂(X_u, Y_u)/∂(X_d, Y_d)
  const double cross_term = 2.0 * kappa * xd * yd;
  undistort_part << factor + 2.0 * kappa * xd * xd, cross_term,  //
      cross_term, factor + 2.0 * kappa * yd * yd;

  const Vector3d direction = multiply_transposed(
      rotation_, Vector3d(factor * xd, factor * yd, intrinsic_.focal_mm));  // d = Rᵀ (X_u, Y_u, f)
  const Vector3d along_x = rotation_.row(0).transpose();                    // a = ∂d/∂X_u
  const Vector3d along_y = rotation_.row(1).transpose();                    // b = ∂d/∂Y_u
  const double scale = (ground_height_m - centre_.z()) / (direction.z() * direction.z());
  Matrix2d ray_part;  // ∂(x, y)/∂(X_u, Y_u)
  ray_part << scale * (along_x.x() * direction.z() - direction.x() * along_x.z()),
      scale * (along_y.x() * direction.z() - direction.x() * along_y.z()),
      scale * (along_x.y() * direction.z() - direction.y() * along_x.z()),
      scale * (along_y.y() * direction.z() - direction.y() * along_y.z());

  return multiply(multiply(ray_part, undistort_part), pixel_part);
}

TsaiCamera TsaiCamera::with_pose_error(const Vector3d& rotation_error_rad,
                                       const Vector3d& centre_shift_m) const {
  const Matrix3d turn = tsai_rotation(rotation_error_rad.x(), rotation_error_rad.y(), rotation_error_rad.z());
  const Matrix3d rotation = multiply(turn, rotation_);
  const Vector3d centre = centre_ + centre_shift_m;
  const Vector3d translation = -multiply(rotation, centre);
  return TsaiCamera(name_, geometry_, intrinsic_, rotation, translation);
}

// ── Reading ──

namespace {

// The calibration file: its elements and attributes, reported at the element's line on any problem.
class CalibrationFile : public XmlFile {
 public:
  explicit CalibrationFile(const std::string& path) : XmlFile(path, "Camera") {}

  pugi::xml_node element(const pugi::xml_node& parent, const char* name) const {
    const pugi::xml_node child = parent.child(name);
    if (!child) fail(parent, fmt::format("<{}> has no <{}> element", parent.name(), name));
    return child;
  }

  double positive_number(const pugi::xml_node& element, const char* name) const {
    const double value = number(element, name);
    if (!(value > 0.0)) {
      fail(element, fmt::format("<{}> attribute {} must be positive (got {})", element.name(), name, value));
    }
    return value;
  }

  int positive_whole_number(const pugi::xml_node& element, const char* name) const {
    const double value = positive_number(element, name);
    if (value != std::floor(value) || value > 1e9) {
      fail(element, fmt::format("<{}> attribute {} must be a whole number of pixels (got {})", element.name(),
                                name, value));
    }
    return static_cast<int>(value);
  }
};

constexpr double kMillimetresPerMetre = 1000.0;

}  // namespace

TsaiCamera read_tsai_camera(const std::string& path) {
  const CalibrationFile file(path);
  const pugi::xml_node& camera = file.top();

  const pugi::xml_node geometry_element = file.element(camera, "Geometry");
  TsaiGeometry geometry;
  geometry.width_px = file.positive_whole_number(geometry_element, "width");
  geometry.height_px = file.positive_whole_number(geometry_element, "height");
  geometry.ncx = file.number(geometry_element, "ncx");
  geometry.nfx = file.number(geometry_element, "nfx");
  geometry.dx_mm = file.number(geometry_element, "dx");
  geometry.dy_mm = file.number(geometry_element, "dy");
  geometry.dpx_mm = file.positive_number(geometry_element, "dpx");
  geometry.dpy_mm = file.positive_number(geometry_element, "dpy");

  const pugi::xml_node intrinsic_element = file.element(camera, "Intrinsic");
  TsaiIntrinsic intrinsic;
  intrinsic.focal_mm = file.positive_number(intrinsic_element, "focal");
  intrinsic.kappa1_per_mm2 = file.number(intrinsic_element, "kappa1");
  intrinsic.cx_px = file.number(intrinsic_element, "cx");
  intrinsic.cy_px = file.number(intrinsic_element, "cy");
  intrinsic.sx = file.positive_number(intrinsic_element, "sx");

  const pugi::xml_node extrinsic_element = file.element(camera, "Extrinsic");
  TsaiExtrinsic extrinsic;
  extrinsic.tx_m = file.number(extrinsic_element, "tx") / kMillimetresPerMetre;
  extrinsic.ty_m = file.number(extrinsic_element, "ty") / kMillimetresPerMetre;
  extrinsic.tz_m = file.number(extrinsic_element, "tz") / kMillimetresPerMetre;
  extrinsic.rx_rad = file.number(extrinsic_element, "rx");
  extrinsic.ry_rad = file.number(extrinsic_element, "ry");
  extrinsic.rz_rad = file.number(extrinsic_element, "rz");

  std::string name = camera.attribute("name").value();
  try {
    return TsaiCamera(std::move(name), geometry, intrinsic, extrinsic);
  } catch (const std::invalid_argument& error) {
    file.fail(camera, error.what());
  }
}

}  // namespace stgf
