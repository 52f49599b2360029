// SPDX-License-Identifier: Apache-2.0
#pragma once
// The figures of stgf reproduce and stgf plot, drawn by gnuplot. Each figure STEM gets its data (STEM*.dat), the
// gnuplot script that draws it (STEM.gp, re-runnable by hand: `cd DIR && gnuplot STEM.gp`), and
// STEM.svg and STEM.png.
//   views curve   DE against the number of views that saw the object (paper Fig. 6), a line per
//                 method, log scale;
//   trajectories  one scene seen from above (x, y): the true paths against each method's estimates
//                 held by one view (paper Figs. 4–5).

#include <span>
#include <string>
#include <utility>
#include <vector>

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
// method's; `measured` (may be empty) are drawn as small grey points under them.
void write_trajectories(std::span<const TruthPoint> truth, std::span<const MethodTrajectory> methods,
                        const std::string& directory, const std::string& stem, const std::string& title,
                        std::span<const Measurement> measured = {});

}  // namespace stgf::cli
