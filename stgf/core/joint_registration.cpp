// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/joint_registration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace stgf {
using Matrix36 = Eigen::Matrix<double, 3, 6>;
using Matrix3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;

namespace {

using MatrixX3 = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// Σ Mᵀ for a 3-row M (= (M Σ)ᵀ, Σ symmetric): three matrix-vector products down Σ's columns.
MatrixX3 sigma_times_transposed(const Eigen::MatrixXd& sigma, const Matrix3X& m) {
  MatrixX3 result(sigma.rows(), 3);
  for (int k = 0; k < 3; ++k) result.col(k).noalias() = sigma * m.row(k).transpose();
  return result;
}

// M Σ Mᵀ for a 3-row M.
Matrix3d quadratic_form(const Matrix3X& m, const Eigen::MatrixXd& sigma) {
  return m.lazyProduct(sigma_times_transposed(sigma, m));
}

}  // namespace

JointRegistration::JointRegistration(const RegistrationPrior& prior)
    : prior_(prior), prior_covariance_(prior.covariance()) {}

const JointRegistration::ViewBlocks* JointRegistration::view_blocks(std::string_view view) const {
  const auto found = views_.find(view);
  return found == views_.end() ? nullptr : &found->second;
}

void JointRegistration::add_block(ViewBlocks& view, const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions,
                                  const Eigen::MatrixXd& covariance) {
  // covariance = U diag(λ) Uᵀ; the block holds the coordinates along the eigenvectors with λ > 0.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  const double floor = 1e-12 * std::max(values.cwiseAbs().maxCoeff(), 0.0);
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < values.size(); ++k) {
    if (values(k) > floor && values(k) > 0.0) kept.push_back(k);
  }
  const auto size = static_cast<Eigen::Index>(kept.size());
  if (size == 0) return;
  Eigen::Matrix<double, 6, Eigen::Dynamic> basis(6, size);
  const Eigen::Index start = offsets_mean_.size();
  offsets_mean_.conservativeResize(start + size);
  offsets_mean_.tail(size).setZero();
  offsets_covariance_.conservativeResize(start + size, start + size);
  offsets_covariance_.rightCols(size).setZero();
  offsets_covariance_.bottomRows(size).setZero();
  for (Eigen::Index k = 0; k < size; ++k) {
    basis.col(k) = directions * eigen.eigenvectors().col(kept[k]);
    offsets_covariance_(start + k, start + k) = values(kept[k]);
  }
  for (auto& [name, object] : objects_) {
    object.offsets.conservativeResize(Eigen::NoChange, start + size);
    object.offsets.rightCols(size).setZero();  // no position depends on the new block
  }
  view.blocks.push_back({start, std::move(basis)});
}

const JointRegistration::ViewBlocks* JointRegistration::add_view(std::string_view view) {
  if (prior_.is_zero()) return nullptr;
  if (const ViewBlocks* known = view_blocks(view)) return known;
  ViewBlocks& blocks = views_.emplace(std::string(view), ViewBlocks{}).first->second;
  add_block(blocks, Eigen::Matrix<double, 6, 6>::Identity(), prior_covariance_);
  return &blocks;
}

Eigen::MatrixXd JointRegistration::offset_selector(const ViewBlocks& view) const {
  Eigen::MatrixXd selector = Eigen::MatrixXd::Zero(6, offsets_mean_.size());
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
                     Matrix3X::Zero(3, offsets_mean_.size())};
  object.offsets = -measurement_offsets(object, view, offset_jacobian(r));
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
  found->second.covariance += process_noise;
}

void JointRegistration::release_offset(std::string_view view, const Matrix3d& covariance) {
  const auto found = views_.find(view);
  if (found == views_.end()) return;
  Eigen::Matrix<double, 6, 3> translation = Eigen::Matrix<double, 6, 3>::Zero();
  translation.topRows<3>().setIdentity();
  add_block(found->second, translation, symmetrised(covariance));
}

JointRegistration::Innovation JointRegistration::innovation(const Measurement& measurement, double noise_scale) const {
  const ObjectState& object = object_state(measurement.object);
  const ViewBlocks* view = view_blocks(measurement.view);
  const Matrix3d& r = measurement.position.covariance();
  const Matrix36 h = offset_jacobian(r);
  // ν = z − p̂_i − H_u β̂_u = z − â_i − C β̂,  S = P_i + C Σ_β Cᵀ + μR (+ H_u Σ_prior H_uᵀ for a view not yet seen).
  const Matrix3X c = measurement_offsets(object, view, h);
  Innovation result{measurement.position.mean() - object.mean - c * offsets_mean_,
                    object.covariance + quadratic_form(c, offsets_covariance_) + noise_scale * r};
  if (view == nullptr && !prior_.is_zero()) result.covariance += h * prior_covariance_ * h.transpose();
  result.covariance = symmetrised(result.covariance);
  return result;
}

