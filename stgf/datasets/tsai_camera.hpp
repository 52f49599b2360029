// SPDX-License-Identifier: Apache-2.0
#pragma once
// A calibrated camera in R. Y. Tsai's model (IEEE J. Robotics and Automation 3(4), 1987), as the
// PETS 2009 calibration files give it (View_001.xml … View_008.xml; data/README.md §2), and the
// geometry the mpl benchmark needs: project a world point to a pixel, back-project a pixel onto the
// ground, the Jacobian of that back-projection, and a camera whose pose differs slightly from the
// calibration.
//
// ── Units ────────────────────────────────────────────────────────────────────────────────────────
// World coordinates are in METRES (stgf's unit). The files give the translation in millimetres;
// read_tsai_camera converts it, and nothing else in stgf sees millimetres of the world. The sensor
// plane keeps Tsai's units: focal length, sensor coordinates (X, Y) and pixel sizes in sensor
// millimetres, κ₁ in 1/mm² — only ratios of them reach the world, so they need no conversion.
//
// ── The model (world point p_w → pixel (u, v)) ──────────────────────────────────────────────────
//   rotation    with sa = sin rx, ca = cos rx, sb = sin ry, cb = cos ry, sg = sin rz, cg = cos rz
//                   ⎡ cb·cg   cg·sa·sb − ca·sg   sa·sg + ca·cg·sb ⎤
//               R = ⎢ cb·sg   sa·sb·sg + ca·cg   ca·sb·sg − cg·sa ⎥   (= Rz(rz) Ry(ry) Rx(rx))
//                   ⎣ −sb     cb·sa              ca·cb            ⎦
//   camera      p_c = R p_w + T,  T = (tx, ty, tz);  the point is in front of the camera when z_c > 0
//   pinhole     X_u = f x_c / z_c,   Y_u = f y_c / z_c                    (undistorted sensor, mm)
//   distortion  X_u = X_d (1 + κ₁ r_d²),  Y_u = Y_d (1 + κ₁ r_d²),  r_d² = X_d² + Y_d²
//   pixels      u = s_x X_d / d'_x + C_x,   v = Y_d / d'_y + C_y
// The camera centre is C = −Rᵀ T (p_c = R (p_w − C)).
//
// Projecting needs (X_d, Y_d) from (X_u, Y_u): both lie on the same ray from the principal point,
// (X_d, Y_d) = (r_d / r_u)(X_u, Y_u), where r_d solves g(r_d) = r_d + κ₁ r_d³ = r_u. Solved by
// Newton's method r ← r − g(r)/g'(r), g'(r) = 1 + 3κ₁r², from r₀ = r_u, until the step is below
// 1e-15 of r (at most 100 iterations). Newton converges monotonically here: for κ₁ ≥ 0, g is
// convex and increasing and g(r₀) = κ₁r_u³ ≥ 0 (start right of the root); for κ₁ < 0, g is concave
// and g(r₀) ≤ 0 (start left of the root). For κ₁ < 0, g increases only up to r* = 1/√(−3κ₁), where
// it reaches r_u,max = (2/3) r*: undistorted radii beyond r_u,max have no image (the model folds
// back), and such points are reported as outside the model's domain. Every pixel's undistorted
// radius is at most r_u,max, so these points lie outside the field of view the model describes. Of the
// PETS cameras only view 7 (κ₁ = −0.062/mm², r* = 2.32 mm) folds within its image: its principal
// point is off-centre and two image corners lie up to 2.5 mm from it. 1996 of the 4650 annotated foot
// points are beyond its r_u,max; an undistortion by fixed-point iteration r ← r_u/(1 + κ₁r²), which
// does not converge there, would put hundreds of them inside the image.
//
// ── Back-projection onto the ground plane z = h ──────────────────────────────────────────────────
//   X_d = d'_x (u − C_x) / s_x,   Y_d = d'_y (v − C_y),   (X_u, Y_u) = (1 + κ₁ r_d²)(X_d, Y_d)
//   ray   p(λ) = C + λ d,  d = Rᵀ (X_u, Y_u, f)   (world direction of the pixel's line of sight)
//   hit   λ = (h − C_z) / d_z,  valid when λ > 0 (the ray goes down to the ground in front of the
//         camera; pixels at or above the horizon have no ground point)
//   (x, y) = (C_x + λ d_x,  C_y + λ d_y)
//
// ── Jacobian of the back-projection J = ∂(x, y)/∂(u, v) (analytic, by the chain rule) ───────────
//   J = J_ray · J_undistort · J_pixel
//   J_pixel     = diag(d'_x / s_x, d'_y)                                            ∂(X_d,Y_d)/∂(u,v)
//   J_undistort = ⎡ 1 + κ₁ r_d² + 2κ₁X_d²   2κ₁ X_d Y_d           ⎤                 ∂(X_u,Y_u)/∂(X_d,Y_d)
//                 ⎣ 2κ₁ X_d Y_d             1 + κ₁ r_d² + 2κ₁Y_d² ⎦
//   J_ray       = (h − C_z)/d_z² ⎡ a_x d_z − d_x a_z   b_x d_z − d_x b_z ⎤          ∂(x,y)/∂(X_u,Y_u)
//                                ⎣ a_y d_z − d_y a_z   b_y d_z − d_y b_z ⎦
//   where a = Rᵀe₁ = ∂d/∂X_u and b = Rᵀe₂ = ∂d/∂Y_u (the first two rows of R), from
//   x = C_x + (h − C_z) d_x/d_z and y = C_y + (h − C_z) d_y/d_z.
// A pixel error δ with covariance Σ moves the ground point by ≈ J δ, with covariance J Σ Jᵀ: larger
// and more elongated along the line of sight the further (and the more grazing) the ray.
//
// ── A camera that differs from its calibration ───────────────────────────────────────────────────
// with_pose_error(ε, δ) is the camera turned by small angles ε = (ε_x, ε_y, ε_z) about its OWN axes
// and moved by δ (world metres), same intrinsics:
//   R' = ΔR R with ΔR = Rz(ε_z) Ry(ε_y) Rx(ε_x) (the matrix above with the angles ε),
//   C' = C + δ,  T' = −R' C'.
// Its extrinsic() angles are recovered from R' (ry' = asin(−R'₃₁), rx' = atan2(R'₃₂, R'₃₃),
// rz' = atan2(R'₂₁, R'₁₁)) for information; all computation uses R' itself.
//
// Reproducibility: sines and cosines come from stgf::portable and products are written out in a
// fixed order, so the same camera gives the same bits on every IEEE 754 platform.

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

