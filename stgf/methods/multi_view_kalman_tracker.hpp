// SPDX-License-Identifier: Apache-2.0
#pragma once
// `mmt`: one constant-velocity Kalman filter per object (ConstantVelocityFilter, after AB3DMOT),
// updated at each step with every view's measurement of the object. An object seen for the first
// time starts a filter at its fused measurement with zero velocity; an object that was missed for
// a while is predicted across the gap. Every view that saw the object gets the same estimate.

#include <map>
#include <string>

#include "stgf/core/constant_velocity_filter.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

class MultiViewKalmanTracker final : public Localizer {
 public:
  explicit MultiViewKalmanTracker(const ConstantVelocityModel& model) : model_(model) {}

  std::vector<Gaussian3> step(double time, std::span<const Measurement* const> measurements) override;

 private:
  struct Track {
    ConstantVelocityFilter filter;
    double time;  // of the last update
  };
  ConstantVelocityModel model_;
  std::map<std::string, Track, std::less<>> tracks_;
};

}  // namespace stgf
