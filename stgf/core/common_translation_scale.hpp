// SPDX-License-Identifier: Apache-2.0
#pragma once
// The size of the translation common to a scene's views, from the run's scenes (design §1.7, "What is
// left at 5×"). No disagreement shows the offset common to all of a scene's views; the filter keeps it
// in every position's covariance at the scene's own scale κ̂_t (registration_prior_scale.hpp): with n
// views whose relative offsets are resolved, their mean translation has the covariance
//     diag(σ_t²) κ̂_t / n,
// σ_t the calibration's. But κ̂_t is learned from the relative offsets alone — n draws, which for
// Gaussian offsets are independent of their mean — so a scene whose views happen to agree gets a small
// κ̂_t and states its common offset too small, and NEES, a mean of κ/κ̂ over the scenes, rises wherever
// κ̂_t scatters (mpl val with 5× the calibration error: x, y NEES 3.04 in the fifth of the scenes with
// the lowest κ̂_t, 2.05–2.41 in the others). The scenes of one run come from the same sensors, so the
// median of the κ̂_t of the scenes before, κ̂_run, is a steadier estimate of that size (a median, not
// the scenes' summed likelihood, which the offsets' misfit inflates: registration_scale_pool.hpp). Where
// a scene's κ̂_t is below it, the estimates it reports carry
//     diag(σ_t²) (κ̂_run − κ̂_t) / n
// more. Reported covariances only: the filter's state, its estimates and what it feeds back to the
// motion model are unchanged. Never less than the filter states: a scene whose κ̂_t is above κ̂_run has
// shown larger relative offsets, which its own estimate accounts for.
//
// Like the pools, a scene takes the median of the scenes of the epochs before its own
// (scene_epochs.hpp), so what it reports depends on its place in the list only; none before
// kMinimumScenes scenes. Assumption: every scene's views share one size of offset (as
// registration_prior_scale.hpp). A run keeps one for scenes of fixed sensors and one for those whose
// sensors move (filter_runner.hpp); a streaming filter, which sees one scene, has none.

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace stgf {

using Eigen::Matrix3d;
using Eigen::Vector3d;

class CommonTranslationScale {
 public:
  static constexpr std::size_t kMinimumScenes = 8;

  // A scene's final κ̂_t (relative to the calibration), the scene at `scene_index` in the list; scenes
  // in list order of epochs (std::logic_error otherwise).
  void add(std::size_t scene_index, double translation_scale);
  // κ̂_run for the scene at `scene_index`: the median of the κ̂_t of the scenes of earlier epochs;
  // none while they are fewer than kMinimumScenes.
  std::optional<double> run_scale_for(std::size_t scene_index) const;

 private:
  struct Added {
    std::size_t epoch;
    double scale;
  };
  std::vector<Added> added_;  // in list order of epochs
};

// diag(σ_t²) (κ̂_run − κ̂_t)₊ / n: what a scene of `views` views with the scale `scene_scale` adds to the
// covariance it reports (zero without views).
Matrix3d common_translation_addition(const Vector3d& translation_sigma, double run_scale, double scene_scale,
                                     std::size_t views);

}  // namespace stgf
