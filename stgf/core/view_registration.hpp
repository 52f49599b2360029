// SPDX-License-Identifier: Apache-2.0
#pragma once
// Registration error: the part of a view's error that its R does not state and that does not
// average out over time — a camera's calibration error, a vehicle's GPS pose error. It shifts all of
// that view's measurements the same way, so a filter that trusts R alone gets overconfident (NEES ≫ 3)
// and weights a biased view as if it were exact.
//
// Model. View u's measurement of an object at p is
//     z = p + H_u β_u + e,   e ~ N(0, R),   H_u = [ I₃  F  r ]  (offset_jacobian below),
//     F = G L(Gᵀ R G)  (L(·) the lower Cholesky factor, G the turn about the vertical to the ray's
//         heading, sensor → object),   r = (z − s) in the horizontal plane (s the sensor's position),
// with β_u = (t_u, δ_u, ε_u) ∈ R⁷ constant over a scene:
//   t_u  a translation in the world frame (a GPS or extrinsic position error);
//   δ_u  an offset in the view's own noise units (a small rotation of a camera or range sensor moves
//        every measurement by about the same angle / the same pixels, which reaches the world through
//        the same Jacobian that shapes R, so it grows with range exactly as R does). In the ray's
//        frame its first component moves the measurement along the ray in the ray's own sense (a
//        tilt), its second across it (a pan), for every ray of the view, whatever the world frame;
//   ε_u  a scale of the view's horizontal range about its own position: a ground-plane camera whose
//        height is off by Δh places every ground point (h + Δh)/h as far from its foot, an offset
//        (Δh/h)(p − s) linear in range, where R along the ray grows with its square, so δ cannot hold
//        it; a range sensor's scale error likewise. Rows without a sensor position have no range (r = 0).
// Prior: t_u ~ N(0, diag(σ_x², σ_y², σ_z²)), δ_u ~ N(0, diag(α_along², α_across², α_vertical²)) in the
// ray's frame, ε_u ~ N(0, σ_ε²), independent across views (RegistrationPrior; calibrate it with
// registration_calibration.hpp: one α for all three axes by default, or one per axis; σ_ε = 0 unless
// calibrated with `stgf train --range-scale` or set: a zero prior keeps ε out of β, at no cost).
//
// Online estimation, per scene. The joint Gaussian N(β̂, Σ) over the offsets of every view seen so far
// is learned only from what views disagree on: when views V = {u₁..u_k}, k ≥ 2, measure the same object
// at the same step, the differences d_j = z_{u_j} − z_{u₁} (j = 2..k) do not depend on the unknown p:
//     d = D G β_V + D e,   D = [−I I 0 …; −I 0 I …; …],  G = blockdiag(H_{u_j}),
// a linear measurement of β with noise D diag(R) Dᵀ; a Kalman update on it is the exact posterior of β
// with p marginalised under a flat prior (so the motion model never feeds back into β). An offset
// shared by every view is not observable this way; it stays at its prior, and its uncertainty stays in
// the fused covariance.
//
// Fusion. The measurements of one object at a step, corrected c_u = z_u − H_u β̂_u, carry the noise
// e_u + H_u (β_u − β̂_u): covariance C = G Σ_VV Gᵀ + diag(R_u) (correlated across views through Σ).
// Their combined measurement is the generalised least-squares mean
//     A = Sᵀ C⁻¹ S,   x = A⁻¹ Sᵀ C⁻¹ c,   covariance A⁻¹,     S = [I₃; I₃; …],
// which feeds the multi-view update like a single view. With Σ = 0 and β̂ = 0 it is the
// information-weighted mean of the measurements, so the filter reduces to the plain update.
// Learn from a step only after fusing it, so no measurement is used twice.
//
// Views on their own clocks rarely measure an object at the same instant, so these differences seldom
// form: the spatiotemporal graph filter's one-track-per-object mode estimates offsets jointly with the
// positions instead (joint_registration.hpp); this class serves its per-view tracks.
//
// Cost: state 7n for n views; a learning update is O((6n)² k) per object, a fusion O((3k)³).

#include <map>
#include <optional>
#include <span>
#include <string>

#include <Eigen/Dense>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/records.hpp"
#include "stgf/core/sensor_motion.hpp"

