// SPDX-License-Identifier: Apache-2.0
#pragma once
// Files read scene by scene (`stgf run`, `stgf eval`; DESIGN §3.8) must be grouped by scene: the
// rows of each scene contiguous, scenes in any order. A reader that holds one scene at a time cannot
// fuse a scene whose rows come back after another scene started, and must not guess: such a row is
// an error at its line (SceneOrderError), with the command that groups the file.

#include <string>
#include <unordered_map>

#include "stgf/io/input_error.hpp"

namespace stgf {

// A scene's rows come again after another scene's: "FILE:LINE: scene 'X' appears again after other
// scenes (its rows ended at line L); ... group the file by scene, e.g. with ...".
class SceneOrderError : public InputError {
 public:
  SceneOrderError(const std::string& file, int line, const std::string& scene, int ended_at_line);
};

// The shell command that groups a file by scene, keeping each scene's rows in their order and the
// header first, for a file whose first column is `scene` (the writers' layout) and whose scene names
// hold no comma: (head -n 1 FILE && tail -n +2 FILE | LC_ALL=C sort -s -t, -k1,1) > grouped.csv
std::string group_by_scene_command(const std::string& file);

namespace detail {

// The scenes of a file as its rows come: which one is open, and where each earlier one ended.
class SceneOrder {
 public:
  // Row `line` of `file`, of `scene`, comes after `previous_line`, which belonged to the open scene
  // (none before the first row). Returns true when the row opens a new scene; throws SceneOrderError
  // when that scene's rows ended earlier in the file.
  bool opens_scene(const std::string& file, int line, const std::string& scene, int previous_line);

 private:
  std::string open_;
  bool any_ = false;
  std::unordered_map<std::string, int> ended_;  // scene → the line of its last row
};

}  // namespace detail
}  // namespace stgf
