// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the χ² gate did in a run, said in the log: how many measurements failed it (by view), which
// views of which scenes had their noise scaled for disagreeing with the rest, and the tracks it
// restarted; and the measurements that the other views placed far off and that were fused with their
// noise scaled up (cross_view_weights.hpp, gate or not). Nothing the gate does goes unreported.

#include <string>

#include "stgf/core/measurement_gate.hpp"
#include "stgf/core/view_noise_scales.hpp"

namespace stgf::cli {

void log_gating(const std::string& method, const GateOptions& gate, const GatingSummary& summary);

}  // namespace stgf::cli
