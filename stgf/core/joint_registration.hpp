// SPDX-License-Identifier: Apache-2.0
#pragma once
// The positions of a scene's objects and the registration offsets of its views, estimated jointly:
// one Gaussian over s = (p_1, …, p_m, β_1, …, β_n), so that views on their own clocks — which never
// measure an object at the same instant, so view_registration.hpp's differences never form — still
// teach the filter their offsets, through each measurement's innovation against the fused prediction.
//
// Model (view_registration.hpp): view u's measurement of object i is
//     z = p_i + H_u β_u + e,   e ~ N(0, R),   H_u = [ I₃  L ],  L Lᵀ = R,
// with β_u = (t_u, δ_u) ∈ R⁶ constant over the scene and a prior N(0, diag(σ², α² I₃)) per view,
// independent across views (RegistrationPrior). A measurement is a linear observation of s with
// H = [0 … I₃ (at p_i) … H_u (at β_u) … 0], and the Kalman update on it is exact:
//     ν = z − p̂_i − H_u β̂_u,   S = H Σ Hᵀ + R,   K = Σ Hᵀ S⁻¹,   ŝ += K ν,   Σ −= K S Kᵀ.
// It moves every object's position and every view's offset by what the measurement says about them
// through their correlations. Several views measuring an object at one time are several such updates,
// which together are the exact multi-view update of the joint model: their differences teach the
// offsets exactly as in view_registration.hpp. Between times, an object's position moves by its
// motion forecast, p_i += d, Σ_ii += Q (the offsets are constant, so nothing else changes).
// An object starts diffuse (P⁻¹ = 0 on p_i): from its first measurement, p_i = z − H_u β_u − e, i.e.
//     p̂_i = z − H_u β̂_u,   Σ_ii = R + H_u Σ_uu H_uᵀ,   Σ_{i,·} = −H_u Σ_{u,·},
// the exact limit of the update. The offset common to all views, which nothing reveals, stays at its
// prior and in every position's covariance. With a zero prior no offsets are kept, and this is the
// plain filter (information-form multi-view update, multi_view_update.hpp).
//
// Cost: the state has 3m + 6n entries; an update costs O((3m + 6n)²) — scenes of tens of objects and
// views. The positions' cross-covariances are what make it exact.

#include <map>
#include <string>
#include <string_view>

#include <Eigen/Dense>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/records.hpp"
#include "stgf/core/view_registration.hpp"

namespace stgf {

class JointRegistration {
 public:
  // Throws std::invalid_argument when a sigma is negative or not finite.
  explicit JointRegistration(const RegistrationPrior& prior);

  bool has_object(std::string_view object) const { return objects_.contains(object); }
  // `noise_scale` μ ≥ 1 below: the measurement's noise is μ R (view_noise_scales.hpp); its offset
  // model H_u stays that of the stated R.

  // Starts the object from its first measurement (diffuse); adds the view if new.
  void add_object(const Measurement& first, double noise_scale = 1.0);
  void remove_object(std::string_view object);
  // Σ_tt += covariance on the view's translation offset t_u: its calibration may have changed (a
  // jump), by about that much. Nothing for an unknown view or a zero prior.
  void release_offset(std::string_view view, const Matrix3d& covariance);
  // p_i += displacement, Σ_ii += process_noise.
  void predict(std::string_view object, const Vector3d& displacement, const Matrix3d& process_noise);

  // The innovation ν = z − p̂_i − H_u β̂_u and its covariance S (the object must be known).
  struct Innovation {
    Vector3d value;
    Matrix3d covariance;
  };
  Innovation innovation(const Measurement& measurement, double noise_scale = 1.0) const;
  // The Kalman update with one measurement of a known object; adds the view if new.
  void update(const Measurement& measurement, double noise_scale = 1.0);

  Gaussian3 position(std::string_view object) const;  // the marginal of p_i
  // A measurement alone, corrected by its view's offset: N(z − H_u β̂_u, μR + H_u Σ_uu H_uᵀ).
  Gaussian3 corrected(const Measurement& measurement, double noise_scale = 1.0) const;
  // The estimated offset of `view` and its covariance (prior for an unknown view).
  Eigen::Matrix<double, 6, 1> offset(std::string_view view) const;
  Eigen::Matrix<double, 6, 6> offset_covariance(std::string_view view) const;
  std::size_t view_count() const { return views_.size(); }
  bool active() const { return !prior_.is_zero(); }

 private:
  Eigen::Index add_view(std::string_view view);  // index of its block (none for a zero prior: −1)
  Eigen::Index view_index(std::string_view view) const;
  Eigen::Index grow(Eigen::Index size);           // appends a zero block; returns its start

  RegistrationPrior prior_;
  Eigen::Matrix<double, 6, 6> prior_covariance_;
  std::map<std::string, Eigen::Index, std::less<>> objects_;  // start of p_i
  std::map<std::string, Eigen::Index, std::less<>> views_;    // start of β_u
  Eigen::VectorXd mean_;
  Eigen::MatrixXd covariance_;
};

}  // namespace stgf
