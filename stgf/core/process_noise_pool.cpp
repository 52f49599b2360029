// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/process_noise_pool.hpp"

#include <stdexcept>

#include "stgf/core/scene_epochs.hpp"

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
  const std::size_t epoch = scene_epoch(scene_index);
  if (epoch < pending_epoch_) throw std::logic_error("ProcessNoisePool::add: scenes out of list order");
  if (epoch > pending_epoch_) {
    committed_.add(pending_);
    committed_scenes_ += pending_scenes_;
    pending_ = ProcessNoiseEvidence{};
    pending_scenes_ = 0;
    pending_epoch_ = epoch;
  }
  pending_.add(evidence);
  ++pending_scenes_;
}

std::optional<ProcessNoiseEvidence> ProcessNoisePool::evidence_for(std::size_t scene_index) const {
  const bool with_pending = pending_epoch_ < scene_epoch(scene_index);
  if (committed_scenes_ + (with_pending ? pending_scenes_ : 0) == 0) return std::nullopt;
  ProcessNoiseEvidence sum = committed_;
  if (with_pending) sum.add(pending_);
  return sum;
}

ProcessNoisePool::Scales ProcessNoisePool::scales() const {
  ProcessNoiseEvidence sum = committed_;
  sum.add(pending_);
  const auto of = [](const ProcessNoiseScale::Grid& grid) -> std::optional<Vector3d> {
    for (const auto& axis : grid) {
      for (const double value : axis) {
        if (value != 0.0) return ProcessNoiseScale(grid).scales();
      }
    }
    return std::nullopt;
  };
  return {of(sum.followed), of(sum.fallback), of(sum.coasting)};
}

}  // namespace stgf
