// SPDX-License-Identifier: Apache-2.0
#pragma once
// The synthetic benchmark (DESIGN §5): objects that walk, turn, stop and avoid each other on the
// ground, seen by fixed views placed around the scene, each with range-dependent anisotropic noise
// and occasional misses. The same options (seed included) give byte-identical files on every
// platform: all randomness comes from RandomStream and all elementary functions from
// stgf::portable (datasets/random.hpp).
//
// ── Random streams ────────────────────────────────────────────────────────────────────────────────
// root = RandomStream(seed). Views: root.child("views"). Scene k of split S ("train", "val",
// "test"): scene = root.child(S).child(k); its motion draws from scene.child("motion") and view v's
// detections and noise from scene.child("sensing").child(v). So splits and scenes are independent,
// the number of views does not change the trajectories, and one view's misses and noise do not
// depend on the other views.
//
// ── Motion (ground plane, z = 0; every rate per second, so any rate_hz gives the same motion) ─────
// Each frame period 1/rate_hz is integrated in n = ⌈(1/rate_hz)/max_substep_s⌉ equal substeps dt.
// Object i has position p, velocity v, an intended heading h (unit vector), a turn rate ω, a
// preferred speed s ~ U[min_speed, max_speed] and a stop timer. Per substep:
//   stops    while moving, it stops with probability 1 − exp(−stop_rate·dt) and stays stopped for
//            U[min_stop, max_stop] seconds, then walks on.
//   turning  ω is an Ornstein–Uhlenbeck process with standard deviation σ_ω and correlation time τ:
//              ω ← φ ω + σ_ω √(1 − φ²) ξ,  φ = exp(−dt/τ),  ξ ~ N(0, 1)   (exact discretisation)
//            so paths curve smoothly and the heading wanders (var of the heading change over T ≫ τ
//            is ≈ 2 σ_ω² τ T).
//   boundary within boundary_margin of the edge of the square [−w, w]² it turns toward the centre c:
//              ω_b = boundary_turn_rate · min(1, depth/margin) · steer(h, c − p)
//            where depth is how far p is inside the margin band and steer(h, d) = h × d̂ when h points
//            toward d (h·d̂ ≥ 0) and ±1 (the sign of h × d̂) when it points away.
//   avoiding every other object j closer than r_a = avoidance_radius, with closeness κ_j = 1 − d_ij/r_a
//            and d̂_j the unit vector from i to j, asks i to steer away from those ahead (h·d̂_j > 0),
//            to slow down for them, and to step away from all of them:
//              ω_a = −avoidance_turn_rate · Σ_{j ahead} κ_j sign(h × d̂_j)
//              β   = max_{j ahead} κ_j (h·d̂_j)                       (braking, ∈ [0, 1])
//              u_a = −avoidance_speed · Σ_j κ_j d̂_j                  (sidestep velocity)
//   heading  h is rotated by (ω + ω_b + ω_a)·dt.
//   velocity the intended velocity is s (1 − β) h + u_a (only u_a while stopped); v moves toward it
//            by at most max_acceleration·dt (so objects come to rest when they stop, and sharp turns
//            widen).
//   position after every object's velocity is updated, p ← p + v dt.
// Objects start in the inner square [−(w − margin), w − margin]², at least avoidance_radius apart
// when possible, walking in a uniformly random direction with ω drawn from its stationary
// N(0, σ_ω²). Truth is (p_x, p_y, 0) at every frame t = step / rate_hz for every object.
//
// ── Views ────────────────────────────────────────────────────────────────────────────────────────
// View k (of V) sits at angle α₀ + 2πk/V + U[−angle_jitter, angle_jitter] (α₀ ~ U[0, 2π)) on a circle
// of radius view_ring_radius + U[−ring_jitter, ring_jitter] around the centre, at height
// U[min_sensor_height, max_sensor_height], with a noise scale g ~ U[min_noise_scale, max_noise_scale]
// that multiplies all its standard deviations. Views are fixed for the whole benchmark (shared by
// all splits and scenes), like an installed camera network.
//
// ── Measurement noise ───────────────────────────────────────────────────────────────────────────
// For a view at sensor position s and an object at p, range r = ‖p − s‖, the line-of-sight basis
// U = [u_r u_c u_v] (line_of_sight.hpp):
//   u_r = (p − s)/r                            along the range
//   u_c = (−u_r,y, u_r,x, 0)/‖·‖               across, horizontal
//   u_v = u_r × u_c                            across, in the vertical plane of the line of sight
// and the standard deviations (stereo/depth-like along the range, angular across it)
//   σ_r = g (a_r + b_r r²),   σ_c = g (a_c + b_c r),   σ_v = g (a_v + b_v r)
// give R = U diag(σ_r², σ_c², σ_v²) Uᵀ. The measurement is z = p + U diag(σ) ξ with ξ ~ N(0, I₃):
// U diag(σ) is a square root of R ((U diag σ)(U diag σ)ᵀ = R exactly, as a Cholesky factor would
// be), so z − p ~ N(0, R) exactly: R is the true error covariance, no bias is hidden, and the NEES
// (z − p)ᵀ R⁻¹ (z − p) of the raw measurements is χ²₃ (mean 3, variance 6).
//
// ── Misses ───────────────────────────────────────────────────────────────────────────────────────
// A view detects an object at range r with probability
//   P_d(r) = P_near − (P_near − P_far) (r / max_range)²   for r ≤ max_range,   0 beyond,
// independently per view, object and step. A missed object has no row for that view and step; the
// truth still has every object at every step.
//
// ── Clocks and latency ───────────────────────────────────────────────────────────────────────────
// Off by default. With options.clocks asynchronous and/or a latency, every split goes through
// apply_view_clocks (view_clocks.hpp) with T = 1 / rate_hz. The walkers exist only during their
// scene, so a track beyond the scene's first or last step is extrapolated linearly from its two
// nearest steps. The description then has a "clocks" entry.
//
// ── Output ───────────────────────────────────────────────────────────────────────────────────────
// Scenes "synthetic-<split>-NNNN", objects "o0"…, views "v0"…; measurement rows sorted by (scene,
// step, view index, object index), truth rows by (scene, step, object index); every measurement
// carries its view's sensor position. The description (benchmark.json) records source "synthetic",
// the seed, every option, the views and the model formulas.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/line_of_sight.hpp"
#include "stgf/datasets/view_clocks.hpp"

