// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/joint_registration.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "stgf/core/cholesky3.hpp"
#include "stgf/core/dense_kernels.hpp"
#include "stgf/core/eigenvalue_floor.hpp"

namespace stgf {
using Matrix36 = OffsetJacobian;
using Matrix3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;

namespace {

// Which scale of the prior (registration_prior_scale.hpp) a coordinate of β_u = (t, δ, ε) takes: the
// horizontal translations' κ_t; δ's components along and across the rays κ_a and κ_c (κ_n unless other
// scenes' evidence sets them apart); ε, a geometric error of the sensor in relative terms, κ_n; and the
// vertical ones — t_z and δ's vertical component — κ_v of their own: a ground-plane camera's
// calibration error moves its points across the ground, not up, and the z disagreements, not the
// ground ones, say how large the vertical offsets are.
RegistrationPriorScale::Group offset_scale_group(int coordinate) {
  using Group = RegistrationPriorScale::Group;
  switch (coordinate) {
    case 0:
    case 1: return Group::kTranslation;
    case 2:
    case 5: return Group::kVertical;
    case 3: return Group::kAlong;
    case 4: return Group::kAcross;
    default: return Group::kNoiseRatio;  // ε
  }
}

using MatrixX3 = Eigen::Matrix<double, Eigen::Dynamic, 3>;
// A measurement's dependence on one offset block (at most 6 coordinates), on the stack.
using BlockColumns = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, kOffsetSize>;
// Two blocks' term of the offsets' information, and one block's of a vector, on the stack.
using OffsetInformationBlock = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kOffsetSize, kOffsetSize>;
using BlockVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kOffsetSize, 1>;

// A measurement's own term of the offsets' information, G_kᵀ W G_k and G_kᵀ W z_k, on its view's
// blocks only (G_k = H_u × each block's basis): add_block(row start, column start, block) for the block
// pairs of M's lower triangle, add_vector(row start, segment) for each block.
template <class Blocks, class AddBlock, class AddVector>
void add_own_terms(const Blocks& blocks, const Matrix36& h, const Matrix3d& weight, const Vector3d& z,
                   AddBlock&& add_block, AddVector&& add_vector) {
  // Fixed-size products on the padded bases (zero columns past a block's size): unrolled, and the
  // padding's rows and columns of each term are dropped.
  for (const auto& row : blocks) {
    const Matrix36 g_row = h * row.padded_basis;
    const Matrix36 weighted_row = weight * g_row;  // W G
    const OffsetVector vector = weighted_row.transpose() * z;
    add_vector(row.start, BlockVector(vector.head(row.size())));
    for (const auto& column : blocks) {
      if (column.start > row.start) continue;
      const OffsetMatrix block =
          weighted_row.transpose() * (column.start == row.start ? g_row : Matrix36(h * column.padded_basis));
      add_block(row.start, column.start, OffsetInformationBlock(block.topLeftCorner(row.size(), column.size())));
    }
  }
}

// Eigen's blocked kernels (rank update of M, triangular solve) from this many columns on — pending
// rank-3 terms, or 3 per object whose position is read; fewer (a small event) take the column kernels
// of dense_kernels.hpp, which cost less there.
constexpr Eigen::Index kBlockedColumns = 24;
// At most this many pending columns (128 objects' updates): memory 2 · 8 · c · 384 bytes.
constexpr std::size_t kMaxPendingColumns = 384;

}  // namespace

JointRegistration::JointRegistration(const RegistrationPrior& prior)
    : prior_(prior), prior_covariance_(prior.covariance()) {}

const JointRegistration::ViewBlocks* JointRegistration::view_blocks(std::string_view view) const {
  const auto found = views_.find(view);
  return found == views_.end() ? nullptr : &found->second;
}

void JointRegistration::add_block(ViewBlocks& view, const Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic>& directions,
                                  const Eigen::MatrixXd& covariance) {
  // covariance = U diag(λ) Uᵀ; the block holds the coordinates along the eigenvectors with λ > 0.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  const double floor = 1e-12 * std::max(values.cwiseAbs().maxCoeff(), 0.0);
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < values.size(); ++k) {
    if (values(k) > floor && values(k) > 0.0) kept.push_back(k);
  }
  Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic> basis(kOffsetSize, static_cast<Eigen::Index>(kept.size()));
  std::vector<double> information;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    basis.col(static_cast<Eigen::Index>(k)) = directions * eigen.eigenvectors().col(kept[k]);
    information.push_back(1.0 / values(kept[k]));
  }
  append_block(view, basis, information, std::vector(kept.size(), RegistrationPriorScale::Group::kFixed));
}

void JointRegistration::add_own_block(ViewBlocks& view) {
  Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic> basis(kOffsetSize, 0);
  std::vector<double> information;
  std::vector<RegistrationPriorScale::Group> groups;
  for (int j = 0; j < kOffsetSize; ++j) {
    const double variance = prior_covariance_(j, j);
    if (!(variance > 0.0)) continue;
    basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
    basis.rightCols<1>() = OffsetVector::Unit(j);
    information.push_back(1.0 / variance);
    groups.push_back(offset_scale_group(j));
  }
  append_block(view, basis, information, groups);
}

