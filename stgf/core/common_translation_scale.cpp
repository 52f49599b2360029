// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/common_translation_scale.hpp"

#include <algorithm>
#include <stdexcept>

#include "stgf/core/scene_epochs.hpp"

namespace stgf {

void CommonTranslationScale::add(std::size_t scene_index, double translation_scale) {
  const std::size_t epoch = scene_epoch(scene_index);
  if (!added_.empty() && epoch < added_.back().epoch) {
    throw std::logic_error("CommonTranslationScale::add: scenes out of list order");
  }
  added_.push_back({epoch, translation_scale});
}

std::optional<double> CommonTranslationScale::run_scale_for(std::size_t scene_index) const {
  const std::size_t epoch = scene_epoch(scene_index);
  std::vector<double> before;
  for (const Added& added : added_) {
    if (added.epoch < epoch) before.push_back(added.scale);
  }
  if (before.size() < kMinimumScenes) return std::nullopt;
  // The median: the middle one, or the mean of the middle two.
  const std::size_t middle = before.size() / 2;
  std::nth_element(before.begin(), before.begin() + static_cast<std::ptrdiff_t>(middle), before.end());
  const double upper = before[middle];
  if (before.size() % 2 == 1) return upper;
  const double lower =
      *std::max_element(before.begin(), before.begin() + static_cast<std::ptrdiff_t>(middle));
  return 0.5 * (lower + upper);
}

Matrix3d common_translation_addition(const Vector3d& translation_sigma, double run_scale, double scene_scale,
                                     std::size_t views) {
  if (views == 0 || !(run_scale > scene_scale)) return Matrix3d::Zero();
  const Vector3d variance = translation_sigma.cwiseProduct(translation_sigma);
  return ((run_scale - scene_scale) / static_cast<double>(views) * variance).asDiagonal();
}

}  // namespace stgf