namespace stgf {

struct SyntheticOptions {
  // ── Shape of the benchmark ──
  std::uint64_t seed = 1;  // every random draw derives from it
  int objects = 6;         // objects per scene (≥ 1)
  int views = 4;           // views around the scene, shared by all scenes (≥ 1)
  int steps = 50;          // steps per scene (≥ 2)
  int scenes = 10;         // scenes per split: train, val and test get this many each (≥ 1)
  double rate_hz = 10.0;   // steps per second; t = step / rate_hz (> 0)

  // ── Scene and motion ──
  double area_half_width_m = 15.0;        // objects walk in the square [−w, w]² (m)
  double boundary_margin_m = 3.0;         // width of the band along the edge where they turn back (m)
  double boundary_turn_rate_rad_s = 2.0;  // turn rate toward the centre at the band's outer edge (rad/s)
  double min_speed_m_s = 0.8;             // preferred walking speed, uniform in [min, max] per object (m/s)
  double max_speed_m_s = 1.6;             //   (pedestrians)
  double max_acceleration_m_s2 = 2.0;     // how fast velocity follows the intended one (m/s²)
  double turn_rate_std_rad_s = 0.5;       // stationary standard deviation of the random turn rate (rad/s)
  double turn_rate_correlation_s = 2.0;   // correlation time of the random turn rate (s)
  double stop_rate_per_s = 0.08;          // stops per second of walking (1/s)
  double min_stop_s = 1.0;                // a stop lasts uniform in [min, max] (s)
  double max_stop_s = 4.0;
  double avoidance_radius_m = 2.0;         // objects closer than this avoid each other (m; 0 = off)
  double avoidance_turn_rate_rad_s = 2.0;  // turn rate away from a neighbour ahead at contact (rad/s)
  double avoidance_speed_m_s = 1.0;        // sidestep speed away from a neighbour at contact (m/s)
  double max_substep_s = 0.02;             // longest integration substep (s)