void JointRegistration::append_block(ViewBlocks& view, const Eigen::Matrix<double, kOffsetSize, Eigen::Dynamic>& basis,
                                     const std::vector<double>& information,
                                     const std::vector<RegistrationPriorScale::Group>& groups) {
  const Eigen::Index size = basis.cols();
  if (size == 0) return;
  fold_pending_terms();  // their columns have β's present size
  // Zero mean (m unchanged there), the given information along each coordinate, independent of the rest.
  const Eigen::Index start = offsets_information_vector_.size();
  offsets_information_vector_.conservativeResize(start + size);
  offsets_information_vector_.tail(size).setZero();
  offsets_information_.conservativeResize(start + size, start + size);
  offsets_information_.rightCols(size).setZero();
  offsets_information_.bottomRows(size).setZero();
  for (Eigen::Index k = 0; k < size; ++k) {
    const auto j = static_cast<std::size_t>(k);
    // A view's own coordinate has the prior κ λ: information 1/(κ λ) (registration_prior_scale.hpp).
    offsets_information_(start + k, start + k) = information[j] / prior_scale_.scale(groups[j]);
    prior_scale_.add_coordinate(information[j], groups[j]);
  }
  ++version_;
  for (auto& [name, object] : objects_) {
    object.offsets.conservativeResize(Eigen::NoChange, start + size);
    object.offsets.rightCols(size).setZero();  // no position depends on the new block
  }
  OffsetMatrix padded = OffsetMatrix::Zero();
  padded.leftCols(size) = basis;
  view.blocks.push_back({start, basis, padded});
}

const JointRegistration::ViewBlocks* JointRegistration::add_view(std::string_view view) {
  if (prior_.is_zero()) return nullptr;
  if (const ViewBlocks* known = view_blocks(view)) return known;
  ViewBlocks& blocks = views_.emplace(std::string(view), ViewBlocks{}).first->second;
  add_own_block(blocks);
  return &blocks;
}

Eigen::MatrixXd JointRegistration::offset_selector(const ViewBlocks& view) const {
  Eigen::MatrixXd selector = Eigen::MatrixXd::Zero(kOffsetSize, offsets_information_vector_.size());
  for (const OffsetBlock& block : view.blocks) selector.middleCols(block.start, block.basis.cols()) = block.basis;
  return selector;
}

const JointRegistration::ObjectState& JointRegistration::object_state(std::string_view object) const {
  const auto found = objects_.find(object);
  if (found == objects_.end()) throw std::logic_error("JointRegistration: unknown object");
  return found->second;
}

Matrix3X JointRegistration::measurement_offsets(const ObjectState& object, const ViewBlocks* view,
                                                const Matrix36& h) const {
  Matrix3X c = object.offsets;
  if (view == nullptr) return c;
  for (const OffsetBlock& block : view->blocks) c.middleCols(block.start, block.basis.cols()) += h * block.basis;
  return c;
}

void JointRegistration::add_object(const Measurement& first, double noise_scale) {
  if (has_object(first.object)) throw std::logic_error("JointRegistration::add_object: object already known");
  const ViewBlocks* view = add_view(first.view);
  const Matrix3d& r = first.position.covariance();
  // p = z − H_u β_u − e: a = z − e, B = −C with C of a position that does not depend on β.
  ObjectState object{first.position.mean(), noise_scale * r,
                     Matrix3X::Zero(3, offsets_information_vector_.size())};
  object.offsets = -measurement_offsets(object, view, offset_jacobian(first));
  objects_.emplace(first.object, std::move(object));
}

void JointRegistration::remove_object(std::string_view object) {
  const auto found = objects_.find(object);
  if (found != objects_.end()) objects_.erase(found);
}

void JointRegistration::predict(std::string_view object, const Vector3d& displacement, const Matrix3d& process_noise) {
  const auto found = objects_.find(object);
  if (found == objects_.end()) throw std::logic_error("JointRegistration::predict: unknown object");
  found->second.mean += displacement;
  // The motion may take variance away (a forecast more certain than the state: object_track.hpp); of P_i
  // at most half its least variance.
  found->second.covariance += grown_within(found->second.covariance, process_noise);
}

void JointRegistration::release_offset(std::string_view view, const Matrix3d& covariance) {
  const auto found = views_.find(view);
  if (found == views_.end()) return;
  Eigen::Matrix<double, kOffsetSize, 3> translation = Eigen::Matrix<double, kOffsetSize, 3>::Zero();
  translation.topRows<3>().setIdentity();
  add_block(found->second, translation, symmetrised(covariance));
}

