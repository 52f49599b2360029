// SPDX-License-Identifier: Apache-2.0
#pragma once
// The ethucy benchmark (DESIGN §5): real ETH/UCY pedestrian trajectories (datasets/eth_ucy.hpp) seen
// by simulated cameras around each scene, split leave-one-scene-out. Its purpose is plenty of real
// pedestrian motion for training Φ, and the standard leave-one-scene-out test. The same options (seed
// included) and files give the same benchmark: all randomness comes from RandomStream and all
// elementary functions from stgf::portable (datasets/random.hpp).
//
// ── Splits ───────────────────────────────────────────────────────────────────────────────────────
// test   every recording of the test scene (eth | hotel | univ | zara1 | zara2, see eth_ucy_scenes()),
//        over its whole frame range.
// train  every other recording — the other four scenes and the training-only files crowds_zara03 and
// val    uni_examples — split in time: a recording with frame indices F₀ … F₁ (n = F₁ − F₀ + 1) gives
//          val   frames [B, F₁],  train frames [F₀, B),  B = F₁ + 1 − ⌊val_fraction · n + ½⌋,
//        so validation is the last val_fraction of each recording's time. Windows never cross B, so
//        train and val share no frame of any recording, and the test scene appears in neither.
// This is the leave-one-out convention of Social-GAN and Trajectron++ (see eth_ucy.hpp); their val
// files are also a later stretch of each training file (e.g. biwi_eth_val.txt: frames 10240–12380).
//
// ── Instances ────────────────────────────────────────────────────────────────────────────────────
// An eligible window is `steps` consecutive frame indices, all annotated, inside one recording's part
// of the split, in which at least min_objects pedestrians are present in every frame
// (windows_with_objects; windows start at every frame, so neighbouring windows overlap). A split's
// pool is the list of its eligible windows in file order, then start frame. Of W windows and N
// requested instances (N = 0: N = W, every window once):
//   each window gives ⌊N/W⌋ instances, and N mod W windows drawn uniformly without replacement give
//   one more,
// so no window repeats while N ≤ W and windows are spread evenly when N > W. Instances are listed in
// pool order. An instance keeps k = min(present, max_objects) of the window's pedestrians, drawn
// uniformly (choose_ids); every one of them has a truth row at every step.
//
// ── Views ────────────────────────────────────────────────────────────────────────────────────────
// Each recording gets `views` fixed cameras, "cam0" … , placed around the bounding box of all its
// positions, [x₀, x₁] × [y₀, y₁] with centre c and half sizes w, h. The ellipse with semi-axes √2·w,
// √2·h through the box's corners encloses it; camera k stands outside it on the ellipse
//   c + ((√2 w + s_k) cos α_k, (√2 h + s_k) sin α_k),
//   α_k = α₀ + 2πk/V + U[−view_angle_jitter, view_angle_jitter],  α₀ ~ U[0, 2π),
//   s_k ~ U[min_view_standoff, max_view_standoff],
// at height U[min_sensor_height, max_sensor_height], with a noise scale g_k ~ U[min_noise_scale,
// max_noise_scale]. Cameras see the whole scene (no field-of-view limit); they miss pedestrians only
// through the detection probability below. sensor_x/y/z of every measurement is its camera's position.
//
// ── Measurement noise (unbiased part, in R) ──────────────────────────────────────────────────────
// The line-of-sight model of the synthetic benchmark (synthetic.hpp, line_of_sight_noise), with this
// benchmark's parameters: for a camera at s and a pedestrian at p, r = ‖p − s‖ and the basis
// U = [along, horizontal across, vertical across] of the line of sight,
//   σ_r = g (a_r + b_r r²),   σ_c = g (a_c + b_c r),   σ_v = g (a_v + b_v r),
//   R = U diag(σ_r², σ_c², σ_v²) Uᵀ,
// which is how a ground-plane camera's foot-point error behaves: angular (across) error grows with r,
// depth (along) error with r² (a pixel of image row spans more ground the flatter the ray). The noise
// is e ~ N(0, R) (draw_gaussian_error), so the NEES eᵀ R⁻¹ e of the unbiased errors is χ²₃ (mean 3).
//
// ── Registration bias (not in R) ─────────────────────────────────────────────────────────────────
// A camera's registration to the world (extrinsics or ground homography) is never exact; its error
// shifts all of that camera's ground-plane measurements together. Per instance and camera,
//   b = (σ_b ξ₁, σ_b ξ₂, 0),  ξ ~ N(0, I₂),   σ_b = registration_bias_m (0 = off),
// and the measurement is z = p + b + e with the R above (R does not include b). With the bias the
// mean NEES of the raw measurements rises above 3 by E[bᵀR⁻¹b] = σ_b² E[(R⁻¹)_xx + (R⁻¹)_yy].
//
// ── Misses ───────────────────────────────────────────────────────────────────────────────────────
// Detected with probability P_d(r) = P_near − (P_near − P_far)(r / max_range)² for r ≤ max_range,
// 0 beyond (synthetic.hpp, detection_probability), independently per camera, pedestrian and step.
// A missed pedestrian has no measurement row for that camera and step; its truth row is still there.
//
// ── Random streams ───────────────────────────────────────────────────────────────────────────────
// root = RandomStream(seed). Cameras of recording N: root.child("views").child(N). Split S ("train",
// "val", "test"): windows drawn from root.child(S).child("windows"); instance k from
// I = root.child(S).child(k): pedestrians from I.child("objects"), biases from I.child("bias") (camera
// by camera: ξ₁, ξ₂), camera v's misses and noise from I.child("sensing").child(v) (step by step,
// pedestrian by pedestrian: one detection draw, then three normals when detected).
//
// ── Clocks and latency ───────────────────────────────────────────────────────────────────────────
// Off by default. With options.clocks asynchronous and/or a latency, every split goes through
// apply_view_clocks (view_clocks.hpp) with T = 0.4 s; a track beyond the window is the recording's
// own samples of the pedestrian at the frame before the window and the two after it where they
// exist, else extrapolated linearly. The description then has a "clocks" entry.
//
// ── Output ───────────────────────────────────────────────────────────────────────────────────────
// Scenes "ethucy-<split>-NNNN" (instance k of the split); t = f / 2.5 Hz with f the recording's frame
// index (frame_id / 10), so times are the recording's own; objects "<recording short name>-<pedestrian>"
// ("eth-17", "students001-5"); views "cam0" …. Measurement rows are sorted by (scene, t, view index,
// object) and truth rows by (scene, t, object); scene order is instance order and view order index
// order, which are the string orders below 10000 instances and up to 10 views. benchmark.json records
// the source files, the seed, every option, the leave-one-out scene table, per recording its frame
// range, size, bounding box and cameras, per split its recordings with frame ranges, eligible windows
// and instances, and the models.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/eth_ucy.hpp"
#include "stgf/datasets/synthetic.hpp"
#include "stgf/datasets/view_clocks.hpp"