  // ── Views ──
  double view_ring_radius_m = 30.0;     // views stand on a circle of this radius around the centre (m)
  double view_ring_jitter_m = 4.0;      // ± uniform jitter of each view's radius (m)
  double view_angle_jitter_rad = 0.25;  // ± uniform jitter of each view's angle on the circle (rad)
  double min_sensor_height_m = 3.0;     // sensor height, uniform in [min, max] (m)
  double max_sensor_height_m = 8.0;
  double min_noise_scale = 0.7;  // per-view factor g on all noise standard deviations,
  double max_noise_scale = 1.4;  //   uniform in [min, max]

  // ── Measurement noise: σ_r = g (a_r + b_r r²), σ_c = g (a_c + b_c r), σ_v = g (a_v + b_v r) ──
  double range_noise_m = 0.05;          // a_r: along-range standard deviation at range 0 (m)
  double range_noise_per_m2 = 5e-4;     // b_r: growth with range squared (1/m); σ_r = 0.5 m at 30 m
  double cross_noise_m = 0.03;          // a_c: horizontal across-range standard deviation at range 0 (m)
  double cross_noise_per_m = 0.005;     // b_c: growth with range (rad); σ_c = 0.18 m at 30 m
  double vertical_noise_m = 0.03;       // a_v: vertical across-range standard deviation at range 0 (m)
  double vertical_noise_per_m = 0.004;  // b_v: growth with range (rad); σ_v = 0.15 m at 30 m

  // ── Misses: P_d(r) = P_near − (P_near − P_far)(r/max_range)², 0 beyond max_range ──
  double max_range_m = 50.0;                 // no detection beyond this range (m)
  double detection_probability_near = 0.98;  // P_near: at range 0
  double detection_probability_far = 0.7;    // P_far: at max_range

  // ── Clocks and latency (view_clocks.hpp); the defaults leave the data synchronous, no arrivals ──
  ViewClockOptions clocks = {};
};

// Throws std::invalid_argument naming the first option out of range and its value.
void validate_synthetic_options(const SyntheticOptions& options);

struct SyntheticView {
  std::string id;            // "v0", "v1", ...
  Vector3d sensor_position;  // constant over time (m)
  double noise_scale = 1.0;  // g
};

// The views of the benchmark (from the "views" stream of the seed). Validates the options.
std::vector<SyntheticView> place_synthetic_views(const SyntheticOptions& options);

// The measurement noise of `view` for an object at `target` (see the header comment):
// line_of_sight (line_of_sight.hpp) with σ_r, σ_c, σ_v of these options and the view's g.
LineOfSightNoise line_of_sight_noise(const SyntheticOptions& options, const SyntheticView& view,
                                     const Vector3d& target);

// P_d(range) (see the header comment; range_detection_probability with these options).
double detection_probability(const SyntheticOptions& options, double range_m);

// The "views" of benchmark.json: per view its id, sensor_position [x, y, z] and noise_scale.
nlohmann::json describe_synthetic_views(std::span<const SyntheticView> views);

// What benchmark.json records about a synthetic benchmark (without "counts").
nlohmann::json describe_synthetic_benchmark(const SyntheticOptions& options,
                                            std::span<const SyntheticView> views);

// The whole benchmark: validated options, views, and `scenes` scenes per split.
Benchmark make_synthetic_benchmark(const SyntheticOptions& options);

}  // namespace stgf
