// SPDX-License-Identifier: Apache-2.0
#pragma once
// Dense kernels for the joint registration's offsets (joint_registration.hpp): a symmetric positive
// definite M of order c — up to seven per view, so tens to a few hundred — kept as its lower triangle, its
// Cholesky factor M = L Lᵀ, and triangular solves and rank-3 updates with a few right-hand sides.
// At these sizes Eigen's blocked kernels spend more on packing than on arithmetic; these are written
// column by column instead (measured: the factor of c = 35 in 1.8 µs against Eigen's LLT's 3.7 µs),
// and hand over to Eigen's blocked kernels where those win.
//
//   factor       left-looking: for j = 0 … c−1, column j below the diagonal is
//                  l_{j:,j} = (a_{j:,j} − L_{j:,0:j} L_{j,0:j}ᵀ) / l_jj,   l_jj = √(a_jj − ‖L_{j,0:j}‖²)
//                one matrix-vector product per column, which reads L by contiguous columns.
//   substitute   X ← L⁻¹ X by columns of L: x_j /= l_jj, then x_{j+1:} −= l_{j+1:,j} x_j.
//   rank-3       the lower triangle of M gets s · U Uᵀ for a c × 3 matrix U (s = ±1), A Aᵀ − B Bᵀ or
//                A Aᵀ + B Bᵀ, one pass over M.
//   Gram         WᵀW for a c × N matrix W (N = 3, 6): one dot product per distinct entry (Eigen's
//                product of a dynamic N × c by c × N matrix packs both for its blocked kernel first,
//                which took longer).

#include <Eigen/Dense>

namespace stgf {

// From this order on, factor_lower hands over to Eigen's blocked LLT (at 200 both take the same time).
inline constexpr Eigen::Index kBlockedFactorOrder = 192;

// Replaces the lower triangle of `a` (symmetric, only the lower triangle read) by L with L Lᵀ = a; the
// strict upper triangle is left as it was. Returns false when `a` is not positive definite.
inline bool factor_lower(Eigen::MatrixXd& a) {
  const Eigen::Index size = a.rows();
  if (size >= kBlockedFactorOrder) {
    const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> factor(a);  // in place
    // Eigen's check passes NaN; a NaN anywhere in the lower triangle reaches a later diagonal.
    return factor.info() == Eigen::Success && a.diagonal().array().isFinite().all();
  }
  for (Eigen::Index j = 0; j < size; ++j) {
    const Eigen::Index rest = size - j;
    if (j > 0) a.col(j).tail(rest).noalias() -= a.block(j, 0, rest, j) * a.row(j).head(j).transpose();
    const double pivot = a(j, j);
    if (!(pivot > 0.0)) return false;  // also NaN
    const double diagonal = std::sqrt(pivot);
    a(j, j) = diagonal;
    a.col(j).tail(rest - 1) /= diagonal;
  }
  return true;
}

// X ← L⁻¹ X for the lower triangle L of `factor` (forward substitution by columns of L), the
// right-hand sides side by side in one pass down each column of L. X's rows above `first_nonzero`
// are zero, and stay so: the substitution starts there (a view's selector, nonzero on its blocks only).
template <int Columns>
void forward_substitute(const Eigen::MatrixXd& factor, Eigen::Matrix<double, Eigen::Dynamic, Columns>& x,
                        Eigen::Index first_nonzero = 0) {
  static_assert(Columns > 0, "a fixed number of right-hand sides");
  const Eigen::Index size = factor.rows();
  double* columns[Columns];
  for (int k = 0; k < Columns; ++k) columns[k] = x.col(k).data();
  for (Eigen::Index j = first_nonzero; j < size; ++j) {
    const double* __restrict l = factor.col(j).data();
    // One contiguous update per right-hand side: X's columns and L do not overlap, which the compiler
    // is told, so that it vectorises over i (each element's arithmetic is the same as element by element).
    for (int k = 0; k < Columns; ++k) {
      double* __restrict column = columns[k];
      const double solved = column[j] /= l[j];
      for (Eigen::Index i = j + 1; i < size; ++i) column[i] -= l[i] * solved;
    }
  }
}

// x ← M⁻¹ x = L⁻ᵀ L⁻¹ x for the lower triangle L of `factor`.
// Forward substitution, then back substitution with Lᵀ by dot products with the columns of L.
inline void solve_factored(const Eigen::MatrixXd& factor, Eigen::VectorXd& x) {
  forward_substitute(factor, x);
  for (Eigen::Index j = factor.rows() - 1; j >= 0; --j) {
    const Eigen::Index below = factor.rows() - j - 1;
    x(j) = (x(j) - factor.col(j).tail(below).dot(x.tail(below))) / factor(j, j);
  }
}

namespace detail {
// Column j of the lower triangle gets Σ_t sign_t u_t u_tᵀ for the columns u_t of `terms` (at most 6).
template <int Terms>
void add_rank_terms(Eigen::MatrixXd& lower, const double* const (&terms)[Terms], const double (&signs)[Terms]) {
  const Eigen::Index size = lower.rows();
  for (Eigen::Index j = 0; j < size; ++j) {
    // M's column and the terms do not overlap (the compiler is told, so that it vectorises over i).
    double* __restrict column = lower.col(j).data();
    double scales[Terms];
    for (int t = 0; t < Terms; ++t) scales[t] = signs[t] * terms[t][j];
    for (Eigen::Index i = j; i < size; ++i) {
      double sum = 0.0;
      for (int t = 0; t < Terms; ++t) sum += terms[t][i] * scales[t];
      column[i] += sum;
    }
  }
}
}  // namespace detail

// The lower triangle of M gets A Aᵀ − B Bᵀ (A, B: c × 3, contiguous columns), in one pass.
template <class Added, class Subtracted>
void add_rank3_difference(Eigen::MatrixXd& lower, const Added& a, const Subtracted& b) {
  const double* const terms[6] = {a.col(0).data(), a.col(1).data(), a.col(2).data(),
                                  b.col(0).data(), b.col(1).data(), b.col(2).data()};
  detail::add_rank_terms<6>(lower, terms, {1.0, 1.0, 1.0, -1.0, -1.0, -1.0});
}

// The lower triangle of M gets A Aᵀ + B Bᵀ (A, B: c × 3, contiguous columns), in one pass.
template <class First, class Second>
void add_rank3_sum(Eigen::MatrixXd& lower, const First& a, const Second& b) {
  const double* const terms[6] = {a.col(0).data(), a.col(1).data(), a.col(2).data(),
                                  b.col(0).data(), b.col(1).data(), b.col(2).data()};
  detail::add_rank_terms<6>(lower, terms, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0});
}

// WᵀW for W with N columns (symmetric: each distinct entry one dot product).
template <int N, class Columns>
Eigen::Matrix<double, N, N> gram(const Columns& w) {
  Eigen::Matrix<double, N, N> result;
  for (int a = 0; a < N; ++a) {
    for (int b = 0; b <= a; ++b) result(a, b) = result(b, a) = w.col(a).dot(w.col(b));
  }
  return result;
}

// The lower triangle of M gets sign · U Uᵀ (U: c × 3, contiguous columns).
template <class Columns>
void add_rank3(Eigen::MatrixXd& lower, const Columns& u, double sign) {
  const double* const terms[3] = {u.col(0).data(), u.col(1).data(), u.col(2).data()};
  detail::add_rank_terms<3>(lower, terms, {sign, sign, sign});
}

}  // namespace stgf