JointRegistration::Innovation JointRegistration::innovation(const Measurement& measurement, double noise_scale) const {
  const ObjectState& object = object_state(measurement.object);
  const ViewBlocks* view = view_blocks(measurement.view);
  const Matrix3d& r = measurement.position.covariance();
  const Matrix36 h = offset_jacobian(measurement);
  // ν = z − p̂_i − H_u β̂_u = z − â_i − C β̂,  S = P_i + C Σ_β Cᵀ + μR (+ H_u Σ_prior H_uᵀ for a view not
  // yet seen), C = B_i + H_u E_u: C Σ_β Cᵀ = ‖L⁻¹Cᵀ‖², L⁻¹Cᵀ = W_i + Y_u H_uᵀ.
  refresh();
  const ObjectState& current = whitened(object);
  Innovation result{measurement.position.mean() - object.mean - object.offsets * offsets_mean_,
                    object.covariance + noise_scale * r};
  if (view != nullptr) {
    result.value -= h * offset_mean(*view);
    const Eigen::Matrix<double, Eigen::Dynamic, 3> whitened_rows =
        current.whitened_offsets + whitened_selector(*view).lazyProduct(h.transpose());
    result.covariance += gram<3>(whitened_rows);
  } else {
    result.covariance += current.offsets_spread;
    if (!prior_.is_zero()) result.covariance += h * prior_covariance() * h.transpose();
  }
  result.covariance = symmetrised(result.covariance);
  return result;
}

JointRegistration::Innovation JointRegistration::innovation(std::span<const Measurement* const> measurements,
                                                            std::span<const double> noise_scales) const {
  if (measurements.size() != noise_scales.size() || measurements.empty()) {
    throw std::invalid_argument("JointRegistration::innovation: one noise scale per measurement, at least one");
  }
  if (measurements.size() == 1) return innovation(*measurements.front(), noise_scales.front());
  const ObjectState& object = object_state(measurements.front()->object);
  std::vector<Matrix3d>& weights = combined_weights_;  // R_k⁻¹, then W_k
  weights.clear();
  Matrix3d information = Matrix3d::Zero();
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    if (measurements[k]->object != measurements.front()->object) throw std::logic_error("JointRegistration::innovation: measurements of several objects");
    const Cholesky3 noise_factor(noise_scales[k] * measurements[k]->position.covariance());
    if (!noise_factor.ok()) throw std::runtime_error("registration: a measurement's covariance is not positive definite");
    information += weights.emplace_back(noise_factor.inverse());
  }
  const Cholesky3 information_factor(information);
  if (!information_factor.ok()) throw std::runtime_error("registration: the measurements' total information is not positive definite");
  const Matrix3d combined_noise = symmetrised(information_factor.inverse());  // R̄
  refresh();
  const ObjectState& current = whitened(object);
  const Vector3d predicted = object.mean + object.offsets * offsets_mean_;
  Innovation result{Vector3d::Zero(), object.covariance + combined_noise};
  // V̄ = W_i + L⁻¹ U with U = Σ_k E_kᵀ H_kᵀ W_kᵀ (Σ_k W_k = I): each measurement's term on its view's
  // blocks, then one substitution from the first block any of them touches.
  Eigen::Matrix<double, Eigen::Dynamic, 3>& summed = combined_selector_;
  summed.setZero(offsets_mean_.size(), 3);
  Eigen::Index first = summed.rows();
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& measurement = *measurements[k];
    const Matrix3d weight = combined_noise * weights[k];  // W_k
    const Matrix36 h = offset_jacobian(measurement);
    Vector3d value = measurement.position.mean() - predicted;
    if (const ViewBlocks* view = view_blocks(measurement.view); view != nullptr) {
      value -= h * offset_mean(*view);
      const Eigen::Matrix<double, kOffsetSize, 3> term = h.transpose() * weight.transpose();
      for (const OffsetBlock& block : view->blocks) {
        summed.middleRows(block.start, block.size()).noalias() += block.basis.transpose() * term;
        first = std::min(first, block.start);
      }
    } else if (!prior_.is_zero()) {
      const Matrix36 moved = weight * h;
      result.covariance.noalias() += moved * prior_covariance() * moved.transpose();
    }
    result.value.noalias() += weight * value;
  }
  if (first < summed.rows()) forward_substitute(offsets_factor_, summed, first);
  summed += current.whitened_offsets;
  result.covariance += gram<3>(summed);
  result.covariance = symmetrised(result.covariance);
  return result;
}

void JointRegistration::update(const Measurement& measurement, double noise_scale) {
  const Measurement* one = &measurement;
  update(std::span(&one, 1), std::span(&noise_scale, 1));
}

