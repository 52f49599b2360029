// SPDX-License-Identifier: Apache-2.0
#pragma once
// `wls`: the information-weighted mean of the views' measurements of an object at a step — the
// best linear unbiased estimate without a motion model (DESIGN §2, beyond the paper):
//
//   P̂ = (Σ_u R_u⁻¹)⁻¹,   x̂ = P̂ Σ_u R_u⁻¹ z_u
//
// It is the multi-view update with no prior; no memory across steps. With the gate (an option, off
// by default), only the measurements that agree with the consensus of the step's measurements of the
// object are fused (MeasurementGate::consensus); the others are counted per view.

#include "stgf/core/measurement_gate.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

class WeightedLeastSquares final : public Localizer {
 public:
  explicit WeightedLeastSquares(const GateOptions& gate = GateOptions{}) : gate_(gate) {}

  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;
  void report_gating(const std::string& scene, GatingSummary& summary) const override { summary.add(scene, counts_); }

 private:
  MeasurementGate gate_;
  ViewNoiseScales counts_;  // the gate's counts only
};

}  // namespace stgf
