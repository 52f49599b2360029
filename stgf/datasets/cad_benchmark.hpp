// SPDX-License-Identifier: Apache-2.0
#pragma once
// The cad benchmark (DESIGN §5): connected vehicles that share what their sensors see, built from
// real KITTI tracking sequences (datasets/kitti_tracking.hpp). The true trajectories are the
// labelled 10 Hz box tracks in each sequence's world frame; the ego car and up to three other real
// moving cars of the same sequence act as connected vehicles, each with a range- and field-of-view-
// limited RGB-D sensor, and each sharing its measurements in the world frame through its own
// (erroneous) GPS pose. The same options (seed and source files included) give byte-identical files
// on every platform: all randomness comes from RandomStream and all elementary functions from
// stgf::portable (datasets/random.hpp).
//
// ── Splits ──────────────────────────────────────────────────────────────────────────────────────
// Disjoint by sequence: every sequence belongs to at most one split (checked). Default assignment of
// ten KITTI tracking training sequences (not shipped; data/README.md), with their frames, moving
// vehicle tracks (Car/Van/Truck averaging > 0.5 m/s) and, with the default options, the
// eligible windows (below) and the share of chosen objects that move:
//   train  0002 0003 0005 0006 0008 0018   1673 frames, 78 moving vehicles, 632 windows, 74% moving
//   val    0004 0010                        608 frames, 34 moving vehicles, 113 windows, 51% moving
//   test   0011 0020                       1210 frames, 95 moving vehicles, 875 windows, 48% moving
// Test gets the long 0020 (the most moving traffic, nearly all going the ego's way: 4 vehicles fit
// most of its windows, the paper's shape) and 0011 (parked rows, pedestrians, oncoming traffic), so
// it holds the largest share of moving vehicles and windows. Train gets six drives of different
// character (0018 dense traffic ahead, 0008 a long drive following traffic, 0005 parked rows and
// oncoming traffic, 0006 an ego mostly standing while traffic passes, 0002 crossing traffic with
// pedestrians and cyclists; 0003 has no eligible window with the defaults). Val gets 0004 (the ego
// turns through oncoming and crossing traffic) and 0010 (trams), whose objects move about as often
// as test's, which matters for calibrating Φ's process noise on val (DESIGN §1.2). Instances:
// 1500 / 500 / 1500, so windows are reused (about 2.4, 4.4 and 1.7 times) with different objects, GPS
// errors and noise.
//
// ── Windows and who is in them ──────────────────────────────────────────────────────────────────
// A window is `steps` consecutive frames [s, s + steps) of one sequence (every start s). In it:
//   present          tracks labelled in every frame of the window (Misc excluded).
//   moving vehicle   a present Car, Van or Truck whose mean speed over the window,
//                    ‖p(s+steps−1) − p(s)‖_xy / ((steps − 1)/10 Hz), is at least
//                    min_vehicle_speed_m_s (horizontal world displacement of the box bottom centre;
//                    label jitter of ~0.1 m gives a parked car an apparent ~0.2 m/s).
//   vehicles         the ego car (always, view "v0") and k = min(max_vehicles − 1, #moving)
//                    moving vehicles drawn uniformly (choose_ids) with the window's own stream, so
//                    a window has the same vehicles whatever instance uses it; views "v1".."vk"
//                    in the order of their ids.
//   visible          an object is visible to a vehicle at a frame when it is within max_range_m of
//                    the vehicle's true sensor and within its horizontal field of view (below).
//   eligible object  a present track that is not one of the vehicles and is visible to at least one
//                    vehicle in at least ⌈min_visible_fraction · steps⌉ frames of the window.
// If fewer than `objects` objects are eligible, the last of the drawn vehicles (in id order) is
// given back (it may then be an object) and the eligibility recomputed, until enough are eligible or
// the window would have fewer than min_vehicles vehicles: then the window is rejected (counted as
// "too few objects"); a window with fewer than min_vehicles − 1 moving vehicles to begin with is
// rejected as "too few vehicles". So instances have as many vehicles as the window allows while
// keeping `objects` objects.
// Instances: the split's eligible windows are shuffled (Fisher–Yates, split stream) and instance k
// uses window k mod W, so windows are used as evenly as possible (⌊N/W⌋ or ⌈N/W⌉ times; windows
// that start a frame apart share steps − 1 frames). The instance draws its `objects` objects
// uniformly from the window's eligible ones (choose_ids), its GPS errors and its measurements.
//
// ── Sensors ─────────────────────────────────────────────────────────────────────────────────────
//   ego     at the reference camera's centre (calibration: pose_f · camera_to_imu · 0, ~1.65 m above
//           the road), looking along the IMU's x axis (the oxts yaw) projected on the horizontal.
//   others  at the box's bottom centre raised by sensor_height_m (world z), looking along the label
//           heading (the box's forward axis from rotation_y, kitti_tracking.hpp) projected on the
//           horizontal. The label heading, not the direction of motion: the sensor is fixed to the
//           body, the heading is labelled in every frame, and a 10 Hz difference of positions that
//           jitter by ~0.1 m gives a direction that is off by several degrees at 10 m/s and
//           meaningless when the car slows down.
// Horizontal field of view: with d the horizontal part of (p − s) and h the unit heading,
//   inside ⇔ d·h ≥ ‖d‖ cos(field_of_view_deg/2)   (no vertical limit).
//
// ── Measurement noise (RGB-D: depth along the line of sight, angles across it) ─────────────────────
// For the true sensor position s and the true object position p (bottom centre), r = ‖p − s‖ and the
// line-of-sight basis U = [u_r u_c u_v] (line_of_sight.hpp, as in synthetic.hpp):
//   u_r = (p − s)/r,   u_c = (−u_r,y, u_r,x, 0)/‖·‖ (horizontal, across),   u_v = u_r × u_c
//   σ_d = depth_noise_m + depth_noise_per_m2 · r²       (stereo: σ_z = z² σ_disparity / (f·B))
//   σ_c = r · lateral_angle_noise_rad,   σ_v = r · vertical_angle_noise_rad
// ── GPS pose error (per vehicle and instance; not in R) ────────────────────────────────────────────
// Each vehicle's reference point is its sensor s. Its reported pose is off by a horizontal position
// error δc = (N(0, σ_p²), N(0, σ_p²), 0) and a heading error δψ ~ N(0, σ_ψ²) (σ_p =
// gps_position_error_m, σ_ψ = gps_heading_error_deg), drawn once per vehicle and instance. A
// vehicle measures in its own frame and shares the result through its reported pose, so every one
// of its measurements is moved by the same rigid map G (rotation by δψ about the vertical through
// the reported position s + δc, after translating by δc):
//   G(x) = s + δc + Rz(δψ) (x − s)
// The measurement and the covariance written with it:
//   U' = Rz(δψ) U,   p' = G(p) = s + δc + Rz(δψ)(p − s)
//   z = p' + U' diag(σ_d, σ_c, σ_v) ξ,   ξ ~ N(0, I₃)
//   R = U' diag(σ_d², σ_c², σ_v²) U'ᵀ           (the vehicle's own R, rotated to the world with its
//                                                reported heading)
//   sensor_x/y/z = G(s) = s + δc                 (the reported sensor position, as the vehicle shares it)
// So z − p' ~ N(0, R) exactly, and z − p = (p' − p) + N(0, R): the GPS error adds the bias p' − p =
// δc + (Rz(δψ) − I)(p − s), the same for all of a vehicle's measurements in an instance up to the
// rotation's lever arm, which R does not state. With σ_p = σ_ψ = 0, G is the identity, z − p ~ N(0, R)
// and the raw NEES (z − p)ᵀ R⁻¹ (z − p) is χ²₃ (mean 3, variance 6). σ uses the true range (the
// measured one would make R itself random).
// ── Misses ──────────────────────────────────────────────────────────────────────────────────────
// A visible object is detected with probability
//   P_d(r) = P_near − (P_near − P_far) (r / max_range_m)²
// independently per vehicle, object and step; invisible or missed objects have no row. Truth has
// every object at every step. Occlusion is not modelled.
//
// ── Random streams ──────────────────────────────────────────────────────────────────────────────
// root = RandomStream(seed). Window (sequence q, start s): root.child("vehicles").child(q).child(s).
// Split S: root.child(S).child("order") shuffles its windows; instance k: i = root.child(S).child(k),
// objects from i.child("objects"), vehicle v's GPS error from i.child("gps").child(v) (δc_x, δc_y,
// δψ in that order) and its detections and noise from i.child("sensing").child(v) (per step, per
// object in id order: one Bernoulli draw when visible, then three normals when detected).
//
// ── Clocks and latency ──────────────────────────────────────────────────────────────────────────
// Off by default. With options.clocks asynchronous and/or a latency, every split goes through
// apply_view_clocks (view_clocks.hpp) with T = 0.1 s; a track beyond the window is the object's own
// KITTI box in the frame before the window and the two after it where it is labelled there, else
// extrapolated linearly. A vehicle's reported sensor position stays that of the frame (the vehicle
// moves up to 0.45 T of its motion in the meantime). The description then has a "clocks" entry.
//
// ── Output ──────────────────────────────────────────────────────────────────────────────────────
// Scenes "cad-<split>-NNNN" (instance k of the split), t = frame / 10 with the window's own frame
// numbers, views "v0" (ego) … "v3", objects "<sequence>-<track id>" (kitti_object_id). Measurement
// rows sorted by (scene, t, view, object), truth rows by (scene, t, object); every measurement
// carries its vehicle's reported sensor position. benchmark.json records the source, the seed, every
// option, the model, and per split the sequences, the window counts (candidate, eligible, rejected
// and why), the instance count, how many instances have 1, 2, 3, 4 vehicles, and every instance
// (its sequence, first frame, vehicles with their real track ids and GPS errors, and objects).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/line_of_sight.hpp"
#include "stgf/datasets/view_clocks.hpp"