void JointRegistration::update(const Measurement& measurement, double noise_scale) {
  if (!has_object(measurement.object)) throw std::logic_error("JointRegistration::update: unknown object");
  const ViewBlocks* view = add_view(measurement.view);
  ObjectState& object = objects_.find(measurement.object)->second;
  const Matrix3d& r = measurement.position.covariance();
  const Vector3d& z = measurement.position.mean();
  const Matrix3X c = measurement_offsets(object, view, offset_jacobian(r));
  const Matrix3d t = symmetrised(object.covariance + noise_scale * r);  // T = P_i + μR
  // The offsets: z − â_i = C β + (a_i − â_i + e), noise T. With S = C Σ_β Cᵀ + T = L Lᵀ and
  // V = L⁻¹ C Σ_β: β̂ += Vᵀ L⁻¹ ν and Σ_β −= Vᵀ V (its lower triangle, mirrored: symmetric exactly).
  const MatrixX3 sigma_c = sigma_times_transposed(offsets_covariance_, c);  // Σ_β Cᵀ
  const Eigen::LLT<Matrix3d> s_factor(symmetrised(c.lazyProduct(sigma_c) + t));
  if (s_factor.info() != Eigen::Success) {
    throw std::runtime_error("registration: innovation covariance not positive definite");
  }
  Vector3d whitened = z - object.mean - c * offsets_mean_;  // ν, then L⁻¹ ν
  s_factor.matrixL().solveInPlace(whitened);
  Matrix3X v = sigma_c.transpose();
  s_factor.matrixL().solveInPlace(v);
  offsets_mean_.noalias() += v.transpose() * whitened;
  offsets_covariance_.selfadjointView<Eigen::Lower>().rankUpdate(v.transpose(), -1.0);
  offsets_covariance_.triangularView<Eigen::StrictlyUpper>() = offsets_covariance_.transpose();
  // The object's own part, given β: z − C β = a_i + e.
  const Eigen::LLT<Matrix3d> t_factor(t);
  if (t_factor.info() != Eigen::Success) throw std::runtime_error("registration: P + R not positive definite");
  const Matrix3d gain = t_factor.solve(object.covariance).transpose();  // P_i T⁻¹ (P_i, T symmetric)
  object.mean += gain * (z - object.mean);
  object.offsets -= gain.lazyProduct(c);
  object.covariance = symmetrised(object.covariance - gain * object.covariance);
}

Gaussian3 JointRegistration::corrected(const Measurement& measurement, double noise_scale) const {
  const Matrix3d& r = measurement.position.covariance();
  if (prior_.is_zero() && noise_scale == 1.0) return measurement.position;
  if (prior_.is_zero()) return Gaussian3::from_covariance(measurement.position.mean(), noise_scale * r);
  const Matrix36 h = offset_jacobian(r);
  return Gaussian3::from_covariance(measurement.position.mean() - h * offset(measurement.view),
                                    noise_scale * r + h * offset_covariance(measurement.view) * h.transpose());
}

Gaussian3 JointRegistration::position(std::string_view object) const {
  const ObjectState& state = object_state(object);
  // p_i = a_i + B_i β: mean â_i + B_i β̂, covariance P_i + B_i Σ_β B_iᵀ.
  return Gaussian3::from_covariance(state.mean + state.offsets * offsets_mean_,
                                    symmetrised(state.covariance + quadratic_form(state.offsets, offsets_covariance_)));
}

Eigen::Matrix<double, 6, 1> JointRegistration::offset(std::string_view view) const {
  const ViewBlocks* blocks = view_blocks(view);
  Eigen::Matrix<double, 6, 1> result = Eigen::Matrix<double, 6, 1>::Zero();
  if (blocks == nullptr) return result;
  for (const OffsetBlock& block : blocks->blocks) {
    result.noalias() += block.basis * offsets_mean_.segment(block.start, block.basis.cols());
  }
  return result;
}

Eigen::Matrix<double, 6, 6> JointRegistration::offset_covariance(std::string_view view) const {
  const ViewBlocks* blocks = view_blocks(view);
  if (blocks == nullptr) return prior_covariance_;
  if (blocks->blocks.size() == 1) {
    const OffsetBlock& block = blocks->blocks.front();
    const Eigen::Index size = block.basis.cols();
    return block.basis * offsets_covariance_.block(block.start, block.start, size, size) * block.basis.transpose();
  }
  const Eigen::MatrixXd selector = offset_selector(*blocks);
  return selector * offsets_covariance_ * selector.transpose();
}

}  // namespace stgf