using Eigen::Matrix2d;
using Eigen::Vector2d;

// Geometry: the sensor and the frame grabber.
struct TsaiGeometry {
  int width_px = 0;     // image width (pixels)
  int height_px = 0;    // image height (pixels)
  double ncx = 0.0;     // sensor elements in the camera's x direction (used by calibration only)
  double nfx = 0.0;     // pixels in a line as sampled by the computer (used by calibration only)
  double dx_mm = 0.0;   // centre-to-centre distance of sensor elements in x (mm)
  double dy_mm = 0.0;   // centre-to-centre distance of sensor elements in y (mm)
  double dpx_mm = 0.0;  // d'_x = dx·ncx/nfx, effective pixel width (mm)
  double dpy_mm = 0.0;  // d'_y, effective pixel height (mm)
};

// Intrinsic parameters.
struct TsaiIntrinsic {
  double focal_mm = 0.0;        // f, effective focal length (mm)
  double kappa1_per_mm2 = 0.0;  // κ₁, first-order radial distortion (1/mm²)
  double cx_px = 0.0;           // C_x, principal point, column (pixels)
  double cy_px = 0.0;           // C_y, principal point, row (pixels)
  double sx = 1.0;              // s_x, horizontal scale factor of the frame grabber (dimensionless)
};

// Extrinsic parameters: p_c = R(rx, ry, rz) p_w + T.
struct TsaiExtrinsic {
  double tx_m = 0.0;  // T, the world origin in camera coordinates (metres; the files give mm)
  double ty_m = 0.0;
  double tz_m = 0.0;
  double rx_rad = 0.0;  // rotation angles (radians)
  double ry_rad = 0.0;
  double rz_rad = 0.0;
};

// The projection of a world point.
struct CameraProjection {
  bool in_front = false;   // z_c > 0
  bool in_domain = false;  // the distortion model has an image for it (always when κ₁ ≥ 0)
  double depth_m = 0.0;    // z_c (metres)
  Vector2d pixel = Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());  // (u, v) when valid()

  bool valid() const { return in_front && in_domain; }
};