namespace stgf {

struct CadOptions {
  // ── Source and shape ──
  std::uint64_t seed = 1;                                          // every random draw derives from it
  std::string source_directory;                                    // holds label/ oxts/ calib/ (KITTI is not
                                                                   //   shipped: the caller says where it is)
  std::vector<std::string> train_sequences = {"0002", "0003", "0005", "0006", "0008", "0018"};
  std::vector<std::string> val_sequences = {"0004", "0010"};  // disjoint by sequence (see above)
  std::vector<std::string> test_sequences = {"0011", "0020"};
  int train_instances = 1500;  // instances (scenes) per split (≥ 0; a split with instances needs
  int val_instances = 500;     //   at least one eligible window)
  int test_instances = 1500;
  int steps = 10;        // frames per instance at 10 Hz (≥ 2; the paper's shape is ≥ 8)
  int objects = 3;       // tracked objects per instance (≥ 1)
  int max_vehicles = 4;  // connected vehicles per instance, the ego included (≥ 1)
  int min_vehicles = 2;  // windows that cannot have this many (ego included) are rejected
                         //   (1 ≤ min_vehicles ≤ max_vehicles)

  // ── Who is a vehicle, which objects count ──
  double min_vehicle_speed_m_s = 1.0;  // a Car/Van/Truck is a moving vehicle at this mean window
                                       //   speed or more (m/s)
  double min_visible_fraction = 0.8;   // an object must be visible to some vehicle in at least this
                                       //   share of the window's frames ([0, 1])
  double sensor_height_m = 1.65;       // other vehicles' sensor above their box bottom centre (m;
                                       //   KITTI's own camera is 1.65 m above the road)

