// SPDX-License-Identifier: Apache-2.0
#pragma once
// The mpl benchmark (DESIGN §5): real pedestrian trajectories of PETS 2009 S2.L1 seen by the seven
// real, calibrated cameras of that sequence (views 1 and 3–8), each measuring a person's foot point
// on the ground with pixel noise, through a calibration that is slightly wrong. It stands in for the
// paper's "MPL" data (not public) and has the paper's shape: instances of 4 pedestrians × 7 views,
// 20 steps at 7 Hz, 1500 / 1000 / 2000 train / val / test instances.
//
// ── Truth ────────────────────────────────────────────────────────────────────────────────────────
// The world trajectories of pets2009.hpp: the view-1 annotations' foot pixels back-projected
// through the View_001 calibration onto the ground z = 0 (metres, PETS world frame), 7 Hz. The FILE
// calibrations define this world; what the cameras measure is simulated from it.
//
// ── Splits and instances ─────────────────────────────────────────────────────────────────────────
// The recording's frames [first, last] are cut into three contiguous ranges, train then val then
// test, in proportion to the requested instance counts (boundaries rounded to the nearest frame), so
// the splits are disjoint in time. An instance is `steps` consecutive frames inside one split's
// range (windows never cross a boundary) with `pedestrians` people present in every one of them:
// its window is drawn uniformly among all eligible windows of the split (windows_with_objects), its
// people uniformly among those present throughout the window (choose_ids). The ranges are short
// (≈ 265 / 177 / 353 frames at the defaults), so instances of a split overlap in time and share
// people; they differ in who is chosen, in the noise and in the calibration errors. Instance k of
// split S is scene "mpl-S-kkkk" ("mpl-train-0000"), at times t = frame / 7 s (recording time).
//
// ── Cameras ──────────────────────────────────────────────────────────────────────────────────────
// View v ("view1", "view3", …) has its FILE camera (calibration/View_00v.xml, what a user of the
// benchmark has) and, in each instance, a TRUE camera: the file camera turned by ε about its own
// axes and moved by δ (TsaiCamera::with_pose_error) with
//   ε ~ N(0, σ_rot² I₃)  (σ_rot = calibration_rotation_error_deg),
//   δ ~ N(0, σ_pos² I₃)  (σ_pos = calibration_translation_error_m),
// drawn independently for every instance and every camera. A real camera network has one fixed
// calibration error per camera; drawing it afresh per instance makes it an unknown bias of each view
// in each instance rather than a fixed offset that a method could learn from the training split and
// subtract. The calibration error is NOT in R: it is the part of the error a user cannot know.
// σ_rot = σ_pos = 0 turns it off (true camera = file camera).
//
// ── What a camera measures ───────────────────────────────────────────────────────────────────────
// At each step, for each chosen person at true foot point p (z = 0) and each view v:
//   visible   the TRUE camera has p in front of it, within its distortion model's domain, and
//             projects it inside its image (0 ≤ u < width, 0 ≤ v < height), pixel q;
//   detected  with probability detection_probability (independently per view, person and step);
//   pixel     q̃ = q + (σ_u ξ_u, σ_v ξ_v), ξ ~ N(0, 1) (the detector's foot-point error);
//   position  (x, y) = the FILE camera's back-projection of q̃ onto z = 0 (what the user computes),
//             z = σ_z ξ_z (the foot's height above the modelled ground plane);
//   R         ⎡ J diag(σ_u², σ_v²) Jᵀ   0   ⎤ ,  J = ∂(x, y)/∂(u, v) of the FILE camera at q̃
//             ⎣ 0                       σ_z²⎦    (TsaiCamera::ground_jacobian),
//   sensor    the FILE camera centre (metres).
// J grows with range and with how grazing the line of sight is, so R is anisotropic (long along the
// line of sight) and grows with distance: σ along the range ≈ (H² + D²)/H · σ_v · d'_y/f for a camera
// at height H and horizontal distance D. In the rare case that q̃'s line of sight does not reach the
// ground (the noise lifted a far point above the horizon), the measurement is dropped and counted in
// the description ("rays_missing_the_ground"); with the PETS cameras and the default noise it does not
// happen.
//
// NEES. With the calibration error off, (x, y) − p ≈ −J (q̃ − q) to first order, so the raw
// measurements' NEES (z − p)ᵀ R⁻¹ (z − p) is χ²(3): mean 3. Checked over every camera at the default
// noise: the ground points of PETS are 3–100 m from the cameras at depression angles of 3.3° (view 4,
// 76–102 m away, f = 18.6 mm) to 35°, and the second-order term of the back-projection relative to
// the first, ≈ cot(depression) · σ_v · d'_y/f, stays below 0.05 — no range limit is needed for R to
// hold. View 7's calibration (κ₁ = −0.062/mm²) folds near its image corners; the foot points it sees
// stay more than 35 pixels inside the fold and their NEES holds too.
//
// ── Defaults and why ─────────────────────────────────────────────────────────────────────────────
// σ_u = 2 px, σ_v = 3 px: a pedestrian detector's box on PETS-sized people (53–153 px tall at
//   768×576) places the box's horizontal centre within a couple of pixels; its bottom edge (feet,
//   shadows, occluded legs, box-height jitter) is less precise. A pixel is d'_y/f = 0.25 mrad (view 4)
//   to 1.35 mrad (view 8) of viewing angle, so 3 px in v is 0.75–4 mrad, i.e. from a few centimetres
//   (near the low cameras) to about 1.4 m (view 4 at 100 m, view 8 at 20 m) on the ground.
// σ_z = 0.05 m: the ground is not exactly a plane, and the foot point is not exactly on it. Its
//   only job is to make R a proper 3×3 covariance; it carries no information the views lack.
// detection_probability = 0.95: occasional detector misses (occlusion is not modelled).
// σ_rot = 0.05° per axis, σ_pos = 0.02 m per axis: a Tsai calibration from surveyed ground points
//   reprojects to about a pixel, and a pixel is 0.84 mrad (0.05°) in view 1 and 0.25–1.35 mrad in the
//   others; camera positions and the ground plane are surveyed to a few centimetres. On the ground this
//   is a bias of 0.1–0.2 m for views 1 and 3 and for the low cameras 5–8 (about 2 m above the ground,
//   so 2 cm of height error alone moves a point 1% of its distance), and about 1 m for view 4 (90 m
//   away at 4° depression, where 0.05° is 3.5 of its pixels) — comparable to the pixel noise, so it
//   matters for fusion without dominating it. Measured on the full-size benchmark (seed 7): mean raw
//   NEES 3.00 with the calibration error off and 4.65 with these defaults (7.4 for view 4, 3.7–4.5
//   for the others); 0.1° and 0.05 m would give 11.
//
// ── Random streams ───────────────────────────────────────────────────────────────────────────────
// root = RandomStream(seed); instance k of split S: I = root.child(S).child(k); its window from
// I.child("window"), its people from I.child("pedestrians"), view v's calibration error from
// I.child("calibration").child(v) (rotation x, y, z, then translation x, y, z), view v's detections
// and noise from I.child("sensing").child(v) (per step, per person in order: the detection draw,
// then ξ_u, ξ_v, ξ_z, drawn only when visible and detected). So instances are independent of each
// other and of the instance counts, and one view's draws do not depend on the others.
//
// ── Clocks and latency ───────────────────────────────────────────────────────────────────────────
// Off by default. With options.clocks asynchronous and/or a latency, every split goes through
// apply_view_clocks (view_clocks.hpp) with T = 1/7 s; the tracks beyond an instance's window are the
// recording's own frames (the frame before the window, the two after it) where the person is
// annotated there, else linearly extrapolated. The description then has a "clocks" entry.
//
// ── Output ───────────────────────────────────────────────────────────────────────────────────────
// Measurement rows sorted by (scene, time, view, object) and truth rows by (scene, time, object);
// the truth has every chosen person at every step of its instance. The description (benchmark.json)
// records the source files, the seed, every option, the views with their camera centres, each
// split's frame range, eligible windows and instances, the dropped measurements and the model.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/recording.hpp"
#include "stgf/datasets/tsai_camera.hpp"
#include "stgf/datasets/view_clocks.hpp"

