// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/process_noise_pool.hpp"

#include <utility>

namespace stgf {
namespace {

void add_grid(ProcessNoiseScale::Grid& sum, const ProcessNoiseScale::Grid& grid) {
  for (std::size_t a = 0; a < sum.size(); ++a) {
    for (std::size_t point = 0; point < sum[a].size(); ++point) sum[a][point] += grid[a][point];
  }
}

}  // namespace

void ProcessNoiseEvidence::add(const ProcessNoiseEvidence& other) {
  add_grid(followed, other.followed);
  add_grid(fallback, other.fallback);
  add_grid(coasting, other.coasting);
}

void ProcessNoisePool::add(std::size_t scene_index, const ProcessNoiseEvidence& evidence) {
  sums_.add_scene(scene_index).add(evidence);
}

std::optional<ProcessNoiseEvidence> ProcessNoisePool::evidence_for(std::size_t scene_index) const {
  auto before = sums_.before(scene_index);
  if (before.scenes == 0) return std::nullopt;
  return std::move(before.evidence);
}

ProcessNoisePool::Scales ProcessNoisePool::scales() const {
  const ProcessNoiseEvidence sum = sums_.all().evidence;
  const auto of = [this](const ProcessNoiseScale::Grid& grid) -> std::optional<Vector3d> {
    for (const auto& axis : grid) {
      for (const double value : axis) {
        if (value != 0.0) return ProcessNoiseScale(grid, below_one_).scales();
      }
    }
    return std::nullopt;
  };
  return {of(sum.followed), of(sum.fallback), of(sum.coasting)};
}

}  // namespace stgf
