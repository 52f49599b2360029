// SPDX-License-Identifier: Apache-2.0
#pragma once
// The registration prior's scales learned across scenes (design §1.7, `registration_prior_scale:
// across-scenes`). Each scene learns κ_t, κ_n from its own views' disagreements, held near 1 by its
// prior (registration_prior_scale.hpp): short scenes cannot move far, so on sensors registered several
// times worse than the training data's the offsets' size stays short of the truth and the covariance
// too narrow. The scenes of one run come from the same sensors: their log likelihoods of the scales
// add up. This pool sums them, scene by scene in list order, and gives a scene the sum of the scenes
// of earlier *epochs* (scene_epochs.hpp), or the scales that maximise it, so that a scene's scales
// depend on its place in the list only — not on how the list was cut into parts or blocks, nor on
// threads.
//
// Grids. A scene's grid is log p(its disagreements | κ) over κ_t = 2^(k/4 − 10) (k = 0 … 80) and
// ρ = κ_n / κ_t = 2^(r − 12) (r = 0 … 24), relative to the prior it ran with. A scene that ran with
// the prior scaled by grid scales (k*, r*) is shifted to the calibration's: k + k* − 40, r + r* − 12.
// The estimate is the argmax over the points every summed scene covers (within the grid's range).
// The axis groups' scales (κ_a, κ_c, κ_v: δ along and across the rays, the vertical offsets) have a row
// each (on κ_t's grid), shifted and summed as κ_t's. As evidence all three are used; the estimate takes
// κ_v's argmax (a flat row, from scenes without vertical offsets, leaves it at 1) and sets κ_a and κ_c
// to κ_n, which a scene learns apart only from other scenes' evidence.
// Assumption: every scene's views share the two sizes of offset (as registration_prior_scale.hpp);
// with the model fitting the sensors (a moving platform's rigid pose error: sensor_motion.hpp) the
// summed likelihood peaks at their true size. A run keeps one pool for scenes of fixed sensors and one
// for scenes whose sensors move (filter_runner.hpp).
//
// Use. As evidence (`registration_prior_scale: across-scenes`; the default where the sensors move:
// sensor_motion.hpp), a scene starts from the earlier
// epochs' summed log likelihoods: they join its prior and its own disagreements in every estimate it
// makes (RegistrationPriorScale::start_from), the hierarchical posterior of one pair of scales shared
// by the run's scenes. With many scenes before it, their evidence decides; with few, the scene's own
// counts as much as any of theirs (design §1.7: cad val with the general model, the first 16 scenes'
// NEES 13.5 → 5.2 against holding each scene at the earlier scenes' argmax after 16 of them, the rest
// 4.1 → 3.8). With the translations lowered only (`shrink-across-scenes`; for a model of several
// benchmarks the default where the sensors stand still), a scene starts from the estimate with κ_t
// taken down to it only where it is below the calibration's (κ_t = 1), and every other scale (κ_n, so
// δ along and across the rays, and κ_v) taken to it either way, and learns its own from there as
// before. Why the translations only down: where the offsets do not fit the model (a camera's height
// error moves ground points along the ray in proportion to range, which a model without the range
// scale lacks), the misfit makes the views disagree more than the modelled offsets explain, and the
// summed evidence of a thousand scenes puts it into the translations, far beyond their size (design
// §1.7: mpl's cameras with 5× the calibration error, κ_t 54 against the 25 they were made with; NEES
// 0.5–0.9 with it). κ_t alone sizes the offset common to all views, which no disagreement shows and which
// then dominates every position's covariance. A misfit cannot make views agree better than their offsets
// allow, so an estimate below the calibration is the sensors' own: better registered than the
// training data (no GPS error, a finer calibration), which a short scene, held near 1 by its prior,
// cannot show alone. The offsets in units of the noise are another matter: the relative offsets
// they size are what the scene's own disagreements resolve, so an estimate too wide costs a little
// accuracy and hardly any honesty, while one held near a calibration made on other sensors (a model
// of vehicles, α 0.1, on cameras that want 0.5) weights the views wrongly all run long (design §1.7,
// 2026-12-02: the general model on mpl val with 5× the calibration error 0.1266 → 0.1126 m, NEES 2.07
// → 2.90; the model trained without mpl on mpl val 0.0365 → 0.0334, 2.42 → 2.75). Unless the model has
// a range scale (σ_ε > 0): δ along the rays and ε are then nearly one direction over a camera's ranges,
// which the disagreements cannot tell apart, and the summed evidence rides that ridge to a κ_n far
// beyond the offsets' size that leaves the disagreements nothing to size κ_t with, and so the common
// offset (mpl's model on mpl val with 5× the calibration error: κ_n 185, κ̂_t's median 6.4 against 25,
// NEES 6.70 against 2.82). There every scale is lowered only (Use::kLowerOnly), as before 2026-12-02.

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "stgf/core/registration_prior_scale.hpp"
#include "stgf/core/scene_epochs.hpp"