void JointRegistration::update(std::span<const Measurement* const> measurements, std::span<const double> noise_scales) {
  if (measurements.size() != noise_scales.size()) throw std::invalid_argument("JointRegistration::update: one noise scale per measurement");
  if (measurements.empty()) return;
  const std::string& name = measurements.front()->object;
  for (const Measurement* measurement : measurements) {
    if (measurement->object != name) throw std::logic_error("JointRegistration::update: measurements of several objects");
  }
  const auto found = objects_.find(name);
  if (found == objects_.end()) throw std::logic_error("JointRegistration::update: unknown object");
  // Per measurement: its view (first, so that β has its final size before any term is formed), H_k
  // and R_k⁻¹; kept in members so that an update allocates nothing in the steady state.
  std::vector<UpdateTerm>& terms = update_terms_;
  terms.clear();
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Matrix3d& r = measurements[k]->position.covariance();
    const Cholesky3 noise_factor(noise_scales[k] * r);  // R_k
    if (!noise_factor.ok()) throw std::runtime_error("registration: a measurement's covariance is not positive definite");
    terms.push_back(UpdateTerm{add_view(measurements[k]->view), offset_jacobian(*measurements[k]), noise_factor.inverse()});
  }
  ObjectState& object = found->second;
  const Eigen::Index size = offsets_information_vector_.size();
  // What the measurements teach of β is added to M and m in one of two exact forms:
  //   one measurement: z = a_i + C β + e with C = B_i + G, a_i ~ N(â, P) independent of β, so
  //     M += Cᵀ S⁻¹ C,  m += Cᵀ S⁻¹ (z − â),  S = P + R:  one rank-3 term (X = L_S⁻¹ C; M += XᵀX);
  //   several: the conditional's terms before and after and each measurement's own term (header),
  //     two rank-3 terms however many measurements there are.
  const bool single = terms.size() == 1 && terms.front().view != nullptr && size > 0;
  const Cholesky3 prior_factor(object.covariance);
  if (!prior_factor.ok()) throw std::runtime_error("registration: a position's covariance is not positive definite");
  const Matrix3d prior_whitening = prior_factor.inverse_factor();  // F = L_P⁻¹
  const Matrix3d prior_information = prior_whitening.transpose() * prior_whitening;  // P⁻¹
  Matrix3d information = prior_information;           // then P'⁻¹
  Vector3d information_mean = information * object.mean;  // P⁻¹ â, then P'⁻¹ â'
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    information += terms[k].noise_inverse;
    information_mean.noalias() += terms[k].noise_inverse * measurements[k]->position.mean();
  }
  // a_i given β, all measurements at once (z_k − (B_i + G_k) β = a_i + e_k):
  //   P' = (P⁻¹ + Σ R_k⁻¹)⁻¹,  â' = P' (P⁻¹ â + Σ R_k⁻¹ z_k),  B' = P' P⁻¹ B − Σ_k P' R_k⁻¹ G_k,
  // the last since p_i = a_i + B β: B − P' Σ R_k⁻¹ (B + G_k) = P' (P'⁻¹ − Σ R_k⁻¹) B − … .
  const Cholesky3 posterior_factor(information);  // P'⁻¹ = L Lᵀ
  if (!posterior_factor.ok()) throw std::runtime_error("registration: a position's information is not positive definite");
  std::optional<Cholesky3> innovation_factor;  // one measurement's S = P + R = L_S L_Sᵀ
  if (single) {
    innovation_factor.emplace(object.covariance + noise_scales[0] * measurements[0]->position.covariance());
    if (!innovation_factor->ok()) throw std::runtime_error("registration: an innovation's covariance is not positive definite");
  }
  // Nothing throws from here on.
  Eigen::VectorXd& information_vector = offsets_information_vector_;
  const std::size_t pending_added = pending_added_.size(), pending_subtracted = pending_subtracted_.size();
  pending_added_.resize(pending_added + static_cast<std::size_t>(3 * size));
  Eigen::Map<MatrixX3> added(pending_added_.data() + pending_added, size, 3);
  Vector3d before_w = Vector3d::Zero();
  if (single) {
    // Xᵀ = Cᵀ L_S⁻ᵀ: B's columns, then each of the view's blocks' G = H × basis.
    const UpdateTerm& term = terms.front();
    const Matrix3d whitening = innovation_factor->inverse_factor();  // L_S⁻¹
    added.noalias() = (whitening.lazyProduct(object.offsets)).transpose();
    for (const OffsetBlock& block : term.view->blocks) {
      const Matrix36 g = whitening * (term.jacobian * block.padded_basis);
      added.middleRows(block.start, block.size()) += g.leftCols(block.size()).transpose();
    }
    information_vector.noalias() += added * (whitening * (measurements[0]->position.mean() - object.mean));
  } else {
    // Each view's own term: G_kᵀ R_k⁻¹ G_k and G_kᵀ R_k⁻¹ z_k with G_k = H_k × a block's basis: H_kᵀ R_k⁻¹ H_k
    // joins the view's pending sum (added to M's blocks of the view when M is next folded), and
    // the vector goes to m now.
    for (std::size_t k = 0; k < measurements.size(); ++k) {
      const UpdateTerm& term = terms[k];
      if (term.view == nullptr) continue;
      const Matrix36 weighted = term.noise_inverse * term.jacobian;  // R_k⁻¹ H_k
      term.view->pending_information.noalias() += term.jacobian.transpose() * weighted;
      term.view->has_pending_information = true;
      const OffsetVector vector = weighted.transpose() * measurements[k]->position.mean();
      for (const OffsetBlock& block : term.view->blocks) {
        information_vector.segment(block.start, block.size()).noalias() += block.basis.transpose() * vector;
      }
    }
    // Before: the conditional's term (F B)ᵀ (F B) and (F B)ᵀ F â.
    added.noalias() = (prior_whitening.lazyProduct(object.offsets)).transpose();
    before_w = prior_whitening * object.mean;
  }
  const Matrix3d covariance = symmetrised(posterior_factor.inverse());  // P'
  const Matrix3d carried = covariance * prior_information;             // P' P⁻¹
  for (Eigen::Index j = 0; j < object.offsets.cols(); ++j) object.offsets.col(j) = carried * object.offsets.col(j);
  for (const UpdateTerm& term : terms) {
    if (term.view == nullptr) continue;
    const Matrix3d gain = covariance * term.noise_inverse;  // P' R_k⁻¹
    for (const OffsetBlock& block : term.view->blocks) {
      const Matrix36 change = gain * (term.jacobian * block.padded_basis);
      object.offsets.middleCols(block.start, block.size()) -= change.leftCols(block.size());
    }
  }
  object.mean = covariance * information_mean;
  object.covariance = covariance;
  object.spread_version = 0;
  if (!single) {
    // After: P'⁻¹ = L Lᵀ, so F' = Lᵀ: the term (Lᵀ B')ᵀ (Lᵀ B') and (Lᵀ B')ᵀ Lᵀ â', subtracted.
    const Matrix3d posterior_whitening = posterior_factor.matrix_l().transpose();
    pending_subtracted_.resize(pending_subtracted + static_cast<std::size_t>(3 * size));
    Eigen::Map<MatrixX3> after(pending_subtracted_.data() + pending_subtracted, size, 3);
    after.noalias() = (posterior_whitening.lazyProduct(object.offsets)).transpose();
    information_vector.noalias() -= added * before_w;
    information_vector.noalias() += after * (posterior_whitening * object.mean);
  }
  ++version_;
  if (pending_added_.size() >= kMaxPendingColumns * static_cast<std::size_t>(information_vector.size())) {
    fold_pending_terms();
  }
}

