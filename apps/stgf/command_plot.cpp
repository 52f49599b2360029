// SPDX-License-Identifier: Apache-2.0
// stgf plot --truth T --estimates E [E2 ...] --out DIR [--measurements M] [--scene S] [--view V]
//           [--from-step K | --from-time S] [--name NAME]
//
// Draws any estimate files, whatever made them: NAME-trajectories (one scene from above, the true
// paths against each method's estimates held by one view, paper Figs. 4–5) and, given the
// measurements, NAME-views (DE against the number of views, paper Fig. 6). Each figure comes as
// .svg and .png with its .dat and .gp beside it. The figures are drawn in a staging folder inside
// DIR and moved in only when gnuplot has drawn them all, so a failure leaves DIR as it was.

#include <filesystem>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "input_guard.hpp"
#include "figures.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/evaluation.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/truth_file.hpp"

namespace stgf::cli {
namespace {

namespace fs = std::filesystem;

struct PlotOptions {
  std::string truth;
  std::vector<std::string> estimates;
  std::string measurements;
  std::string out;
  std::string scene;
  std::string view;
  ScoringStart start;
  std::string name = "stgf";
};

// "a, b, c" (at most `shown` names, then how many more).
std::string listed(const std::set<std::string>& names, std::size_t shown = 8) {
  std::string text;
  std::size_t count = 0;
  for (const std::string& name : names) {
    if (count == shown) return text + fmt::format(", … ({} more)", names.size() - shown);
    text += (count++ > 0 ? ", " : "") + name;
  }
  return text;
}

// The scene and view to draw: the user's, checked against the first estimates file, or the busiest.
std::pair<std::string, std::string> chosen_scene_and_view(const PlotOptions& options, const EstimateFile& first) {
  if (!options.scene.empty()) {
    std::set<std::string> scenes;
    for (const Estimate& row : first.rows) scenes.insert(row.scene);
    if (!scenes.contains(options.scene)) {
      throw std::invalid_argument(fmt::format("--scene {}: {} has no estimates in that scene (its scenes: {})",
                                              options.scene, first.path, listed(scenes)));
    }
  }
  auto [scene, view] = busiest_scene_and_view(first.rows, options.scene);
  if (!options.view.empty()) {
    std::set<std::string> views;
    for (const Estimate& row : first.rows) {
      if (row.scene == scene) views.insert(row.view);
    }
    if (!views.contains(options.view)) {
      throw std::invalid_argument(fmt::format("--view {}: {} has no estimates held by that view in scene {} (its views: {})",
                                              options.view, first.path, scene, listed(views)));
    }
    view = options.view;
  }
  return {scene, view};
}

void plot(const PlotOptions& options) {
  if (options.name.empty() || options.name.find('/') != std::string::npos || options.name.front() == '.') {
    throw std::invalid_argument("--name " + options.name + ": a file name prefix, without '/' and not starting with '.'");
  }
  // Writes --out/NAME-* (through the staging folder --out/.stgf-plot-NAME): no input may be there.
  std::vector<std::string> inputs = options.estimates;
  inputs.push_back(options.truth);
  inputs.push_back(options.measurements);
  refuse_prefixed_outputs_over_inputs("--out", options.out, options.name + "-", inputs);
  refuse_outputs_over_inputs("--out", {(fs::path(options.out) / (".stgf-plot-" + options.name)).string()}, inputs);
  if (!gnuplot_available()) {
    throw std::runtime_error("stgf plot draws with gnuplot, which is not installed (Debian: apt-get install gnuplot-nox)");
  }
  const TruthFile truth = read_truth(options.truth);
  std::vector<EstimateFile> estimates;
  for (const std::string& path : options.estimates) estimates.push_back(read_estimates(path));
  if (estimates.front().rows.empty()) throw std::invalid_argument(options.estimates.front() + ": no estimates to draw");
  std::optional<MeasurementFile> measurements;
  if (!options.measurements.empty()) measurements = read_measurements(options.measurements);

  const auto [scene, view] = chosen_scene_and_view(options, estimates.front());
  std::vector<TruthPoint> scene_truth;
  for (const TruthPoint& point : truth.rows) {
    if (point.scene == scene) scene_truth.push_back(point);
  }
  if (scene_truth.empty()) throw std::invalid_argument(options.truth + ": no truth for scene " + scene);
  std::vector<Measurement> measured;
  if (measurements) {
    for (const Measurement& row : measurements->rows) {
      if (row.scene == scene && row.view == view) measured.push_back(row);
    }
  }
  // Scoring checks that every estimate has its truth and (given) its measurement: bad input stops here.
  std::optional<Evaluation> evaluation;
  if (measurements) evaluation = evaluate(truth, estimates, &*measurements, options.start);

  const fs::path out(options.out);
  fs::create_directories(out);
  const fs::path staging = out / (".stgf-plot-" + options.name);
  fs::remove_all(staging);
  std::vector<std::string> stems = {options.name + "-trajectories"};
  try {
    write_trajectories(scene_truth, trajectories_of(estimates, scene, view), staging.string(), stems[0],
                       fmt::format("scene {}, estimates held by {}", scene, view), measured);
    if (evaluation) {
      stems.push_back(options.name + "-views");
      write_views_curve(*evaluation, staging.string(), stems[1],
                        options.start.from_time_s > 0.0
                            ? fmt::format("DE against the number of views (from {} s)", options.start.from_time_s)
                            : fmt::format("DE against the number of views (from step {})", options.start.from_step));
    }
    for (const std::string& stem : stems) run_gnuplot(staging.string(), stem);
  } catch (...) {
    fs::remove_all(staging);
    throw;
  }
  for (const fs::directory_entry& entry : fs::directory_iterator(staging)) {
    fs::rename(entry.path(), out / entry.path().filename());
  }
  fs::remove_all(staging);
  for (const std::string& stem : stems) spdlog::info("drew {}", (out / (stem + ".svg")).string());
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* command = app.add_subcommand(
      "plot",
      "Draw estimate files (any method's) with gnuplot: one scene's true paths against the estimates, and with "
      "--measurements, DE against the number of views. SVG and PNG, with the data and gnuplot script beside them.");
  command->add_option("--truth", options->truth, "truth CSV (scene,t,object,x,y,z)")->required();
  command->add_option("--estimates", options->estimates, "one or more estimates CSVs (a line per method)")->required();
  command->add_option("--out", options->out, "folder to draw into (made if missing)")->required();
  command->add_option("--measurements", options->measurements,
                      "the measurements the estimates came from: adds the views curve and the drawn view's "
                      "measurements as grey points");
  command->add_option("--scene", options->scene, "scene to draw (default: the one with the most estimates)");
  command->add_option("--view", options->view, "view whose estimates to draw (default: the one with the most in the scene)");
  CLI::Option* from_step =
      command->add_option("--from-step", options->start.from_step, "views curve: leave out each scene's first K steps")
          ->check(CLI::NonNegativeNumber);
  command
      ->add_option("--from-time", options->start.from_time_s,
                   "views curve: leave out each scene's rows earlier than its first measured time + S seconds")
      ->check(CLI::NonNegativeNumber)
      ->excludes(from_step);
  command->add_option("--name", options->name, "file name prefix of the figures")->capture_default_str();
  command->callback([options] { plot(*options); });
}

}  // namespace stgf::cli
