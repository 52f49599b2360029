// SPDX-License-Identifier: Apache-2.0
#pragma once
// The positions of a scene's objects and the registration offsets of its views, estimated jointly:
// one Gaussian over s = (p_1, …, p_m, β_1, …, β_n), so that views on their own clocks — which never
// measure an object at the same instant, so view_registration.hpp's differences never form — still
// teach the filter their offsets, through each measurement's innovation against the fused prediction.
//
// Model (view_registration.hpp): view u's measurement of object i is
//     z = p_i + H_u β_u + e,   e ~ N(0, R),   H_u = [ I₃  F ]  (F: R's factor along the ray, offset_jacobian),
// with β_u = (t_u, δ_u, ε_u) ∈ R⁷ constant over the scene and a prior N(0, diag(σ², α², σ_ε²)) per view (α per ray axis),
// independent across views (RegistrationPrior). A measurement is a linear observation of s with
// H = [0 … I₃ (at p_i) … H_u (at β_u) … 0], and the Kalman update on it is exact:
//     ν = z − p̂_i − H_u β̂_u,   S = H Σ Hᵀ + R,   K = Σ Hᵀ S⁻¹,   ŝ += K ν,   Σ −= K S Kᵀ.
// It moves every object's position and every view's offset by what the measurement says about them
// through their correlations. Several views measuring an object at one time are several such updates,
// which together are the exact multi-view update of the joint model: their differences teach the
// offsets exactly as in view_registration.hpp. Between times, an object's position moves by its
// motion forecast, p_i += d, Σ_ii += Q (the offsets are constant, so nothing else changes).
// An object starts diffuse (P⁻¹ = 0 on p_i): from its first measurement, p_i = z − H_u β_u − e.
// The offset common to all views, which nothing reveals, stays at its prior and in every position's
// covariance. With a zero prior no offsets are kept, and this is the plain filter (information-form
// multi-view update, multi_view_update.hpp).
//
// Representation. Objects are correlated with each other only through the offsets: the Gaussian is
// kept, exactly, as the marginal of the offsets, in information form, and each position given them:
//     β ~ N(β̂, Σ_β),  Σ_β = M⁻¹,  β̂ = M⁻¹ m,     p_i = a_i + B_i β,  a_i ~ N(â_i, P_i) independent,
// with B_i (3 × 6n) how object i's position depends on the offsets. (Cov(p_i, p_j) = B_i Σ_β B_jᵀ and
// Cov(p_i, β) = B_i Σ_β are what the dense (3m + 6n)² covariance held.) Each operation keeps this form:
//   start       a_i = z − e:  â_i = z, P_i = R, B_i = −G_u (G_u = H_u E_u, E_u picks β_u out of β);
//               the first measurement alone says nothing of β
//   predict     â_i += d, P_i += Q
//   update      object i's measurements z_k = p_i + G_k β + e_k at one time (noise R_k = μ_k R):
//                 a_i given β, all at once (z_k − (B_i + G_k) β = a_i + e_k):
//                   P' = (P⁻¹ + Σ_k R_k⁻¹)⁻¹,  â' = P' (P⁻¹ â + Σ_k R_k⁻¹ z_k),
//                   B' = P' P⁻¹ B − Σ_k P' R_k⁻¹ G_k   (G_k is nonzero on view u's blocks only)
//                 β: the joint information of (p_i, β) is the conditional's,
//                   [P⁻¹, −P⁻¹B; −BᵀP⁻¹, BᵀP⁻¹B] (+ M on β), plus the measurements'; marginalising p_i
//                   and writing the result with the new conditional (â', B', P'):
//                   M += Σ_k G_kᵀ R_k⁻¹ G_k + BᵀP⁻¹B − B'ᵀP'⁻¹B',
//                   m += Σ_k G_kᵀ R_k⁻¹ z_k − BᵀP⁻¹â + B'ᵀP'⁻¹â'
//                 which for one measurement (k = 1, what views on their own clocks give) is the
//                 information z alone gives of β, with C = B + G and S = P + R:
//                   M += Cᵀ S⁻¹ C,  m += Cᵀ S⁻¹ (z − â)      (one rank-3 term, XᵀX with X = L_S⁻¹ C)
//                 (every other a_j is independent of z and keeps its own; their positions move with β̂)
//   remove      drop a_i and B_i: the exact marginal of the rest
//   release     view u's translation jumps by w ~ N(0, W) from now on: w joins β as a block of its own
//               (information W⁻¹ on W's range, zero mean, independent of everything), view u's
//               measurements depend on t_u + w, and no position depends on it — the dense filter's
//               Σ_tt += W, exactly.
// What is read (a position, an innovation, an offset) needs β̂ and Σ_β: M = L Lᵀ is factored once
// after it changes, and B Σ_β Bᵀ = ‖L⁻¹Bᵀ‖² (dense_kernels.hpp).
//
// Cost, with n the scene's views, c ≤ 6n the offsets' dimension, m the scene's objects and k the
// measurements of an object at one time: an update costs O(c + k) for the conditional (B' is one
// 3 × 3 product with B and a block per view) and two rank-3 terms of M (one for k = 1), O(c²),
// whatever k and m — kept pending and added for all of an event's objects at once (each
// measurement's own term G_kᵀR_k⁻¹G_k, on its view's blocks, joins a 6 × 6 sum per view, added to
// M once per fold); reading
// a position O(c²) (an event's positions in one blocked solve), an innovation O(c) after it (the
// view's L⁻¹E_uᵀ is kept per factorisation); refactoring M O(c³), once per event that changed it;
// predict O(1); memory O(c² + m c). So one event of m objects each seen by k views costs
// O(m (k + c²) + c³): linear in the views that see an object, and independent of how many objects
// each view sees. (Updating Σ_β itself, measurement by measurement,
// cost O(c²) per measurement, k times more; the dense joint covariance O((3m + c)²).)

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <Eigen/Dense>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/records.hpp"
#include "stgf/core/registration_prior_scale.hpp"
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
  // The combined innovation of several measurements of one known object at one time: ν̄ = Σ_k W_k ν_k
  // with the information weights W_k = R̄ R_k⁻¹, R̄ = (Σ_k R_k⁻¹)⁻¹ (R_k = μ_k R), and, since
  // Cov(ν_k, ν_l) = P_i + C_k Σ_β C_lᵀ + δ_kl R_k (C_k = B_i + H_k E_k, as for one),
  //     S̄ = P_i + V̄ᵀV̄ + R̄ (+ W_k H_k Σ₀' H_kᵀ W_kᵀ per view not yet seen, Σ₀' the scaled prior),
  //     V̄ = Σ_k L⁻¹C_kᵀ W_kᵀ
  //     = W_i + L⁻¹ Σ_k E_kᵀ H_kᵀ W_kᵀ:
  // O(kc + c²), one substitution however many views. What the object's prediction is tested against
  // when its views agree (R̄ ≪ R), so that an understated Q shows where one view's noise would hide
  // it. One measurement: innovation() itself.
  Innovation innovation(std::span<const Measurement* const> measurements, std::span<const double> noise_scales) const;
  // The Kalman update with measurements of one known object (any views, at one time: nothing is
  // predicted between them), each with its noise scale; adds the views that are new. Exactly the
  // updates with each in turn, in any order.
  void update(std::span<const Measurement* const> measurements, std::span<const double> noise_scales);
  void update(const Measurement& measurement, double noise_scale = 1.0);

  // The size of the offsets, learned from the views' disagreements (registration_prior_scale.hpp):
  // adds one object's measurements at one time that were fused (with their noise scales) as evidence,
  // and, once an event is done, re-estimates the prior's scales κ_t, κ_n (when the evidence has doubled)
  // and gives M its new prior term, M += (1/κ' − 1/κ) Λ₀ on each of the views' own coordinates with its
  // group's κ — exact, since M is the prior's information plus the data's. Returns whether either
  // changed. Without these calls, κ_t = κ_n = 1.
  // Measurements of one object at several times, each moved to one time along a predicted path
  // (frame_alignment.hpp), come with the covariance that moving adds to each, A_k: their weights are
  // W_k = (μ_k R_k + A_k)⁻¹ (their offset model H_k stays that of R_k).
  void observe_differences(std::span<const Measurement* const> measurements, std::span<const double> noise_scales,
                           std::span<const Matrix3d> alignment_covariances = {});
  bool adapt_prior_scale();
  RegistrationPriorScales prior_scales() const { return prior_scale_.scales(); }
  // The prior probability that the scales' two-scale hypothesis holds (RegistrationPriorScale::
  // set_two_scales_probability), from the next estimate on.
  void set_prior_scale_two_scales_probability(double probability) { prior_scale_.set_two_scales_probability(probability); }
  // The scales' start from other scenes' evidence (RegistrationPriorScale::start_from); before any view.
  void start_prior_scale_from(std::shared_ptr<const std::vector<double>> pooled) {
    prior_scale_.start_from(std::move(pooled));
  }
  // The evidence's log likelihood grid of the scales (RegistrationPriorScale::log_likelihood_grid) and
  // its size (difference dimensions; 0: none).
  std::vector<double> prior_scale_log_likelihood_grid() const { return prior_scale_.log_likelihood_grid(); }
  double prior_scale_evidence() const { return prior_scale_.evidence_dimensions(); }
  bool prior_scale_estimated() const { return prior_scale_.estimated(); }  // else κ = 1: too little evidence
  // Σ₀ with its translation block scaled by κ_t and its noise-ratio block by κ_n: the prior of a view
  // not yet seen.
  OffsetMatrix prior_covariance() const;

  Gaussian3 position(std::string_view object) const;  // the marginal of p_i
  // position() of several objects at once, in their order. Their spreads B_i Σ_β B_iᵀ that M changed
  // come from one blocked triangular solve with all their 3-column B_iᵀ as right-hand sides, BLAS-3
  // work instead of one forward substitution per object: what an event of many objects needs.
  std::vector<Gaussian3> positions(std::span<const std::string_view> objects) const;
  // A measurement alone, corrected by its view's offset: N(z − H_u β̂_u, μR + H_u Σ_uu H_uᵀ).
  Gaussian3 corrected(const Measurement& measurement, double noise_scale = 1.0) const;
  // The covariance of Σ_k W_k H_k (β_k − β̂_k): what the offsets' errors add to a weighted sum of
  // measurements of one object at one time, each corrected by its view's offset — e.g. one view's
  // disagreement with the others' mean (W = I for it, minus the others' weights). It is
  // ‖Σ_k Y_k H_kᵀ W_kᵀ‖² (Y_k = L⁻¹E_kᵀ), so the offset common to the views, which the combination
  // cancels, is not counted as the measurements' own offset covariances H Σ_kk Hᵀ would count it. A
  // view not yet seen adds W H Σ₀' Hᵀ Wᵀ (the scaled prior), independent of the rest. Zero for a zero prior. O(c) per
  // measurement.
  Matrix3d offsets_covariance(std::span<const Measurement* const> measurements, std::span<const Matrix3d> weights) const;
  // The estimated offset of `view` and its covariance (prior for an unknown view).
  OffsetVector offset(std::string_view view) const;
  OffsetMatrix offset_covariance(std::string_view view) const;
  std::size_t view_count() const { return views_.size(); }
  bool active() const { return !prior_.is_zero(); }

 private:
  // Object i: p_i = a_i + B_i β with a_i ~ N(mean, covariance) independent of β.
  struct ObjectState {
    Vector3d mean;
    Matrix3d covariance;
    Eigen::Matrix<double, 3, Eigen::Dynamic> offsets;  // B_i (3 × 6n)
    // For the M of version `spread_version` (0: not computed since B_i changed): W_i = L⁻¹ B_iᵀ
    // (c × 3) and B_i Σ_β B_iᵀ = W_iᵀ W_i.
    mutable Eigen::Matrix<double, Eigen::Dynamic, 3> whitened_offsets{};
    mutable Matrix3d offsets_spread = Matrix3d::Zero();
    mutable std::uint64_t spread_version = 0;
  };
  // A block of β and how its coordinates move a view's offset (t, δ, ε): by `basis` (7 × its size).
  struct OffsetBlock {
    Eigen::Index start;
    Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic> basis;
    // The basis with zero columns up to 6: a measurement's G on the block is then a fixed-size
    // product, H_u (3 × 6) times this, whose first basis.cols() columns are G.
    OffsetMatrix padded_basis;
    Eigen::Index size() const { return basis.cols(); }
  };
  // A view's offset is Σ basis β_block over its blocks: its own — only the directions in which the
  // prior has variance (a zero σ_z keeps t_z at exactly zero, so it costs nothing) — and the
  // translation jumps released since (only the directions of W's range).
  struct ViewBlocks {
    std::vector<OffsetBlock> blocks;
    // Y_u = L⁻¹ E_uᵀ (c × 6) for the M of version `whitened_version` (0: none): Σ_uu = Y_uᵀ Y_u,
    // and a measurement's C Σ_β Cᵀ = ‖W_i + Y_u H_uᵀ‖² in O(c).
    mutable Eigen::Matrix<double, Eigen::Dynamic, kOffsetSize> whitened_selector;
    mutable std::uint64_t whitened_version = 0;
    // Σ_k H_kᵀ R_k⁻¹ H_k over the view's measurements fused since M was last folded: their own terms
    // of M, added to the view's blocks at once (fold_pending_terms) instead of one block write each.
    mutable OffsetMatrix pending_information = OffsetMatrix::Zero();
    mutable bool has_pending_information = false;
  };
  const ViewBlocks* add_view(std::string_view view);  // none for a zero prior
  const ViewBlocks* view_blocks(std::string_view view) const;  // none when unknown
  // Appends an independent block for `covariance`'s nonzero directions (eigenvectors, as columns of
  // `directions` mapped by it), if any, whose prior is fixed (a release's).
  void add_block(ViewBlocks& view, const Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic>& directions,
                 const Eigen::MatrixXd& covariance);
  // Appends a view's own block: the coordinates of (t, δ, ε) with a nonzero prior variance in Σ₀ (which is
  // diagonal), each scaled by its group's κ.
  void add_own_block(ViewBlocks& view);
  // β grows by a block with these columns of `basis` and this prior information per coordinate.
  void append_block(ViewBlocks& view, const Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic>& basis,
                    const std::vector<double>& information, const std::vector<RegistrationPriorScale::Group>& groups);
  const ObjectState& object_state(std::string_view object) const;
  // C = B_i + H_u E_u: how a measurement of object i by view u (none: a view not in β) depends on β.
  Eigen::Matrix<double, 3, Eigen::Dynamic> measurement_offsets(const ObjectState& object, const ViewBlocks* view,
                                                               const OffsetJacobian& h) const;
  // E_u with view u's offset t_u + Σ jumps, δ_u = E_u β (6 × size of β).
  Eigen::MatrixXd offset_selector(const ViewBlocks& view) const;
  // The object's W_i and B_i Σ_β B_iᵀ, and the view's Y_u, made current (M factored).
  const ObjectState& whitened(const ObjectState& object) const;
  Gaussian3 marginal(const ObjectState& object) const;  // of p_i, as position()
  OffsetVector offset_mean(const ViewBlocks& view) const;  // as offset()
  const Eigen::Matrix<double, Eigen::Dynamic, kOffsetSize>& whitened_selector(const ViewBlocks& view) const;
  // Factors M and solves for β̂, if M changed since (folding in the pending rank-3 terms first).
  void refresh() const;
  // M += the views' pending own terms, and U₊U₊ᵀ − U₋U₋ᵀ over the pending columns; then none are pending.
  void fold_pending_terms() const;

  RegistrationPrior prior_;
  OffsetMatrix prior_covariance_;  // Σ₀, as calibrated
  RegistrationPriorScale prior_scale_;
  // Looked up by name for every measurement: hashed, and by string_view without a copy. Nothing
  // depends on their order.
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view name) const { return std::hash<std::string_view>{}(name); }
  };
  std::unordered_map<std::string, ObjectState, NameHash, std::equal_to<>> objects_;
  std::unordered_map<std::string, ViewBlocks, NameHash, std::equal_to<>> views_;
  // M (its lower triangle), less the pending terms of updates: M += U₊U₊ᵀ − U₋U₋ᵀ, with U₊ = Xᵀ for
  // one measurement, else U₊ = (L_P⁻¹ B)ᵀ and U₋ = (L_P'⁻¹ B')ᵀ (c × 3 each), kept as columns (c each,
  // column-major) and added when M is next factored or β grows, all at once: one pass over M per
  // pair of terms, or blocked rank updates for many. At most kMaxPendingColumns are kept.
  mutable Eigen::MatrixXd offsets_information_;
  mutable std::vector<double> pending_added_, pending_subtracted_;
  // update()'s work space: per measurement, its view, H_k and R_k⁻¹ (kept so as not to allocate).
  struct UpdateTerm {
    const ViewBlocks* view;
    OffsetJacobian jacobian;
    Matrix3d noise_inverse;
  };
  std::vector<UpdateTerm> update_terms_;
  // The combined innovation's work space: R_k⁻¹ then W_k, and U then V̄.
  mutable std::vector<Matrix3d> combined_weights_;
  mutable Eigen::Matrix<double, Eigen::Dynamic, 3> combined_selector_;
  Eigen::VectorXd offsets_information_vector_;  // m
  // Read through refresh(): the factor L of M (its lower triangle; dense_kernels.hpp) and β̂, for the
  // M they were made from.
  mutable Eigen::MatrixXd offsets_factor_;
  mutable Eigen::VectorXd offsets_mean_;
  std::uint64_t version_ = 1;                   // changes with M
  mutable std::uint64_t factored_version_ = 1;  // the M that the factor and β̂ were made from
};

}  // namespace stgf