void JointRegistration::fold_pending_terms() const {
  // The views' own terms: basis_bᵀ (Σ_k H_kᵀ R_k⁻¹ H_k) basis_b' on each pair of the view's blocks.
  for (const auto& [name, view] : views_) {
    if (!view.has_pending_information) continue;
    for (const OffsetBlock& row : view.blocks) {
      const Eigen::Matrix<double, Eigen::Dynamic, kOffsetSize, Eigen::ColMajor, kOffsetSize, kOffsetSize> weighted =
          row.basis.transpose() * view.pending_information;
      for (const OffsetBlock& column : view.blocks) {
        if (column.start > row.start) continue;  // the lower triangle
        offsets_information_.block(row.start, column.start, row.size(), column.size()).noalias() +=
            weighted * column.basis;
      }
    }
    view.pending_information.setZero();
    view.has_pending_information = false;
  }
  if (pending_added_.empty()) return;
  const Eigen::Index size = offsets_information_.rows();
  const auto added_columns = static_cast<Eigen::Index>(pending_added_.size()) / size;
  const auto subtracted_columns = static_cast<Eigen::Index>(pending_subtracted_.size()) / size;
  const Eigen::Map<const Eigen::MatrixXd> added(pending_added_.data(), size, added_columns);
  const Eigen::Map<const Eigen::MatrixXd> subtracted(pending_subtracted_.data(), size, subtracted_columns);
  if (added_columns < kBlockedColumns) {
    // Added and subtracted terms in pairs, one pass over M for both, then the added ones left, two
    // at a time.
    Eigen::Index first = 0;
    for (; first < subtracted_columns; first += 3) {
      add_rank3_difference(offsets_information_, added.middleCols<3>(first), subtracted.middleCols<3>(first));
    }
    for (; first + 3 < added_columns; first += 6) {
      add_rank3_sum(offsets_information_, added.middleCols<3>(first), added.middleCols<3>(first + 3));
    }
    for (; first < added_columns; first += 3) add_rank3(offsets_information_, added.middleCols<3>(first), 1.0);
  } else {
    offsets_information_.selfadjointView<Eigen::Lower>().rankUpdate(added, 1.0);
    if (subtracted_columns > 0) offsets_information_.selfadjointView<Eigen::Lower>().rankUpdate(subtracted, -1.0);
  }
  pending_added_.clear();
  pending_subtracted_.clear();
}

