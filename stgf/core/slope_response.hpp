// SPDX-License-Identifier: Apache-2.0
#pragma once
// How a forecast responds to its history's slope (design §1.2), measured by running the motion model
// once more on its histories tilted.
//
// A forecast f reads a velocity off the history positions, whose errors it carries on: an error δv in
// the history's slope moves f(τ) by J(τ) δv. Constant velocity carries it as it is, J = τ I. A learned
// Φ need not: on a ground plane, where the heights do not move, it learnt that a slope in the history's
// heights is the positions' error and brings the height back toward the history's (its vertical J is
// negative), while it carries the horizontal slope on (J ≈ τ). J is measured per axis by a second
// pass of the model on the same graphs, each object's history tilted by its own slope's error:
//     p_k ← p_k + s ⊙ (t_k − t_n),   s_a = √Var(v̂)_aa  (clamped to [0.01, 1] times the typical speed),
// every axis at once; the response on axis a is the change of the forecast's velocity and acceleration
// on that axis over s_a, so J(τ) = diag(Δv / s τ + ½ Δa / s τ²). A secant over the error's own size,
// not a derivative: Φ is not linear. Reading each axis's response off its own axis leaves out how one
// axis's slope moves another's forecast, and tilting every object of a graph together leaves out what
// a neighbour's tilt does to an object (Φ reads the neighbours' relative motion, which a common tilt
// does not change much). ObjectTrack::velocity_error_to uses J.

#include <span>
#include <vector>

#include "stgf/core/motion_graph.hpp"
#include "stgf/core/motion_predictor.hpp"

namespace stgf {

// s: the tilt for a history whose slope has the error covariance `velocity_variance`.
Vector3d slope_tilt(const Matrix3d& velocity_variance, double typical_speed);

// The graph with object i's history tilted by tilts[i]: p_k + tilts[i] (t_k − t_n), the last position
// kept. One tilt per object.
MotionGraph tilted_graph(const MotionGraph& graph, std::span<const Vector3d> tilts);

// `forecast` with its velocity_response and acceleration_response measured from the forecast of the
// same history tilted by `tilt`.
MotionForecast with_slope_response(MotionForecast forecast, const MotionForecast& tilted, const Vector3d& tilt);

}  // namespace stgf