namespace stgf {

class RegistrationScalePool {
 public:
  enum class Use { kEvidence, kLowerOnly, kTranslationLoweredOnly };
  explicit RegistrationScalePool(Use use = Use::kEvidence) : use_(use) {}
  Use use() const { return use_; }
  // How a pool that may only lower treats a prior with this range scale σ_ε (above): the translations'
  // scale lowered only, or, with a range scale, every scale.
  static Use lowering_for(double range_scale_sigma) {
    return range_scale_sigma > 0.0 ? Use::kLowerOnly : Use::kTranslationLoweredOnly;
  }

  // The estimate is the summed likelihood's maximum, with no prior: over fewer scenes than this it is
  // too rough to start a scene from (on cad val with a model of pedestrians, scenes held at the
  // estimates of 1, 2, 4 and 8 scenes: DE 0.91 m, against 0.52 m learning per scene until 16).
  static constexpr std::size_t kFewestScenes = 16;
  static constexpr int kRatioIndices = RegistrationPriorScale::kPooledRatios;  // log2 ρ = −12 … 12
  static constexpr int kScaleIndices = RegistrationPriorScale::kGridPoints;
  static constexpr int kUnitScale = 40;     // k of κ_t = 1
  static constexpr int kUnitRatio = (kRatioIndices - 1) / 2;  // r of ρ = 1
  // A scene's grid: 25 × 81 of (ρ, κ_t), then 81 for each axis group (κ_a, κ_c, κ_v;
  // RegistrationPriorScale::log_likelihood_grid).
  static constexpr int kGridSize = RegistrationPriorScale::kPooledGridSize;
  static constexpr std::size_t kAxes = RegistrationPriorScale::kAxisGroups.size();
  static constexpr std::size_t kVerticalAxis = 2;  // κ_v's place among them
  static_assert(RegistrationPriorScale::kAxisGroups[kVerticalAxis] == RegistrationPriorScale::Group::kVertical);

  // A grid point of the scales: κ_t = 2^(scale / 4 − 10), κ_n = κ_t 2^(ratio − 12), and the axis groups'
  // (along, across, vertical: RegistrationPriorScale::kAxisGroups) 2^(axes[a] / 4 − 10).
  struct Point {
    int scale = kUnitScale;
    int ratio = kUnitRatio;
    std::array<int, 3> axes{kUnitScale, kUnitScale, kUnitScale};
    RegistrationPriorScales scales() const;
    // The point with each scale lowered to at most 1: κ_t' = min(κ_t, 1), κ_n' = min(κ_n, 1)
    // rounded down to the ratios' grid (exact where κ_t ≤ 1; else at most a factor 2^¾ below), and each
    // axis group's at most 1.
    Point lowered_to_unit() const;
    // The point with κ_t lowered to at most 1 and κ_n kept (rounded down to the ratios' grid: exact
    // where κ_t ≤ 1, else at most a factor 2^¾ below), the axis groups' as they are.
    Point translation_lowered_to_unit() const;
  };

  // Adds the grid (kRatioIndices × kScaleIndices, ratio-major, then kScaleIndices of κ_v) of the scene
  // at `scene_index` in the list, which ran with the prior scaled by `applied` (as calibrated: Point{}).
  // Scenes must come in list order of epochs.
  void add(std::size_t scene_index, std::span<const double> grid, Point applied);
  // The scales for the scene at `scene_index`: the argmax over the scenes of the epochs before its
  // own (Use::kLowerOnly: lowered_to_unit of it; Use::kTranslationLoweredOnly: translation_lowered_to_unit
  // of it); none while they are fewer than kFewestScenes (counting those with disagreements only).
  std::optional<Point> estimate_for(std::size_t scene_index) const;
  // Use::kEvidence: the summed log likelihoods of the scenes of the epochs before its own, on a scene's
  // grid (25 × 81, ratio-major, and 3 × 81 of the axis groups), for it to start from
  // (RegistrationPriorScale::start_from); none before any scene. Every scene must have run with the
  // calibration's prior (added with Point{}).
  std::optional<std::vector<double>> evidence_for(std::size_t scene_index) const;

 private:
  static constexpr int kScaleSpan = kScaleIndices + 2 * kUnitScale;  // k + k* − 40 ∈ [−40, 120]
  static constexpr int kRatioSpan = kRatioIndices + 2 * kUnitRatio;  // r + r* − 12 ∈ [−12, 36]
  // The scenes' shifted grids summed, and at each point how many of them cover it.
  struct Evidence {
    std::vector<double> log_likelihood = std::vector<double>(kScaleSpan * kRatioSpan, 0.0);
    std::vector<std::size_t> covered = std::vector<std::size_t>(kScaleSpan * kRatioSpan, 0);
    // The axis groups' rows, shifted as κ_t's.
    std::array<std::vector<double>, 3> axes{std::vector<double>(kScaleSpan, 0.0), std::vector<double>(kScaleSpan, 0.0),
                                            std::vector<double>(kScaleSpan, 0.0)};
    std::array<std::vector<std::size_t>, 3> axes_covered{std::vector<std::size_t>(kScaleSpan, 0),
                                                         std::vector<std::size_t>(kScaleSpan, 0),
                                                         std::vector<std::size_t>(kScaleSpan, 0)};
    void add(const Evidence& other);
  };
  Use use_;
  EpochSums<Evidence> sums_;
};

}  // namespace stgf
