// SPDX-License-Identifier: Apache-2.0
#pragma once
// Q(τ), the covariance of a forecast's error τ seconds after its last history position (design §1.2,
// §1.9), as a motion model stores it: Q_ref at its calibration interval τ_ref, and optionally Q
// calibrated at longer intervals τ_1 < … < τ_n (inside the filter, on the validation split thinned
// out: learn/filter_calibration.hpp). A model has two such curves: one for its own forecasts, and
// one for a track that *coasts* by constant velocity beyond its horizon (ObjectTrack::coasts_to),
// whose first node plays the part of Q_ref.
//
//     τ ≤ τ_ref:          Q(τ) = Q_ref τ / τ_ref                          (independent increments)
//     τ_i ≤ τ ≤ τ_{i+1}:  Q(τ) = Q_i + (Q_{i+1} − Q_i) (τ² − τ_i²) / (τ_{i+1}² − τ_i²)   (τ_0 = τ_ref)
//     τ > τ_n:            Q(τ) = Q_n (τ / τ_n)³                             (a random-walk velocity's)
//
// Each node is at least the one before (Q_{i+1} − Q_i positive semi-definite; the calibration makes it
// so), so Q grows with τ and every increment Q(τ) − Q(τ_s), τ > τ_s, is a covariance. Without nodes,
// Q(τ) = Q_ref (τ / τ_ref)² beyond τ_ref (an unknown velocity's error). Beyond τ_n the cube is a
// guess, not a calibration: a track is trusted to coast only to kHorizonFactor τ_n
// (motion_predictor.hpp, coasting_horizon).
//
// Why linear below τ_ref: only a track updated between two history positions (views on their own
// clocks) predicts over less than τ_ref, and it does so in pieces, Q(τ_1) − Q(0), Q(τ_2) − Q(τ_1), …,
// each added to a position-only state as if independent of the pieces before (object_track.hpp).
// An error process with independent, stationary increments grows linearly in τ; one that grows as τ²
// (a velocity error, fixed within the interval) has increments that are strongly correlated, and
// counting them as independent put almost none of Q_ref on the first pieces after a history position
// (a tenth of the interval got 1 % of it): the first views after a history position were trusted far
// beyond what the forecast was worth. Both laws agree at τ_ref, where Q_ref is calibrated, so
// synchronised views (which predict over whole intervals) see no difference. Measured on the
// asynchronous validation splits of mpl and cad (design §1.2).

#include <span>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

struct IntervalNoise {
  double interval;  // τ_i (s)
  Matrix3d covariance;  // Q_i (m²)
};

// Q(τ) / Q_ref without nodes: τ / τ_ref up to τ_ref, (τ / τ_ref)² beyond (`period` is τ_ref).
double reference_growth(double period, double tau);
// Its inverse, Q_ref / Q(τ), computed from τ_ref / τ (what the calibration scales a residual at τ by).
double reference_shrinkage(double period, double tau);
// Q(τ) as above. `nodes` sorted by interval, all beyond `period`.
Matrix3d process_noise_at(const Matrix3d& reference, double period, std::span<const IntervalNoise> nodes, double tau);
// Throws std::invalid_argument unless every node's interval is finite and beyond the one before
// (the first beyond `after`) and every covariance finite.
void check_process_noise_nodes(std::span<const IntervalNoise> nodes, double after);
// The coasting curve: Q(τ) with its first node as the reference. `nodes` must not be empty.
Matrix3d coasting_process_noise_at(std::span<const IntervalNoise> nodes, double tau);

}  // namespace stgf
