// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/recording.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace stgf {

std::optional<Vector3d> recording_position_at(const Recording& recording, const std::string& id, double time) {
  const auto frame = recording.frames.find(static_cast<int>(std::lround(time * recording.rate_hz)));
  if (frame == recording.frames.end()) return std::nullopt;
  const auto position = frame->second.find(id);
  if (position == frame->second.end()) return std::nullopt;
  return position->second;
}

std::vector<Window> windows_with_objects(const Recording& recording, int first_frame, int end_frame, int steps,
                                         int min_objects) {
  if (steps < 1) throw std::invalid_argument("windows_with_objects: steps must be >= 1");
  std::vector<Window> windows;
  for (int start = first_frame; start + steps <= end_frame; ++start) {
    std::vector<std::string> present;
    bool complete = true;
    for (int frame = start; frame < start + steps && complete; ++frame) {
      const auto it = recording.frames.find(frame);
      if (it == recording.frames.end()) {
        complete = false;
        break;
      }
      std::vector<std::string> here;
      for (const auto& [id, position] : it->second) here.push_back(id);  // sorted: std::map order
      if (frame == start) {
        present = std::move(here);
      } else {
        std::vector<std::string> both;
        std::set_intersection(present.begin(), present.end(), here.begin(), here.end(), std::back_inserter(both));
        present = std::move(both);
      }
      if (static_cast<int>(present.size()) < min_objects) complete = false;
    }
    if (complete) windows.push_back(Window{start, std::move(present)});
  }
  return windows;
}

std::vector<std::string> choose_ids(RandomStream& random, const std::vector<std::string>& ids, int count) {
  if (count < 0 || count > static_cast<int>(ids.size())) throw std::invalid_argument("choose_ids: bad count");
  // Selection sampling (Knuth's Algorithm S): keeps the order of `ids`, one uniform draw per id.
  std::vector<std::string> chosen;
  int needed = count;
  for (std::size_t k = 0; k < ids.size() && needed > 0; ++k) {
    const auto remaining = static_cast<double>(ids.size() - k);
    if (random.uniform01() * remaining < needed) {
      chosen.push_back(ids[k]);
      --needed;
    }
  }
  return chosen;
}

}  // namespace stgf
