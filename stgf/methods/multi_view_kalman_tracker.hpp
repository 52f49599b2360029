// SPDX-License-Identifier: Apache-2.0
#pragma once
// `mmt`: one constant-velocity Kalman filter per object (ConstantVelocityFilter, after AB3DMOT),
// updated at each step with every view's measurement of the object. An object seen for the first
// time starts a filter at its fused measurement with zero velocity; an object that was missed for
// a while is predicted across the gap. Every view that saw the object gets the same estimate.
// With the gate (an option, off by default), each measurement is checked against the filter's
// predicted position N(x, P): d² = (z − x)ᵀ (P + R)⁻¹ (z − x), and against the step's other
// measurements, as MeasurementGate::decide says; what fails is not fused and is counted per view.

#include <map>
#include <string>

#include "stgf/core/constant_velocity_filter.hpp"
#include "stgf/core/measurement_gate.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

class MultiViewKalmanTracker final : public Localizer {
 public:
  explicit MultiViewKalmanTracker(const ConstantVelocityModel& model, const GateOptions& gate = GateOptions{})
      : model_(model), gate_(gate) {}

  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;
  void report_gating(const std::string& scene, GatingSummary& summary) const override;

 private:
  struct Track {
    ConstantVelocityFilter filter;
    double time;  // of the last update
    int gated_events = 0;
  };
  ConstantVelocityModel model_;
  MeasurementGate gate_;
  ViewNoiseScales counts_;  // the gate's counts only
  std::size_t restarts_ = 0;
  std::map<std::string, Track, std::less<>> tracks_;
};

}  // namespace stgf
