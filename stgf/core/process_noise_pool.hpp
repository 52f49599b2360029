// SPDX-License-Identifier: Apache-2.0
#pragma once
// Q's scales λ learned across scenes (design §1.2, `process_noise_scale: across-scenes`). Each scene
// learns λ from its own innovations (process_noise_scale.hpp), starting at 1: Q as calibrated. On
// motion unlike the training data's (vehicles for a model of pedestrians: Q a hundred times too small)
// a short scene ends before its λ has grown to fit, and its covariance is too narrow all along. The
// scenes of one run come from the same sensors and the same kind of objects: their innovations' log
// likelihoods of λ add up. This pool sums them, scene by scene in list order, for each of the three
// scales a scene keeps (Φ's, constant velocity's where the scene follows it, and the coasting tracks'),
// and a scene starts from the sum of the scenes of earlier *epochs* (scene_epochs.hpp) added to its
// prior, so that its scales depend on its place in the list only — not on
// how the list was cut into parts or blocks, nor on threads. The scene's own innovations then add to
// that start as before.
//
// Assumption: the run's scenes share how far their motion departs from Q (the same λ fits them all,
// up to what each scene's own innovations add). The summed evidence of many scenes holds λ near its
// maximum-likelihood value over the run; a scene whose motion is harder than the rest's still widens
// its own Q, since λ only grows from there as its innovations demand. Started from that sum, λ may
// fall below 1 or is held at 1 and above (ProcessNoiseScale's `below_one`: the caller's choice,
// `process_noise_scale: across-scenes` or `grow-across-scenes`).

#include <cstddef>
#include <optional>

#include "stgf/core/process_noise_scale.hpp"
#include "stgf/core/scene_epochs.hpp"

namespace stgf {

// What a scene's innovations said of each of its Q scales (log likelihoods on ProcessNoiseScale's grid).
struct ProcessNoiseEvidence {
  ProcessNoiseScale::Grid followed{};    // Φ's λ
  ProcessNoiseScale::Grid fallback{};    // constant velocity's λ (motion_choice.hpp)
  ProcessNoiseScale::Grid coasting{};    // the coasting tracks' λ (design §1.9)
  void add(const ProcessNoiseEvidence& other);
};

class ProcessNoisePool {
 public:
  // `below_one`: whether the scenes that start from the pool may take λ below 1 (false: held at 1 and
  // above, Q at least as calibrated).
  explicit ProcessNoisePool(bool below_one = true) : below_one_(below_one) {}
  bool below_one() const { return below_one_; }
  // Adds the evidence of the scene at `scene_index` in the list. Scenes must come in list order of epochs.
  void add(std::size_t scene_index, const ProcessNoiseEvidence& evidence);
  // What the scene at `scene_index` starts from: the sum over the scenes of the epochs before its own;
  // none in the first epoch.
  std::optional<ProcessNoiseEvidence> evidence_for(std::size_t scene_index) const;
  // λ̂ of each of the three scales from every scene added so far: what the run's scenes together said
  // of Q, held at 1 and above where the scenes were (below_one()); none for a scale no innovation
  // taught (e.g. Φ's where every track coasted).
  struct Scales {
    std::optional<Vector3d> followed, fallback, coasting;
  };
  Scales scales() const;

 private:
  bool below_one_;
  EpochSums<ProcessNoiseEvidence> sums_;
};

}  // namespace stgf
