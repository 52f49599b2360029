// SPDX-License-Identifier: Apache-2.0
#pragma once
// The interface every localization method implements (DESIGN §2): model-based (aom, wls, mmt) and,
// later, learned ones. A Localizer serves one scene and is fed one step at a time, so the same
// object runs offline over a file and online in a robot's loop.

#include <span>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/core/view_noise_scales.hpp"

namespace stgf {

class Localizer {
 public:
  virtual ~Localizer() = default;

  // Consumes every measurement of one step of the scene (one time; no (view, object) twice) and
  // returns one estimate per measurement, in the same order: the position of measurement k's
  // object as held by measurement k's view. Times increase strictly from call to call. A step may
  // be empty (no view saw anything).
  virtual std::vector<Gaussian3> step(double time,
                                      std::span<const Measurement* const> measurements) = 0;

  // Adds what its χ² gate did in this scene (core/measurement_gate.hpp); nothing for a method without.
  virtual void report_gating(const std::string& /*scene*/, GatingSummary& /*summary*/) const {}
};

}  // namespace stgf