namespace stgf {

struct MplOptions {
  // ── Source and shape ──
  // Every random draw derives from the seed.
  std::uint64_t seed = 1;
  // Holds PETS2009-S2L1.xml and calibration/View_00N.xml; the CLI's default is <repo>/data/pets2009_s2l1.
  std::string source_directory;
  // Instances (scenes) per split, ≥ 0 each and ≥ 1 in all. The recording's frames are shared out
  // among train, val and test in these proportions.
  int train_instances = 1500;
  int val_instances = 1000;
  int test_instances = 2000;
  int steps = 20;                                  // consecutive 7 Hz frames per instance (≥ 1); 20 = 2.9 s
  int pedestrians = 4;                             // people per instance, present in every step (≥ 1)
  std::vector<int> views = {1, 3, 4, 5, 6, 7, 8};  // PETS cameras used (1 … 8, distinct, at least one)

  // ── Measurement noise (in R) ──
  double pixel_noise_u_px = 2.0;        // σ_u: foot-point error along image rows (pixels, > 0)
  double pixel_noise_v_px = 3.0;        // σ_v: foot-point error down image columns (pixels, > 0)
  double ground_height_noise_m = 0.05;  // σ_z: measured height above the ground plane (metres, > 0)
  double detection_probability = 0.95;  // chance that a visible person is detected (in [0, 1])

