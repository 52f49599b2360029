// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/view_faults.hpp"

#include <cmath>
#include <map>
#include <stdexcept>

#include "stgf/datasets/random.hpp"

#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

Vector3d horizontal(RandomStream& random, double length) {
  const portable::SineCosine angle = portable::sin_cos(random.uniform(0.0, 2.0 * portable::kPi));
  return Vector3d(length * angle.cosine, length * angle.sine, 0.0);
}

}  // namespace

std::string_view view_fault_name(ViewFaultKind kind) {
  switch (kind) {
    case ViewFaultKind::kJump: return "jump";
    case ViewFaultKind::kUnderstatedNoise: return "understated-noise";
    case ViewFaultKind::kOutliers: return "outliers";
  }
  return "?";
}

void check_view_fault_options(const ViewFaultOptions& options) {
  const auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  if (options.view.empty()) fail("--view must name a view");
  if (!(options.jump_m > 0.0) || !std::isfinite(options.jump_m)) fail("--jump-m must be a finite number > 0");
  if (!(options.understatement > 1.0) || !std::isfinite(options.understatement)) {
    fail("--understatement must be a finite number > 1");
  }
  if (!(options.outlier_fraction > 0.0 && options.outlier_fraction <= 1.0)) fail("--outlier-fraction must be in (0, 1]");
  if (!(options.outlier_min_m > 0.0) || !std::isfinite(options.outlier_max_m) ||
      options.outlier_max_m < options.outlier_min_m) {
    fail("--outlier-range-m must be two finite sizes with 0 < min <= max");
  }
}

ViewFaultSummary inject_view_fault(std::span<Measurement> rows, const ViewFaultOptions& options) {
  check_view_fault_options(options);
  struct Scene {
    double first = INFINITY;
    double last = -INFINITY;
    bool has_view = false;
  };
  std::map<std::string, Scene, std::less<>> scenes;
  for (const Measurement& row : rows) {
    Scene& scene = scenes[row.scene];
    scene.first = std::min(scene.first, row.time);
    scene.last = std::max(scene.last, row.time);
    scene.has_view = scene.has_view || row.view == options.view;
  }
  const RandomStream root = RandomStream(options.seed).child("view-faults");
  std::map<std::string, RandomStream, std::less<>> streams;
  std::map<std::string, Vector3d, std::less<>> jumps;
  ViewFaultSummary summary;
  for (const auto& [name, scene] : scenes) {
    if (!scene.has_view) continue;
    ++summary.scenes;
    RandomStream& random = streams.emplace(name, root.child(name)).first->second;
    if (options.kind == ViewFaultKind::kJump) jumps.emplace(name, horizontal(random, options.jump_m));
  }
  for (Measurement& row : rows) {
    if (row.view != options.view) continue;
    ++summary.view_rows;
    RandomStream& random = streams.at(row.scene);
    Vector3d mean = row.position.mean();
    Matrix3d covariance = row.position.covariance();
    switch (options.kind) {
      case ViewFaultKind::kJump: {
        const Scene& scene = scenes.at(row.scene);
        if (row.time < 0.5 * (scene.first + scene.last)) continue;
        mean += jumps.at(row.scene);
        break;
      }
      case ViewFaultKind::kUnderstatedNoise:
        covariance /= options.understatement;
        break;
      case ViewFaultKind::kOutliers:
        if (!random.bernoulli(options.outlier_fraction)) continue;
        mean += horizontal(random, random.uniform(options.outlier_min_m, options.outlier_max_m));
        break;
    }
    row.position = Gaussian3::from_covariance(mean, covariance);
    ++summary.changed_rows;
  }
  return summary;
}

}  // namespace stgf