namespace stgf {

struct EthUcyOptions {
  // ── Source and shape ──
  std::uint64_t seed = 1;                         // every random draw derives from it
  std::string source_directory;                   // folder with the eight ETH/UCY files (the CLI's default:
                                                  //   the shipped data/eth_ucy)
  std::string test_scene = "eth";                 // eth | hotel | univ | zara1 | zara2: the held-out scene
  // Instances per split; 0 = one per eligible window. Defaults: 3000 train and 500 val fit in every
  // leave-one-out pool without repeating a window (12 steps, ≥ 2 pedestrians: 3202–3721 train and
  // 577–633 val windows depending on the test scene), and the test split takes every window of the
  // test scene once (404 eth, 614 hotel, 963 univ, 768 zara1, 990 zara2), as leave-one-out evaluation
  // usually does.
  int train_instances = 3000;
  int val_instances = 500;
  int test_instances = 0;
  int steps = 12;       // frames per instance (0.4 s each; 12 = 4.8 s); ≥ 8, Social-GAN's observed length
  int min_objects = 2;  // a window is eligible with at least this many pedestrians present throughout (≥ 1)
  int max_objects = 8;  // an instance keeps at most this many of them (≥ min_objects); fewer when fewer
                        //   are present, so instances are ragged
  double val_fraction = 0.15;  // last share of each training recording's frames that goes to val, in (0, 1)

