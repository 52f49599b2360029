// SPDX-License-Identifier: Apache-2.0
#pragma once
// Q(τ), the covariance of a forecast's error τ seconds after its last history position (design §1.2,
// §1.9), as a motion model stores it: Q_ref at its calibration interval τ_ref, and optionally Q
// calibrated at longer intervals τ_1 < … < τ_n (inside the filter, on the validation split thinned
// out: learn/filter_calibration.hpp). A model has two such curves: one for its own forecasts, and
// one for a track that *coasts* by constant velocity beyond its horizon (ObjectTrack::coasts_to),
// whose first node plays the part of Q_ref.
//
//     τ ≤ τ_ref:          Q(τ) = Q_ref (τ / τ_ref)²                        (an unknown velocity's error)
//     τ_i ≤ τ ≤ τ_{i+1}:  Q(τ) = Q_i + (Q_{i+1} − Q_i) (τ² − τ_i²) / (τ_{i+1}² − τ_i²)   (τ_0 = τ_ref)
//     τ > τ_n:            Q(τ) = Q_n (τ / τ_n)³                             (a random-walk velocity's)
//
// Each node is at least the one before (Q_{i+1} − Q_i positive semi-definite; the calibration makes it
// so), so Q grows with τ and every increment Q(τ) − Q(τ_s), τ > τ_s, is a covariance. Without nodes
// this is the τ² law of every model before them. Beyond τ_n the cube is a guess, not a calibration:
// a track is trusted to coast only to kHorizonFactor τ_n (motion_predictor.hpp, coasting_horizon).

#include <span>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

struct IntervalNoise {
  double interval;  // τ_i (s)
  Matrix3d covariance;  // Q_i (m²)
};

// Q(τ) as above. `nodes` sorted by interval, all beyond `period`.
Matrix3d process_noise_at(const Matrix3d& reference, double period, std::span<const IntervalNoise> nodes, double tau);
// Throws std::invalid_argument unless every node's interval is finite and beyond the one before
// (the first beyond `after`) and every covariance finite.
void check_process_noise_nodes(std::span<const IntervalNoise> nodes, double after);
// The coasting curve: Q(τ) with its first node as the reference. `nodes` must not be empty.
Matrix3d coasting_process_noise_at(std::span<const IntervalNoise> nodes, double tau);

}  // namespace stgf