  // ── Sensor: range, field of view, noise ──
  double max_range_m = 50.0;                // nothing is seen beyond this distance (m)
  double field_of_view_deg = 90.0;          // horizontal, centred on the heading (deg; (0, 360])
  double depth_noise_m = 0.05;              // a: depth standard deviation at range 0 (m)
  double depth_noise_per_m2 = 5e-4;         // b: σ_d = a + b r² (1/m); 0.5 m at 30 m, 1.3 m at 50 m
                                            //   (a stereo pair like KITTI's, f = 721 px, B = 0.54 m,
                                            //   with 0.2 px disparity noise gives b = 5.1e-4)
  double lateral_angle_noise_rad = 0.003;   // σ_c = r σ_θ across the line of sight, horizontal (rad;
                                            //   ~2 px at f = 721 px)
  double vertical_angle_noise_rad = 0.003;  // σ_v = r σ_θ across the line of sight, vertical (rad)

  // ── Misses: P_d(r) = P_near − (P_near − P_far)(r / max_range)² ──
  double detection_probability_near = 0.95;  // P_near, at range 0
  double detection_probability_far = 0.7;    // P_far, at max_range_m

  // ── GPS pose error of every vehicle, per instance (not in R; 0 turns it off) ──
  double gps_position_error_m = 0.3;   // σ_p: standard deviation of each horizontal axis (m;
                                       //   decimetre-level GNSS/INS without RTK corrections)
  double gps_heading_error_deg = 0.5;  // σ_ψ: standard deviation of the heading (deg)

  // ── Clocks and latency (view_clocks.hpp); the defaults leave the data synchronous, no arrivals ──
  ViewClockOptions clocks = {};
};

// Throws std::invalid_argument naming the first option out of range and its value, or a sequence
// that is in two splits or twice in one.
void validate_cad_options(const CadOptions& options);

// The sensor noise for a true sensor position and a true object position (see the header comment,
// without the GPS rotation): U, (σ_d, σ_c, σ_v) and r (line_of_sight.hpp).
using CadSensorNoise = LineOfSightNoise;
CadSensorNoise cad_sensor_noise(const CadOptions& options, const Vector3d& sensor, const Vector3d& target);

// P_d(range): 0 beyond max_range_m (range_detection_probability with these options).
double cad_detection_probability(const CadOptions& options, double range_m);

// The whole benchmark from the KITTI files in options.source_directory. Validates the options;
// InputError for bad or missing source files; std::runtime_error when a split with instances has
// no eligible window.
Benchmark make_cad_benchmark(const CadOptions& options);

}  // namespace stgf