  // ── Cameras (per recording, fixed for all its instances) ──
  int views = 4;                        // cameras per recording (≥ 1)
  double min_view_standoff_m = 2.0;     // how far outside the box-enclosing ellipse a camera stands,
  double max_view_standoff_m = 6.0;     //   uniform in [min, max] (m)
  double view_angle_jitter_rad = 0.25;  // ± uniform jitter of each camera's angle around the scene (rad)
  double min_sensor_height_m = 3.0;     // camera height, uniform in [min, max] (m)
  double max_sensor_height_m = 8.0;
  double min_noise_scale = 0.7;  // per-camera factor g on all noise standard deviations,
  double max_noise_scale = 1.4;  //   uniform in [min, max]

  // ── Measurement noise: σ_r = g (a_r + b_r r²), σ_c = g (a_c + b_c r), σ_v = g (a_v + b_v r) ──
  double range_noise_m = 0.05;          // a_r: along-range standard deviation at range 0 (m)
  double range_noise_per_m2 = 5e-4;     // b_r: growth with range squared (1/m); σ_r = 0.25 m at 20 m
  double cross_noise_m = 0.03;          // a_c: horizontal across-range standard deviation at range 0 (m)
  double cross_noise_per_m = 0.005;     // b_c: growth with range (rad); σ_c = 0.13 m at 20 m
  double vertical_noise_m = 0.03;       // a_v: vertical across-range standard deviation at range 0 (m)
  double vertical_noise_per_m = 0.004;  // b_v: growth with range (rad); σ_v = 0.11 m at 20 m

  // ── Misses: P_d(r) = P_near − (P_near − P_far)(r/max_range)², 0 beyond max_range ──
  double max_range_m = 50.0;                 // no detection beyond this range (m)
  double detection_probability_near = 0.98;  // P_near: at range 0
  double detection_probability_far = 0.7;    // P_far: at max_range

  // ── Registration bias (not in R): b = (σ_b ξ₁, σ_b ξ₂, 0) per instance and camera ──
  double registration_bias_m = 0.05;  // σ_b, per horizontal axis (m); 0 = off. A few centimetres is a
                                      //   good surveyed camera registration on the ground plane

  // ── Clocks and latency (view_clocks.hpp); the defaults leave the data synchronous, no arrivals ──
  ViewClockOptions clocks = {};
};

// Throws std::invalid_argument naming the first option out of range and its value.
void validate_ethucy_options(const EthUcyOptions& options);

// The cameras of one recording (from root.child("views").child(recording.name)); ids "cam0", ….
// Validates the options.
std::vector<SyntheticView> place_ethucy_views(const EthUcyOptions& options, const Recording& recording);

// Reads options.source_directory (read_eth_ucy_folder) and builds the benchmark.
Benchmark make_ethucy_benchmark(const EthUcyOptions& options);

// Builds the benchmark from files already read (options.source_directory is only recorded): a file
// whose scene is options.test_scene goes to test, every other file to train and val; their order is
// the pool order. std::invalid_argument when two files have the same recording name;
// std::runtime_error when a split with instances requested has no eligible window.
Benchmark make_ethucy_benchmark(const EthUcyOptions& options, std::span<const EthUcyFile> files);

}  // namespace stgf
