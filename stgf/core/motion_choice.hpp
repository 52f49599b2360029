// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which motion a scene's tracks follow: the motion model's forecast (Φ), or constant velocity from
// the same history (DESIGN §1.13). A learned model predicts well on data like its training data; on
// other data (other objects, another rate, a world frame it never saw) it can predict worse than the
// simplest model there is, while its Q, calibrated where it was trained, does not say so. The
// innovations tell which of the two predicts this scene better.
//
// Both predict from the same track state. For the innovation ν = z − x of the first fused
// measurement of a frame (the sample the Q scale learns from, process_noise_scale.hpp), each model m
// has its own prediction x_m and its own scale λ_m of Q:
//     ν_m ~ N(0, A_m + D_m Q D_m),   A_m = P̂_last + R + (τ² − τ_s²) Var_m(v̂),  D_m = diag(√λ_m)
// (Var_m(v̂): the error of the velocity each reads off the history, object_track.hpp — Φ's from the whole
// history, constant velocity's from its last two positions, several times larger) and scores its
// predictive log-likelihood, per axis as the Q scale models it,
//     ℓ_m = Σ_a log N(ν_m,a; 0, A_m,aa + λ_m,a Q_aa),
// with λ_m as learnt from the earlier samples (a prequential score: each model is judged on data it
// had not yet seen). E = Σ (ℓ_cv − ℓ_Φ) over the scene is the log Bayes factor of constant velocity
// against Φ. The scene follows constant velocity once E > kSwitchEvidence and goes back to Φ once
// E < −kSwitchEvidence: a strong evidence either way (odds of 100 to 1), so one odd object does not
// decide, and the choice does not flap. λ_cv starts at 1, i.e. from Φ's Q: it only grows, so constant
// velocity is never presumed better than Φ was calibrated to be.
//
// Policies: kOff (Φ always: the paper's filter), kAuto (the above; the default), kAlways (constant
// velocity always, with Φ's Q: a model-free filter with the rest of stgf).

#include <cstddef>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/process_noise_scale.hpp"

namespace stgf {

enum class MotionFallback { kOff, kAuto, kAlways };

class MotionChoice {
 public:
  // ln 100: the log Bayes factor at which the scene switches.
  static constexpr double kSwitchEvidence = 4.605170185988091;

  // `fallback_scale`: λ_cv's start (its prior, and what other scenes said of it: process_noise_pool.hpp).
  explicit MotionChoice(MotionFallback policy = MotionFallback::kOff, ProcessNoiseScale fallback_scale = {})
      : policy_(policy), constant_velocity_(policy == MotionFallback::kAlways), fallback_scale_(fallback_scale) {}

  // Whether the tracks follow constant velocity now (always with kAlways, never with kOff).
  bool constant_velocity() const { return constant_velocity_; }
  // Whether samples are wanted (kAuto).
  bool compares() const { return policy_ == MotionFallback::kAuto; }


  // One sample: the innovation of both models' predictions (ν_Φ, ν_cv), their A_Φ and A_cv, and
  // Q(τ) − Q(τ_s). `learned` is Φ's λ before this sample. With `adapt`, λ_cv learns from ν_cv.
  void add(const Vector3d& learned_innovation, const Vector3d& fallback_innovation,
           const Matrix3d& learned_known_covariance, const Matrix3d& fallback_known_covariance,
           const Matrix3d& process_noise, const ProcessNoiseScale& learned, bool adapt);
  // kAlways: λ_cv learns from its innovation (there is no comparison).
  void learn_fallback(const Vector3d& innovation, const Matrix3d& known_covariance, const Matrix3d& process_noise) {
    fallback_scale_.add(innovation, known_covariance, process_noise);
  }

  double evidence() const { return evidence_; }          // E: ln of the odds of constant velocity against Φ
  std::size_t switches() const { return switches_; }     // how often the scene changed motion
  std::size_t samples() const { return samples_; }
  const ProcessNoiseScale& fallback_scale() const { return fallback_scale_; }

 private:
  MotionFallback policy_;
  bool constant_velocity_;
  ProcessNoiseScale fallback_scale_;
  double evidence_ = 0.0;
  std::size_t switches_ = 0;
  std::size_t samples_ = 0;
};

// Over the scenes of a run: how many ended following constant velocity, how many ever switched.
struct MotionChoiceSummary {
  std::size_t scenes = 0;
  std::size_t constant_velocity_scenes = 0;  // following constant velocity at their end
  std::size_t switched_scenes = 0;           // changed motion at least once
  void add(const MotionChoice& choice) {
    ++scenes;
    if (choice.constant_velocity()) ++constant_velocity_scenes;
    if (choice.switches() > 0) ++switched_scenes;
  }
  void add(const MotionChoiceSummary& other) {
    scenes += other.scenes;
    constant_velocity_scenes += other.constant_velocity_scenes;
    switched_scenes += other.switched_scenes;
  }
};

// Σ_a log N(ν_a; 0, A_aa + λ_a Q_aa): the per-axis predictive log-likelihood above.
double per_axis_log_likelihood(const Vector3d& innovation, const Matrix3d& known_covariance,
                               const Matrix3d& process_noise, const Vector3d& scales);

}  // namespace stgf
