// SPDX-License-Identifier: Apache-2.0
#pragma once
// `aom`: the plain average of all views' measurements of an object at a step (paper's AOM).
//
//   x̂ = (1/n) Σ_u z_u,   P̂ = (1/n²) Σ_u R_u
//
// P̂ is the exact covariance of that average when the views' errors are independent, so even
// this baseline reports an honest uncertainty. No memory across steps.

#include "stgf/methods/localizer.hpp"

namespace stgf {

class AverageOfMeasurements final : public Localizer {
 public:
  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;
};

}  // namespace stgf
