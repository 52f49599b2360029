// SPDX-License-Identifier: Apache-2.0
#pragma once
// `wls`: the information-weighted mean of the views' measurements of an object at a step — the
// best linear unbiased estimate without a motion model (DESIGN §2, beyond the paper):
//
//   P̂ = (Σ_u R_u⁻¹)⁻¹,   x̂ = P̂ Σ_u R_u⁻¹ z_u
//
// It is the multi-view update with no prior; no memory across steps.

#include "stgf/methods/localizer.hpp"

namespace stgf {

class WeightedLeastSquares final : public Localizer {
 public:
  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;
};

}  // namespace stgf