void JointRegistration::observe_differences(std::span<const Measurement* const> measurements,
                                            std::span<const double> noise_scales,
                                            std::span<const Matrix3d> alignment_covariances) {
  if (measurements.size() != noise_scales.size()) throw std::invalid_argument("JointRegistration::observe_differences: one noise scale per measurement");
  if (!alignment_covariances.empty() && alignment_covariances.size() != measurements.size()) {
    throw std::invalid_argument("JointRegistration::observe_differences: one alignment covariance per measurement, or none");
  }
  if (prior_.is_zero() || measurements.size() < 2 || prior_scale_.has_enough_evidence()) return;
  // A_j = Σ_k G_kᵀ W_k G_k − Fᵀ S⁻¹ F and b_j = Σ_k G_kᵀ W_k z_k − Fᵀ S⁻¹ y (registration_prior_scale.hpp),
  // block by block: G_k is nonzero on its view's blocks only, which are contiguous in β and disjoint
  // across views; Fᵀ S⁻¹ F = XᵀX with X = L_S⁻¹ F. F = Σ_k W_k G_k is summed per block first, so
  // that a view with several measurements (a frame on its own clock) adds one segment, not one each:
  // the products XᵀX cost the square of the segments' number.
  struct Segment {
    Eigen::Index start;
    BlockColumns weighted;  // Σ_k W_k G_k on this block, then X on it
  };
  std::vector<Segment> segments;
  segments.reserve(measurements.size());
  struct Term {
    const ViewBlocks* view;
    Matrix36 h;
    Matrix3d weight;     // W_k
    Vector3d corrected;  // c_k = z_k − G_k β̂
  };
  std::vector<Term> terms(measurements.size());
  Matrix3d s = Matrix3d::Zero();
  Vector3d y = Vector3d::Zero(), corrected_sum = Vector3d::Zero();
  // β̂ as last factored (before this event's updates; coordinates added since count as zero): only
  // for the robustness weight below.
  const Eigen::VectorXd& estimate = offsets_mean_;
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& measurement = *measurements[k];
    const ViewBlocks* view = view_blocks(measurement.view);
    if (view == nullptr) throw std::logic_error("JointRegistration::observe_differences: a view not yet in β");
    Matrix3d noise = noise_scales[k] * measurement.position.covariance();
    if (!alignment_covariances.empty()) noise += alignment_covariances[k];
    const Cholesky3 noise_factor(noise);
    if (!noise_factor.ok()) throw std::runtime_error("registration: a measurement's covariance is not positive definite");
    const Vector3d& z = measurement.position.mean();
    Term& term = terms[k];
    term = Term{view, Matrix36::Zero(), noise_factor.inverse(), z};  // h: below, once S⁻¹ y is known
    s += term.weight;
    y.noalias() += term.weight * z;
  }
  // ε's column from the measurements' weighted mean S⁻¹ y, common to them all (offset_jacobian): from
  // each measurement itself, one ε for every view with t_u = ε s_u would shrink every difference by
  // (1 − ε) and the views' noise pass for offsets (on ETH/UCY the per-scene κ̂ ran to 2¹⁰: design §1.7).
  const bool range_scales = prior_.range_scale_sigma > 0.0;
  const Vector3d common_position = range_scales ? Vector3d(s.llt().solve(y)) : Vector3d::Zero();
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& measurement = *measurements[k];
    const ViewBlocks* view = terms[k].view;
    Term& term = terms[k];
    term.h = range_scales ? offset_jacobian(measurement, common_position) : offset_jacobian(measurement);
    for (const OffsetBlock& block : view->blocks) {
      const BlockColumns g = term.h * block.basis;
      const auto same = std::find_if(segments.begin(), segments.end(),
                                     [&](const Segment& segment) { return segment.start == block.start; });
      if (same == segments.end()) {
        segments.push_back(Segment{block.start, term.weight * g});
      } else {
        same->weighted.noalias() += term.weight * g;
      }
      if (block.start + g.cols() <= estimate.size()) term.corrected.noalias() -= g * estimate.segment(block.start, g.cols());
    }
    corrected_sum.noalias() += term.weight * term.corrected;
  }
  const Cholesky3 s_factor(s);
  if (!s_factor.ok()) throw std::runtime_error("registration: the measurements' total information is not positive definite");
  // Robustness: q = Σ_k (c_k − c̄)ᵀ W_k (c_k − c̄), the disagreement left once the offsets as known
  // are taken out, is about 3(k − 1) when the model holds. A time whose q is more than
  // kDisagreementTolerance times that (a gross outlier, a view whose R is far too small, an offset
  // that has just jumped) counts with the weight ω = tolerance · 3(k − 1) / q, which bounds its pull
  // on κ; one far off with bias from every view alike (offsets larger than the prior) still counts.
  const Vector3d mean = s_factor.inverse() * corrected_sum;
  double disagreement = 0.0;
  for (const Term& term : terms) {
    const Vector3d residual = term.corrected - mean;
    disagreement += residual.dot(term.weight * residual);
  }
  const double dimensions = 3.0 * static_cast<double>(measurements.size() - 1);
  const double limit = RegistrationPriorScale::kDisagreementTolerance * dimensions;
  const double omega = disagreement > limit ? limit / disagreement : 1.0;
  const Matrix3d whitening = s_factor.inverse_factor();  // L_S⁻¹
  const Vector3d w = whitening * y;
  // Σ_k G_kᵀ W_k G_k and Σ_k G_kᵀ W_k z_k, each measurement on its own view's blocks, as in update().
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    add_own_terms(
        terms[k].view->blocks, terms[k].h, terms[k].weight, measurements[k]->position.mean(),
        [this, omega](Eigen::Index row, Eigen::Index column, const OffsetInformationBlock& block) {
          const OffsetInformationBlock weighted = omega * block;
          prior_scale_.add_information(row, column, weighted);
        },
        [this, omega](Eigen::Index row, const BlockVector& segment) {
          const BlockVector weighted = omega * segment;
          prior_scale_.add_vector(row, weighted);
        });
  }
  for (Segment& segment : segments) {
    segment.weighted = whitening * segment.weighted;  // X on this block
    const BlockVector product = -omega * (segment.weighted.transpose() * w);
    prior_scale_.add_vector(segment.start, product);
  }
  for (const Segment& a : segments) {
    for (const Segment& b : segments) {
      if (a.start < b.start) continue;
      const OffsetInformationBlock product = -omega * (a.weighted.transpose() * b.weighted);
      prior_scale_.add_information(a.start, b.start, product);
    }
  }
  prior_scale_.add_dimensions(omega * dimensions);
}

