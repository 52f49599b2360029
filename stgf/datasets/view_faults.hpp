// SPDX-License-Identifier: Apache-2.0
#pragma once
// A faulty view, made on purpose: measurements of one view corrupted the way real sensors fail, to
// test how a fusion method copes (and `stgf inject-fault`, which applies it to any measurements file).
// Every other view, every truth and every row order stay as they are, so the truth of the clean data
// scores the faulty one.
//
// Kinds, applied to each row of the chosen view (in every scene where it measures):
//   kJump              the view's calibration jumps in the middle of each scene: from the scene's
//                      middle time (t_first + t_last)/2 (over all its rows) on, z += d·u, with u a
//                      horizontal unit vector at an angle ~ U[0, 2π) per scene (a camera knocked, a
//                      vehicle's pose estimate jumping); R unchanged.
//   kUnderstatedNoise  the view states its noise `understatement` times too small: R ← R / factor,
//                      z unchanged (a detector whose covariance was tuned elsewhere).
//   kOutliers          each row, with probability `outlier_fraction`, is a gross error:
//                      z += r·u with r ~ U[r_min, r_max] and u horizontal at an angle ~ U[0, 2π)
//                      (a false detection, a wrong association); R unchanged.
// Horizontal, because a ground-plane error is the hard case: it lies where the views' noise is large.
//
// Random numbers: RandomStream(seed).child("view-faults").child(scene): the jump's angle (one
// uniform draw), or per row of the view in file order one Bernoulli draw and, for an outlier, its
// size and angle. So the faults of a scene do not depend on the other scenes.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "stgf/core/records.hpp"

namespace stgf {

enum class ViewFaultKind { kJump, kUnderstatedNoise, kOutliers };

// "jump", "understated-noise", "outliers".
std::string_view view_fault_name(ViewFaultKind kind);

struct ViewFaultOptions {
  ViewFaultKind kind = ViewFaultKind::kJump;
  std::string view;                // the faulty view
  double jump_m = 1.0;             // kJump: the size d of the step (m, > 0)
  double understatement = 100.0;   // kUnderstatedNoise: the factor (> 1)
  double outlier_fraction = 0.02;  // kOutliers: the probability of a row (0, 1]
  double outlier_min_m = 5.0;      // kOutliers: r_min (> 0)
  double outlier_max_m = 20.0;     // kOutliers: r_max (≥ r_min)
  std::uint64_t seed = 1;
};

// Throws std::invalid_argument for an option out of its range (named as the CLI names it).
void check_view_fault_options(const ViewFaultOptions& options);

struct ViewFaultSummary {
  std::size_t view_rows = 0;     // rows of the faulty view
  std::size_t changed_rows = 0;  // of which changed
  std::size_t scenes = 0;        // scenes in which the view measures
};

// Corrupts `rows` in place (any order; rows of other views untouched).
ViewFaultSummary inject_view_fault(std::span<Measurement> rows, const ViewFaultOptions& options);

}  // namespace stgf
