// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/scene_order.hpp"

#include "stgf/io/input_bounds.hpp"

namespace stgf {

std::string group_by_scene_command(const std::string& file) {
  return "(head -n 1 " + file + " && tail -n +2 " + file + " | LC_ALL=C sort -s -t, -k1,1) > grouped.csv";
}

SceneOrderError::SceneOrderError(const std::string& file, int line, const std::string& scene, int ended_at_line)
    : InputError(file, line,
                 "scene " + quoted_excerpt(scene) + " appears again after other scenes (its rows ended at line " +
                     std::to_string(ended_at_line) +
                     "); the file is read scene by scene, so it must be grouped by scene: sort it, e.g. with `" +
                     group_by_scene_command(file) + "` when `scene` is its first column (README, Files)") {}

namespace detail {

bool SceneOrder::opens_scene(const std::string& file, int line, const std::string& scene, int previous_line) {
  if (any_ && scene == open_) return false;
  if (const auto ended = ended_.find(scene); ended != ended_.end()) {
    throw SceneOrderError(file, line, scene, ended->second);
  }
  if (any_) ended_.emplace(std::move(open_), previous_line);
  open_ = scene;
  any_ = true;
  return true;
}

}  // namespace detail
}  // namespace stgf