  // ── Calibration error (NOT in R), drawn per instance and camera; both 0 turn it off ──
  double calibration_rotation_error_deg = 0.05;   // σ_rot: per-axis turn of the true camera (degrees, ≥ 0)
  double calibration_translation_error_m = 0.02;  // σ_pos: per-axis shift of its centre (metres, ≥ 0)

  // ── Clocks and latency (view_clocks.hpp); the defaults leave the data synchronous, no arrivals ──
  ViewClockOptions clocks = {};
};

// Throws std::invalid_argument naming the first option out of range and its value.
void validate_mpl_options(const MplOptions& options);

// A PETS camera as the benchmark uses it.
struct MplView {
  int number = 0;                // 1 … 8
  std::string id;                // "view1"
  std::string calibration_path;  // the file it was read from
  TsaiCamera camera;             // the FILE calibration
};

// The data the benchmark is built from.
struct MplSource {
  std::string annotation_path;
  Recording recording;         // world foot points (pets2009.hpp)
  std::vector<MplView> views;  // options.views in ascending order
  nlohmann::json files;        // every file read: name within the source folder, size, 64-bit FNV-1a
};

// Reads the annotations, View_001 and the calibrations of options.views from options.source_directory
// (InputError on bad files). Validates the options.
MplSource read_mpl_source(const MplOptions& options);

// The frames [first_frame, end_frame) of a split.
struct FrameRange {
  int first_frame = 0;
  int end_frame = 0;
};

// The train, val and test frame ranges: the recording's frames [first, last + 1) cut in proportion to
// the instance counts, boundaries rounded to the nearest frame.
struct MplSplitRanges {
  FrameRange train, val, test;
};
MplSplitRanges mpl_split_ranges(const MplOptions& options, const Recording& recording);

// The whole benchmark from already-read source data (the options must match the source's views).
// Throws std::invalid_argument when a split that needs instances has no eligible window.
Benchmark make_mpl_benchmark(const MplOptions& options, const MplSource& source);

// read_mpl_source, then the benchmark.
Benchmark make_mpl_benchmark(const MplOptions& options);

}  // namespace stgf