namespace stgf {

// A view's offset β_u = (t_u, δ_u, ε_u): its size, and the fixed-size types that hold one.
inline constexpr int kOffsetSize = 7;
using OffsetVector = Eigen::Matrix<double, kOffsetSize, 1>;
using OffsetMatrix = Eigen::Matrix<double, kOffsetSize, kOffsetSize>;
using OffsetJacobian = Eigen::Matrix<double, 3, kOffsetSize>;

struct RegistrationPrior {
  Vector3d translation_sigma = Vector3d::Zero();  // σ of t along the world axes (m)
  // α: σ of δ in units of the view's own noise, per axis of δ: along the measurement's ray, across it
  // (horizontal), vertical (offset_jacobian's frame; for a row without a sensor position the world's
  // x, y, z). Offsets differ by direction: a camera's tilt moves its measurements along their rays,
  // its pan across them; a vehicle's GPS heading error only across (design §1.7).
  Vector3d noise_ratio = Vector3d::Zero();
  // σ_ε of the view's horizontal range scale ε (a ratio: 0.01 is 1 %); 0: none.
  double range_scale_sigma = 0.0;
  // The kind of sensors it was calibrated on, where all were of one kind (none: unknown, or both kinds):
  // on sensors of that kind its shape is expected to hold (registration_prior_scale.hpp).
  std::optional<SensorMotion> calibrated_sensors;
  bool is_zero() const { return translation_sigma.isZero() && noise_ratio.isZero() && range_scale_sigma == 0.0; }
  // diag(σ_x², σ_y², σ_z², α_along², α_across², α_vertical², σ_ε²). Throws std::invalid_argument when a
  // σ or α is negative or not finite.
  OffsetMatrix covariance() const;
};

// H = [I₃  L  0] with L Lᵀ = R in the world's axes: how a view's offset β = (t, δ, ε) moves a
// measurement with covariance R whose sensor position is not known (no range to scale).
OffsetJacobian offset_jacobian(const Matrix3d& measurement_covariance);
// H = [I₃  F  r] for a measurement: with its sensor position s known, F = G L(Gᵀ R G), G the turn
// about the vertical taking x to the heading of its ray (object − sensor), so that δ's first component
// moves the measurement along its own ray, in the ray's own sense, and F turns with the world frame
// (design §1.1), and r = (z − s) in the horizontal plane, ε's column; without one (or straight above
// the sensor), offset_jacobian(R).
OffsetJacobian offset_jacobian(const Measurement& measurement);
// The same with ε's column from `position`, common to the views being compared (their weighted mean):
// wherever views' measurements are differenced, from each measurement itself one ε for every view with
// t_u = ε s_u would make every offset ε z_u, a scaling of the world about its origin that shrinks each
// disagreement by (1 − ε), and the views' noise would pass for offsets (design §1.7). Without a sensor
// position, as above.
OffsetJacobian offset_jacobian(const Measurement& measurement, const Vector3d& position);

class ViewRegistration {
 public:
  static constexpr int kOffsetSize = stgf::kOffsetSize;  // (t, δ, ε)

  // Throws std::invalid_argument when a sigma is negative or not finite.
  explicit ViewRegistration(const RegistrationPrior& prior);

  // Combines the measurements of ONE object at the current step (each view at most once) into one
  // equivalent measurement, corrected for the estimated offsets and uncertain by what is left of them.
  // Views not seen before count with their prior.
  Gaussian3 combine(std::span<const Measurement* const> measurements_of_object) const;

  // Learns from every measurement of a step (all objects); adds views seen for the first time.
  void learn(std::span<const Measurement* const> step);

  // The estimated offset (t, δ, ε) of `view` and its covariance (prior for an unknown view).
  OffsetVector offset(std::string_view view) const;
  OffsetMatrix offset_covariance(std::string_view view) const;
  std::size_t view_count() const { return views_.size(); }
  // False for a zero prior: every offset is exactly zero and nothing needs correcting.
  bool active() const { return !prior_.is_zero(); }

 private:
  int index_of(std::string_view view) const;  // −1 when unknown
  int add_view(std::string_view view);

  RegistrationPrior prior_;
  OffsetMatrix prior_covariance_;
  std::map<std::string, int, std::less<>> views_;
  Eigen::VectorXd offsets_;      // β̂, kOffsetSize per view in order of first appearance
  Eigen::MatrixXd covariance_;   // Σ
};

}  // namespace stgf