bool JointRegistration::adapt_prior_scale() {
  using Group = RegistrationPriorScale::Group;
  const RegistrationPriorScales before = prior_scale_.scales();
  if (!prior_scale_.update()) return false;
  // M = Λ₀/κ + the data's information: only the prior term changes.
  const RegistrationPriorScales after = prior_scale_.scales();
  for (std::size_t j = 0; j < prior_scale_.coordinates(); ++j) {
    const Group group = prior_scale_.group(j);
    if (group == Group::kFixed) continue;
    const auto index = static_cast<Eigen::Index>(j);
    const double change = 1.0 / scale_of(after, group) - 1.0 / scale_of(before, group);
    offsets_information_(index, index) += change * prior_scale_.prior_information(j);
  }
  ++version_;
  return true;
}

OffsetMatrix JointRegistration::prior_covariance() const {
  OffsetMatrix covariance = prior_covariance_;
  for (int j = 0; j < kOffsetSize; ++j) covariance.row(j) *= prior_scale_.scale(offset_scale_group(j));
  return covariance;  // diagonal
}

void JointRegistration::refresh() const {
  if (factored_version_ == version_) return;
  factored_version_ = version_;
  fold_pending_terms();
  if (offsets_information_vector_.size() == 0) {
    offsets_mean_.resize(0);
    return;
  }
  offsets_factor_ = offsets_information_;
  if (!factor_lower(offsets_factor_)) {
    throw std::runtime_error("registration: the offsets' information is not positive definite");
  }
  offsets_mean_ = offsets_information_vector_;
  solve_factored(offsets_factor_, offsets_mean_);
}

const JointRegistration::ObjectState& JointRegistration::whitened(const ObjectState& object) const {
  refresh();
  if (object.spread_version == version_) return object;
  object.spread_version = version_;
  object.whitened_offsets = object.offsets.transpose();
  if (object.whitened_offsets.rows() > 0) forward_substitute(offsets_factor_, object.whitened_offsets);
  object.offsets_spread = gram<3>(object.whitened_offsets);
  return object;
}

const Eigen::Matrix<double, Eigen::Dynamic, kOffsetSize>& JointRegistration::whitened_selector(const ViewBlocks& view) const {
  refresh();
  if (view.whitened_version != version_) {
    view.whitened_version = version_;
    view.whitened_selector = offset_selector(view).transpose();
    // E_uᵀ is zero above the view's first block (its own; released ones come later in β).
    Eigen::Index first = view.whitened_selector.rows();
    for (const OffsetBlock& block : view.blocks) first = std::min(first, block.start);
    if (view.whitened_selector.rows() > 0) forward_substitute(offsets_factor_, view.whitened_selector, first);
  }
  return view.whitened_selector;
}

Matrix3d JointRegistration::offsets_covariance(std::span<const Measurement* const> measurements,
                                               std::span<const Matrix3d> weights) const {
  if (measurements.size() != weights.size()) throw std::invalid_argument("offsets_covariance: one weight per measurement");
  Matrix3d covariance = Matrix3d::Zero();
  if (prior_.is_zero()) return covariance;
  refresh();
  Eigen::Matrix<double, Eigen::Dynamic, 3> whitened = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(offsets_mean_.size(), 3);
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Matrix36 weighted = weights[k] * offset_jacobian(*measurements[k]);
    if (const ViewBlocks* view = view_blocks(measurements[k]->view); view != nullptr) {
      whitened.noalias() += whitened_selector(*view) * weighted.transpose();
    } else {
      covariance.noalias() += weighted * prior_covariance() * weighted.transpose();
    }
  }
  covariance += gram<3>(whitened);
  return symmetrised(covariance);
}

