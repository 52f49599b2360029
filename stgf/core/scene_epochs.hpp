// SPDX-License-Identifier: Apache-2.0
#pragma once
// The epochs of a run's scenes, for what they learn together (registration_scale_pool.hpp,
// process_noise_pool.hpp): a scene starts from what the scenes of the epochs before its own said, so
// that what it starts from depends on its place in the list only — not on how the list was cut into
// parts or blocks, nor on threads. The epochs double up to kSceneEpoch scenes, then stay at that:
//     [0, 1), [1, 2), [2, 4), [4, 8), [8, 16), [16, 32), [32, 48), …
// so the second scene already starts from the first's evidence (a scene that starts from nothing but
// the calibration is as far off as without pooling, and on data unlike the training data that is
// far: on cad with a model of pedestrians, NEES about 30 in the first 16 scenes against 3–4 after),
// while later scenes wait at most kSceneEpoch − 1 scenes for the newest evidence.
//
// EpochSums keeps what the scenes said, summed: the epochs before the newest one (committed) and
// the newest one so far (pending, committed once a scene of a later epoch is added).

#include <bit>
#include <cstddef>
#include <stdexcept>

namespace stgf {

inline constexpr std::size_t kSceneEpoch = 16;

// The epoch of the scene at `scene` in the list: 0, 1, 2, 2, 3, 3, 3, 3, 4 (×8), 5 (×16), 6 (×16), …
constexpr std::size_t scene_epoch(std::size_t scene) {
  if (scene < kSceneEpoch) return scene == 0 ? 0 : static_cast<std::size_t>(std::bit_width(scene));
  return static_cast<std::size_t>(std::bit_width(kSceneEpoch - 1)) + 1 + (scene - kSceneEpoch) / kSceneEpoch;
}

// The first scene of the epoch after that of `scene`.
constexpr std::size_t scene_epoch_end(std::size_t scene) {
  if (scene < kSceneEpoch) return scene == 0 ? 1 : std::bit_floor(scene) * 2;
  return (scene / kSceneEpoch + 1) * kSceneEpoch;
}

static_assert(scene_epoch(0) == 0 && scene_epoch(1) == 1 && scene_epoch(3) == 2 && scene_epoch(8) == 4 &&
              scene_epoch(15) == 4 && scene_epoch(16) == 5 && scene_epoch(31) == 5 && scene_epoch(32) == 6);
static_assert(scene_epoch_end(0) == 1 && scene_epoch_end(1) == 2 && scene_epoch_end(3) == 4 && scene_epoch_end(15) == 16 &&
              scene_epoch_end(16) == 32 && scene_epoch_end(47) == 48);

// Evidence: default-constructible (an empty sum) with `void add(const Evidence&)`.
template <class Evidence>
class EpochSums {
 public:
  // The sum the evidence of the scene at `scene_index` in the list goes into (the scene counted).
  // Scenes must come in list order of epochs.
  Evidence& add_scene(std::size_t scene_index) {
    const std::size_t epoch = scene_epoch(scene_index);
    if (epoch < pending_epoch_) throw std::logic_error("EpochSums::add_scene: scenes out of list order");
    if (epoch > pending_epoch_) {
      committed_.add(pending_);
      committed_scenes_ += pending_scenes_;
      pending_ = Evidence{};
      pending_scenes_ = 0;
      pending_epoch_ = epoch;
    }
    ++pending_scenes_;
    return pending_;
  }

  struct Sum {
    Evidence evidence;
    std::size_t scenes = 0;
  };
  // The sum over the scenes of the epochs before that of `scene_index`: what that scene starts from.
  // Asked in list order too: for a scene of an epoch already committed that sum is gone.
  Sum before(std::size_t scene_index) const {
    const std::size_t epoch = scene_epoch(scene_index);
    if (epoch < pending_epoch_) throw std::logic_error("EpochSums::before: a scene of an epoch already committed");
    // The pending epoch is complete once a scene of a later one runs.
    return pending_epoch_ < epoch ? all() : Sum{committed_, committed_scenes_};
  }
  // The sum over every scene added so far.
  Sum all() const {
    Sum sum{committed_, committed_scenes_ + pending_scenes_};
    sum.evidence.add(pending_);
    return sum;
  }

 private:
  Evidence committed_, pending_;  // epochs before pending_epoch_, and pending_epoch_ so far
  std::size_t committed_scenes_ = 0, pending_scenes_ = 0;
  std::size_t pending_epoch_ = 0;
};

}  // namespace stgf
