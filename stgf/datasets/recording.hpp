// SPDX-License-Identifier: Apache-2.0
#pragma once
// Ground-truth trajectories of one real recording (a PETS sequence, a KITTI drive, an ETH/UCY
// scene), and the windows of it that benchmark instances are cut from (DESIGN §5).
//
// An instance of a benchmark is `steps` consecutive frames of one recording with a chosen set of
// objects, each present in every one of those frames. Builders find the windows, choose objects
// and sensors in them, and simulate the views' measurements.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/datasets/random.hpp"

namespace stgf {

struct Recording {
  std::string name;       // e.g. "PETS2009-S2L1", "kitti-0004", "biwi_eth"
  double rate_hz = 0.0;   // frames per second; frame f is at time f / rate_hz
  // frame → object id → true position (metres, world frame).
  std::map<int, std::map<std::string, Vector3d>> frames;
};

struct Window {
  int first_frame = 0;
  std::vector<std::string> present;  // ids present in every frame of the window, sorted
};

// Every window [s, s + steps) with first_frame ≤ s and s + steps ≤ end_frame whose frames all exist
// in the recording and in which at least `min_objects` objects are present throughout.
std::vector<Window> windows_with_objects(const Recording& recording, int first_frame, int end_frame, int steps,
                                         int min_objects);

// The recording's position of `id` at the frame nearest `time` (frame = round(time · rate_hz)), if the
// recording has that frame and the object in it.
std::optional<Vector3d> recording_position_at(const Recording& recording, const std::string& id, double time);

// `count` distinct ids drawn uniformly from `ids` (count ≤ ids.size()), returned in the order of `ids`.
std::vector<std::string> choose_ids(RandomStream& random, const std::vector<std::string>& ids, int count);

}  // namespace stgf