Gaussian3 JointRegistration::corrected(const Measurement& measurement, double noise_scale) const {
  const Matrix3d& r = measurement.position.covariance();
  if (prior_.is_zero() && noise_scale == 1.0) return measurement.position;
  if (prior_.is_zero()) return Gaussian3::from_covariance(measurement.position.mean(), noise_scale * r);
  const Matrix36 h = offset_jacobian(measurement);
  return Gaussian3::from_covariance(measurement.position.mean() - h * offset(measurement.view),
                                    noise_scale * r + h * offset_covariance(measurement.view) * h.transpose());
}

Gaussian3 JointRegistration::marginal(const ObjectState& object) const {
  // p_i = a_i + B_i β: mean â_i + B_i β̂, covariance P_i + B_i Σ_β B_iᵀ.
  const ObjectState& current = whitened(object);
  return Gaussian3::from_covariance(current.mean + current.offsets * offsets_mean_,
                                    symmetrised(current.covariance + current.offsets_spread));
}

Gaussian3 JointRegistration::position(std::string_view object) const { return marginal(object_state(object)); }

std::vector<Gaussian3> JointRegistration::positions(std::span<const std::string_view> objects) const {
  refresh();
  // The objects whose spread is stale, each once: B_iᵀ side by side, whitened by one solve with L.
  std::vector<const ObjectState*> states, stale;
  states.reserve(objects.size());
  for (const std::string_view name : objects) {
    const ObjectState& state = *states.emplace_back(&object_state(name));
    if (state.spread_version != version_) stale.push_back(&state);
  }
  const Eigen::Index size = offsets_information_vector_.size();
  if (size > 0 && static_cast<Eigen::Index>(3 * stale.size()) >= kBlockedColumns) {
    Eigen::MatrixXd whitened(size, static_cast<Eigen::Index>(3 * stale.size()));
    for (std::size_t s = 0; s < stale.size(); ++s) {
      whitened.middleCols<3>(static_cast<Eigen::Index>(3 * s)) = stale[s]->offsets.transpose();
    }
    offsets_factor_.triangularView<Eigen::Lower>().solveInPlace(whitened);  // L⁻¹ Bᵀ
    for (std::size_t s = 0; s < stale.size(); ++s) {
      stale[s]->whitened_offsets = whitened.middleCols<3>(static_cast<Eigen::Index>(3 * s));
      stale[s]->offsets_spread = gram<3>(stale[s]->whitened_offsets);
      stale[s]->spread_version = version_;
    }
  } else if (size > 0) {
    // Fewer: two objects per pass down L (each column is substituted exactly as alone).
    Eigen::Matrix<double, Eigen::Dynamic, 6> pair(size, 6);
    for (std::size_t s = 0; s + 1 < stale.size(); s += 2) {
      pair.leftCols<3>() = stale[s]->offsets.transpose();
      pair.rightCols<3>() = stale[s + 1]->offsets.transpose();
      forward_substitute(offsets_factor_, pair);
      for (std::size_t t = 0; t < 2; ++t) {
        const ObjectState& state = *stale[s + t];
        state.whitened_offsets = pair.middleCols<3>(static_cast<Eigen::Index>(3 * t));
        state.offsets_spread = gram<3>(state.whitened_offsets);
        state.spread_version = version_;
      }
    }
  }
  std::vector<Gaussian3> result;
  result.reserve(objects.size());
  for (const ObjectState* state : states) result.push_back(marginal(*state));  // whitens what is left
  return result;
}

OffsetVector JointRegistration::offset(std::string_view view) const {
  const ViewBlocks* blocks = view_blocks(view);
  return blocks == nullptr ? OffsetVector::Zero() : offset_mean(*blocks);
}

OffsetVector JointRegistration::offset_mean(const ViewBlocks& view) const {
  refresh();
  OffsetVector result = OffsetVector::Zero();
  for (const OffsetBlock& block : view.blocks) {
    result.noalias() += block.basis * offsets_mean_.segment(block.start, block.basis.cols());
  }
  return result;
}

OffsetMatrix JointRegistration::offset_covariance(std::string_view view) const {
  const ViewBlocks* blocks = view_blocks(view);
  if (blocks == nullptr) return prior_covariance();
  refresh();
  if (offsets_information_vector_.size() == 0) return OffsetMatrix::Zero();
  const Eigen::Matrix<double, Eigen::Dynamic, kOffsetSize>& whitened = whitened_selector(*blocks);  // Y_u
  return gram<kOffsetSize>(whitened);
}

}  // namespace stgf
