// SPDX-License-Identifier: Apache-2.0
#pragma once
// Does an estimate's stated variance follow its error across its whole range (DESIGN §4)? NEES checks
// the mean: a covariance too large where it is large and too small where it is small can meet it. Per
// world axis a, the rows are binned by their stated variance P̂_aa in octaves (bin k holds
// 2^k ≤ P̂_aa < 2^(k+1) m²) and each bin keeps the mean of P̂_aa and of the squared error
// r_a² = (x̂_a − y_a)²; where the covariance means what it says, r_a² / P̂_aa is 1 in every bin.
// A ratio that rises toward the smallest variances is an error floor the estimate does not know of
// (design.md §1.2).

#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

struct VarianceBin {
  int octave = 0;  // k: 2^k ≤ P̂_aa < 2^(k+1) m²
  std::size_t rows = 0;
  double mean_variance = 0.0;       // of P̂_aa
  double mean_squared_error = 0.0;  // of r_a²

  double variance_from() const { return std::ldexp(1.0, octave); }  // 2^k m²
  double variance_to() const { return std::ldexp(1.0, octave + 1); }
};

class ErrorByVariance {
 public:
  // Adds one row to each axis's bin of its P̂_aa (positive: Gaussian3's covariance is).
  void add(const Gaussian3& estimate, const Vector3d& truth);

  // Per axis (x, y, z), the bins that hold a row, smallest variance first.
  std::array<std::vector<VarianceBin>, 3> bins() const;

 private:
  struct Sums {
    std::size_t rows = 0;
    double variance = 0.0;
    double squared_error = 0.0;
  };
  std::array<std::map<int, Sums>, 3> axes_;
};

}  // namespace stgf
