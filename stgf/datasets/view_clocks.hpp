// SPDX-License-Identifier: Apache-2.0
#pragma once
// Per-view clocks and message latency for any benchmark (DESIGN §5), applied to a split that a
// builder has made synchronous — every view measuring at the frame times t_k = t_0 + k·T — so that
// all four builders (synthetic, mpl, cad, ethucy) get the same model from one implementation.
// Real camera networks and connected vehicles sample on their own clocks, and their messages reach
// the fuser late.
//
// ── Clocks (asynchronous) ────────────────────────────────────────────────────────────────────────
// A message is what view v of scene s sends for frame k: its measurements of every object it
// detected in that frame, all at one time (a camera images all its objects in one exposure). It is
// measured at
//   t'(s, v, k) = µs( t_k + φ_{s,v} + j_{s,v,k} ),
//     φ_{s,v}  ~ U[0, T)             the view's phase in this scene (T = the frame period),
//     j_{s,v,k} ~ N(0, σ²) truncated to |j| ≤ 0.45 T (redrawn beyond; σ = jitter_s < T/10, so a
//                                   redraw is a 4.5σ event), the message's timing jitter,
//     µs(x)    x rounded to the microsecond, the resolution at which the files store times.
// Then, per scene, message times that are 1 µs apart (two views that happened to fire within a
// microsecond) are merged into the earlier one, so that any two distinct times of a scene are at
// least 2 µs apart — never within the 1e-6 s that makes two times one step, and never a duplicate
// truth row. Consequences: the times of one (scene, view, object) are distinct and increase with k
// (consecutive ones are at least 0.1 T apart); a message can lie up to 0.45 T before its frame
// time and up to 1.45 T after it.
//
// Each measurement row moves with its object: for a row of frame time t_k measuring object o,
//   t ← t',   z ← z + (p_o(t') − p_o(t_k)),   R and the sensor position unchanged,
// where p_o is the object's true track. So z − p_o(t) — the noise, the registration or
// calibration bias and the misses — is exactly what the synchronous builder drew (to rounding,
// 1e-12 m); only the time at which the object is seen changes. (The sensor position stays the one
// of frame k: for moving sensors — cad's vehicles — it is up to 0.45·T of motion off.)
//
// p_o(τ): the track is the split's truth rows of (s, o) — the frames of the instance window — plus,
// when the builder passes a TrackBeyondWindow, the recording's positions of the object at the frame
// before the window and at the two frames after it, each used only if the recording has the object
// there (and the second after only if the first is there). Between two known frames p_o is linear
// in τ; at a known frame it is that frame's position exactly; before the first known frame and after
// the last it is extrapolated linearly from the two nearest known frames (held constant when only
// one frame is known). The mpl, cad and ethucy builders pass their recording; synthetic does not
// (its walkers do not exist beyond the scene), so its tracks are extrapolated.
//
// The truth of an asynchronous split is p_o(t') at every distinct measured (s, t', o): one row per
// distinct time a view measured the object, sorted by (scene, time, object), and nothing else (no
// frame-time rows: every scored row has its truth, and the files stay free of near-duplicate times).
//
// ── Latency ──────────────────────────────────────────────────────────────────────────────────────
// latency_s = S > 0 gives every row an arrival time (the `arrival` column):
//   arrival(s, v, k) = t'(s, v, k) + U[0, S),   one draw per message (all its rows arrive together).
// It works with and without asynchronous clocks (without, t' = t_k).
//
// ── Random streams ───────────────────────────────────────────────────────────────────────────────
// From the benchmark's root stream R = RandomStream(seed), through children no builder draws from,
// so every existing draw is untouched:
//   clocks of (s, v):  R.child("clocks").child(s).child(v): φ = uniform(0, T), then j for k = 0, 1, …
//                      over every frame of the scene, whether or not the view measured in it;
//   latency of (s, v): R.child("latency").child(s).child(v): one uniform(0, S) per frame k = 0, 1, ….
// So a view's times do not depend on the other views, on its detections, or on the instance
// counts; the phases are not listed per scene in benchmark.json (4500 scenes × 7 views for mpl) but
// are reproducible from the seed this way; the description has a summary of them per split.
//
// ── Output ───────────────────────────────────────────────────────────────────────────────────────
// Measurement rows are sorted by (scene, time) keeping the builder's order — view, then object —
// among rows of one time; scenes stay in the builder's order. When the clocks are synchronous and
// the latency 0, apply_view_clocks changes nothing and the builders add no "clocks" entry to the
// description: the files are byte-identical to a build without these options.

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "stgf/core/gaussian.hpp"
#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/option_checks.hpp"
#include "stgf/datasets/random.hpp"

namespace stgf {

struct ViewClockOptions {
  bool asynchronous = false;  // each view on its own clock: phase φ ~ U[0, T) and jitter
  double jitter_s = 0.002;    // σ of each message's timing jitter (seconds; 0 ≤ σ < T/10; asynchronous only)
  double latency_s = 0.0;     // arrival = t' + U[0, latency_s) (seconds, ≥ 0); 0: no arrival column

  // Anything to do: asynchronous clocks or a latency.
  bool active() const { return asynchronous || latency_s > 0.0; }
};

// Checks the options of a benchmark whose frame period is `frame_period_s` (std::invalid_argument
// through `check`, naming jitter_s or latency_s). The jitter is checked only when asynchronous.
void check_view_clock_options(const OptionChecks& check, const ViewClockOptions& options, double frame_period_s);

// The true position of `object` of `scene` at `frame_time`, a frame time just outside the scene's
// truth rows (one frame before them, one or two after), when the builder's recording has it there.
using TrackBeyondWindow =
    std::function<std::optional<Vector3d>(const std::string& scene, const std::string& object, double frame_time)>;

// Moves a synchronous split to per-view clocks and/or adds arrivals (see above). `root` is the
// benchmark's root stream, RandomStream(seed). Returns the split's entry of the description's
// "clocks" → "splits" (counts and a summary of the phases, jitters and latencies); null when the
// options are not active (and the split is left as it was). Throws std::invalid_argument for bad
// options, when two rows of a (scene, view, object) share a frame, or (asynchronous) when a measured
// object has no truth rows in its scene.
nlohmann::json apply_view_clocks(BenchmarkSplit& split, const ViewClockOptions& options, double frame_period_s,
                                 const RandomStream& root, const TrackBeyondWindow& track_beyond_window = {});

// The description's "clocks" entry: the options, the frame period, the model in words, and the
// splits' entries from apply_view_clocks (an object "train"/"val"/"test" → entry).
nlohmann::json view_clocks_json(const ViewClockOptions& options, double frame_period_s, nlohmann::json splits);

}  // namespace stgf
