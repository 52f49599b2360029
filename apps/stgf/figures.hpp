// SPDX-License-Identifier: Apache-2.0
#pragma once
// The figures of stgf reproduce and stgf plot, drawn by gnuplot. Each figure STEM gets its data (STEM*.dat), the
// gnuplot script that draws it (STEM.gp, re-runnable by hand: `cd DIR && gnuplot STEM.gp`), and
// STEM.svg and STEM.png.
//   views curve   DE against the number of views that saw the object (paper Fig. 6), a line per
//                 method, log scale. Each method's points are shifted sideways by a few hundredths
//                 of a view (the data keep the whole numbers), so methods whose numbers coincide
//                 (wls and mmt often do) all show;
//   trajectories  one scene seen from above (x, y): the true paths against each method's estimates
//                 held by one view (paper Figs. 4–5), and around every k-th estimate of each track
//                 (k so that a track has 10–19 ellipses, see ellipse_indices) the 95 % region of the x–y
//                 marginal of the estimate's covariance, a thin closed line in the method's colour,
//                 from STEM-ellipses-METHOD.dat (one block per ellipse); the title says what they
//                 are. The plot's range is set by the paths and measurements, so an ellipse reaching
//                 past it is clipped, and one whose major semi-axis is wider than half the plot (a
//                 track's uninformed start) is left out and named in the comments of its file.
// In both, a method has the same colour, point type and dash pattern (every method stgf runs has
// its own; another name gets a fallback), and dashed lines are drawn after solid ones.

#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "stgf/core/records.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/evaluation.hpp"

namespace stgf::cli {

// Whether `gnuplot` runs; without it the data and scripts are written and the images are not.
bool gnuplot_available();

// Runs `gnuplot STEM.gp` in the figure's directory; std::runtime_error when it fails.
void run_gnuplot(const std::string& directory, const std::string& stem);

// Writes the data and script of the views curve of `evaluation` to DIRECTORY/STEM.*.
void write_views_curve(const Evaluation& evaluation, const std::string& directory, const std::string& stem,
                       const std::string& title);

// The 0.95 quantile of the chi-square distribution with 2 degrees of freedom (−2 ln 0.05): a 2-D
// Gaussian puts 95 % of its mass inside (p − mean)ᵀ covariance⁻¹ (p − mean) ≤ this.
inline constexpr double kChiSquare2Dof95 = 5.991464547107979;

// Points drawn per ellipse (the file repeats the first after them, to close the line).
inline constexpr int kEllipsePoints = 36;

// `points` points, evenly spaced in angle, on the ellipse (p − mean)ᵀ covariance⁻¹ (p − mean) =
// chi_square of a symmetric positive semi-definite 2×2 covariance: with covariance = Σ λᵢ eᵢ eᵢᵀ
// (λ₁ ≥ λ₂), point j is mean + √(chi_square λ₁) cos θⱼ e₁ + √(chi_square λ₂) sin θⱼ e₂,
// θⱼ = 2πj/points, so the semi-axes are √(chi_square λᵢ) and the first point ends the major axis.
// diag(4, 1) at (0, 0): semi-axes √(5.991·4) ≈ 4.895 along x and √5.991 ≈ 2.448 along y.
std::vector<Eigen::Vector2d> covariance_ellipse(const Eigen::Vector2d& mean, const Eigen::Matrix2d& covariance,
                                                int points = kEllipsePoints, double chi_square = kChiSquare2Dof95);

// Which of a track's `count` estimates (in time order) get an ellipse: the first and every k-th
// after it, k = max(1, ⌊count / 10⌋), so 10–19 ellipses on a track of 10 or more estimates and one
// per estimate on a shorter one.
std::vector<std::size_t> ellipse_indices(std::size_t count);

struct MethodTrajectory {
  std::string method;
  std::vector<Estimate> estimates;  // one view's estimates in one scene
};

// The scene with the most rows (ties: the first name), or `scene` when given, and in it the view
// with the most.
std::pair<std::string, std::string> busiest_scene_and_view(std::span<const Estimate> rows,
                                                           const std::string& scene = {});

// The rows of `scene` held by `view`, one trajectory per method (the method column of each file,
// in the order the methods first appear).
std::vector<MethodTrajectory> trajectories_of(std::span<const EstimateFile> files, const std::string& scene,
                                              const std::string& view);

// Writes the data and script of a trajectory plot to DIRECTORY/STEM.*: the true paths, then each
// method's (STEM-METHOD.dat) with its 95 % covariance ellipses (STEM-ellipses-METHOD.dat, see
// covariance_ellipse and ellipse_indices); `measured` (may be empty) are drawn as small grey points
// under them.
void write_trajectories(std::span<const TruthPoint> truth, std::span<const MethodTrajectory> methods,
                        const std::string& directory, const std::string& stem, const std::string& title,
                        std::span<const Measurement> measured = {});

}  // namespace stgf::cli