// R = Rz(rz) Ry(ry) Rx(rx), Tsai's rotation (see the header comment).
Matrix3d tsai_rotation(double rx_rad, double ry_rad, double rz_rad);

class TsaiCamera {
 public:
  // Throws std::invalid_argument when a parameter is out of range (image size, pixel sizes, focal
  // length or s_x not positive, anything not finite), naming it.
  TsaiCamera(std::string name, const TsaiGeometry& geometry, const TsaiIntrinsic& intrinsic,
             const TsaiExtrinsic& extrinsic);

  const std::string& name() const { return name_; }
  const TsaiGeometry& geometry() const { return geometry_; }
  const TsaiIntrinsic& intrinsic() const { return intrinsic_; }
  const TsaiExtrinsic& extrinsic() const { return extrinsic_; }
  const Matrix3d& rotation() const { return rotation_; }        // R
  const Vector3d& translation() const { return translation_; }  // T (metres)
  const Vector3d& centre() const { return centre_; }            // C = −Rᵀ T (world, metres)
  int width_px() const { return geometry_.width_px; }
  int height_px() const { return geometry_.height_px; }

  // p_c = R p_w + T.
  Vector3d camera_coordinates(const Vector3d& world_point) const;

  // World point (metres) → pixel.
  CameraProjection project(const Vector3d& world_point) const;

  // 0 ≤ u < width and 0 ≤ v < height: the pixel lies on the image (u, v as the calibration and the
  // PETS annotations use them, u along a row, v down the rows).
  bool is_inside_image(const Vector2d& pixel) const;

  // The projection is valid and inside the image.
  bool sees(const Vector3d& world_point) const;

  // The point of the plane z = ground_height_m on the pixel's line of sight, or nullopt when the
  // ray does not reach that plane in front of the camera (λ ≤ 0 or d_z = 0).
  std::optional<Vector3d> back_project_to_ground(const Vector2d& pixel, double ground_height_m = 0.0) const;

  // J = ∂(x, y)/∂(u, v) of back_project_to_ground at `pixel` (metres per pixel). Defined wherever
  // the ray is not parallel to the plane; meaningful where back_project_to_ground has a point.
  Matrix2d ground_jacobian(const Vector2d& pixel, double ground_height_m = 0.0) const;

  // The distorted sensor coordinates (X_d, Y_d) of a pixel and the undistorted ones of a sensor point.
  Vector2d distorted_sensor_point(const Vector2d& pixel) const;
  Vector2d undistorted_sensor_point(const Vector2d& distorted) const;
  // (X_d, Y_d) from (X_u, Y_u) by the Newton solve above; nullopt outside the model's domain.
  std::optional<Vector2d> distorted_from_undistorted(const Vector2d& undistorted) const;

  // The same camera turned by `rotation_error_rad` (small angles about its own x, y, z axes) and
  // with its centre moved by `centre_shift_m` (world, metres). See the header comment.
  TsaiCamera with_pose_error(const Vector3d& rotation_error_rad, const Vector3d& centre_shift_m) const;

 private:
  TsaiCamera(std::string name, const TsaiGeometry& geometry, const TsaiIntrinsic& intrinsic,
             const Matrix3d& rotation, const Vector3d& translation);
  void validate() const;

  std::string name_;
  TsaiGeometry geometry_;
  TsaiIntrinsic intrinsic_;
  TsaiExtrinsic extrinsic_;
  Matrix3d rotation_;
  Vector3d translation_;
  Vector3d centre_;
};

// Reads a Tsai calibration file:
//   <Camera name="View_001">
//     <Geometry width=".." height=".." ncx=".." nfx=".." dx=".." dy=".." dpx=".." dpy=".."/>
//     <Intrinsic focal=".." kappa1=".." cx=".." cy=".." sx=".."/>
//     <Extrinsic tx=".." ty=".." tz=".." rx=".." ry=".." rz=".."/>   (tx, ty, tz in millimetres)
//   </Camera>
// Throws InputError (stgf/io/input_error.hpp) naming `path` and the line of the offending element
// when the file cannot be read, is not well-formed XML, or an element or attribute is missing,
// not a finite number (width and height: not a positive whole number), or out of range.
TsaiCamera read_tsai_camera(const std::string& path);

}  // namespace stgf
