// SPDX-License-Identifier: Apache-2.0
#pragma once
// One object's measurements within a track's open frame, moved along the track's predicted path to
// one time, so that views on their own clocks can still be compared: what the registration prior's
// scale κ learns from (registration_prior_scale.hpp).
//
// Views that measure an object at one time disagree by their offsets and their noise alone, and the
// filter compares them there (SceneFilter, JointRegistration::observe_differences). Views on their
// own clocks never measure an object at the same time: without more, κ learns nothing from them and
// stays at the prior as calibrated — a camera network registered 3× worse than the training data,
// unsynchronised, gave NEES 7.4 (mpl test split made asynchronous, first 300 scenes) where the same
// network synchronised gives 2.8. Within a frame (object_track.hpp: less than a frame period), the
// track is predicted from one event to the next along one forecast, x(t_k) = x(t_1) + d_k with
//     d_k = Σ (the displacements of the predictions from t_1 to t_k),
//     C_k = Σ (their covariances, D [Q(τ) − Q(τ_s)] D and the speed term),
// so z_k − d_k measures the object's position at t_1, with the forecast's error between t_1 and t_k,
// of covariance C_k, added to its noise. That error is shared by later measurements (a random walk:
// Cov(e_j, e_k) = C_min(j,k)); the comparison takes each measurement's as its own and independent.
// Referred to the middle of the gathered ones (1 and n the first and last), each gets
//     A_k = |s_k| (C_n − C_1) / 2,   s_k = 2 tr(C_k − C_1) / tr(C_n − C_1) − 1 ∈ [−1, 1]
// — |C_k − C_mid| with C_mid = (C_1 + C_n) / 2 when the increments keep one shape, as Q's do along one
// forecast (the speed term and a change of Q's online scale within the frame bend it a little), and
// positive semidefinite in any case (C_n − C_1 is a sum of covariances). The difference of two
// measurements on either side of the middle then has its exact covariance, of two on one side more
// than its own: the comparison errs towards noise, never towards offsets, and the motion model's
// errors cannot pass for registration error.
//
// Only measurements fused alone at their time are gathered (a measurement compared at its own time
// with another view's is already counted there); a frame of a single time, as on synchronised views,
// adds nothing.

#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/records.hpp"

namespace stgf {

class FrameAlignment {
 public:
  // The track was predicted within the frame: the path moves by `displacement` with `covariance`.
  void follow(const Vector3d& displacement, const Matrix3d& covariance);
  // A measurement fused alone at the path's current time, with its noise scale μ.
  void gather(const Measurement& measurement, double noise_scale);

  std::size_t size() const { return gathered_.size(); }
  // The gathered measurements (at z_k − d_k, in gathering order; pointers into this frame, valid until
  // it changes), their noise scales and A_k, written over the three lists.
  void aligned(std::vector<const Measurement*>& measurements, std::vector<double>& noise_scales,
               std::vector<Matrix3d>& covariances) const;

 private:
  static constexpr std::size_t kTypicalViews = 8;  // room reserved at a frame's first measurement
  struct Gathered {
    Measurement measurement;  // z_k − d_k
    double noise_scale;
    Matrix3d path_covariance;  // C_k
  };
  std::vector<Gathered> gathered_;
  Vector3d displacement_ = Vector3d::Zero();  // d of the path's current time
  Matrix3d covariance_ = Matrix3d::Zero();    // C of the path's current time
};

}  // namespace stgf
