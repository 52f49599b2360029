// SPDX-License-Identifier: Apache-2.0
#include "figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "stgf/io/output_file.hpp"

namespace stgf::cli {
namespace {

// Single-quoted for the shell.
std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

// Single-quoted for gnuplot (a quote is doubled).
std::string gnuplot_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    quoted += c;
    if (c == '\'') quoted += '\'';
  }
  return quoted + "'";
}

// Draws to SVG, then the same plot to PNG.
std::string script(const std::string& stem, const std::string& settings, const std::string& plot) {
  return fmt::format(
      "# Drawn by stgf; run `gnuplot {0}.gp` in this directory to draw it again.\n"
      "set terminal svg size 900,560 dynamic enhanced font 'sans,13' background rgb 'white'\n"
      "set output '{0}.svg'\n{1}{2}\n"
      "set terminal pngcairo size 900,560 enhanced font 'sans,11' background rgb 'white'\n"
      "set output '{0}.png'\nreplot\nunset output\n",
      stem, settings, plot);
}

// One colour per method in every figure; the filter (ours) stands out.
std::string colour_of(const std::string& method) {
  static const std::map<std::string, std::string> colours = {
      {"aom", "#7b3294"},  {"wls", "#1b9e77"},   {"mmt", "#56b4e9"},
      {"sttp", "#e69f00"}, {"ours-l", "#a6761d"}, {"ours", "#d7191c"}};
  const auto found = colours.find(method);
  return found == colours.end() ? "#666666" : found->second;
}

}  // namespace

bool gnuplot_available() { return std::system("gnuplot --version >/dev/null 2>&1") == 0; }

void run_gnuplot(const std::string& directory, const std::string& stem) {
  const std::string command = "cd " + shell_quoted(directory) + " && gnuplot " + shell_quoted(stem + ".gp") + " 2>&1";
  if (std::system(command.c_str()) != 0) {
    throw std::runtime_error("gnuplot failed on " + (std::filesystem::path(directory) / (stem + ".gp")).string());
  }
}

void write_views_curve(const Evaluation& evaluation, const std::string& directory, const std::string& stem,
                       const std::string& title) {
  std::set<int> counts;
  for (const MethodScore& method : evaluation.methods) {
    for (const auto& entry : method.by_views) counts.insert(entry.first);
  }
  std::string data = "# views";
  for (const MethodScore& method : evaluation.methods) data += " " + method.method;
  data += "   (DE in metres; NaN: no such rows)\n";
  for (const int n : counts) {
    data += std::to_string(n);
    for (const MethodScore& method : evaluation.methods) {
      const auto found = method.by_views.find(n);
      const double de = found == method.by_views.end() ? std::nan("") : found->second.displacement_error;
      data += std::isfinite(de) ? fmt::format(" {:.6f}", de) : " NaN";
    }
    data += "\n";
  }
  std::string plot = "plot ";
  for (std::size_t m = 0; m < evaluation.methods.size(); ++m) {
    if (m > 0) plot += ", \\\n     ";
    const std::string& method = evaluation.methods[m].method;
    plot += fmt::format("'{}.dat' using 1:{} with linespoints lw {} pt 7 lc rgb '{}' title {}", stem, m + 2,
                        method == "ours" ? 3 : 2, colour_of(method), gnuplot_quoted(method));
  }
  const int lowest = counts.empty() ? 1 : *counts.begin();
  const int highest = counts.empty() ? 1 : *counts.rbegin();
  const std::string settings = fmt::format(
      "set title {}\nset xlabel 'number of views that saw the object'\nset ylabel 'DE (m)'\n"
      "set logscale y\nset grid\nset key outside right\nset xrange [{}:{}]\nset xtics 1\n",
      gnuplot_quoted(title), lowest - 0.2, highest + 0.2);
  std::filesystem::create_directories(directory);
  write_text_file((std::filesystem::path(directory) / (stem + ".dat")).string(), data);
  write_text_file((std::filesystem::path(directory) / (stem + ".gp")).string(), script(stem, settings, plot));
}

std::pair<std::string, std::string> busiest_scene_and_view(std::span<const Estimate> rows,
                                                           const std::string& given_scene) {
  auto most_common = [](const std::map<std::string, std::size_t>& counts) {
    std::string name;
    std::size_t most = 0;
    for (const auto& [candidate, count] : counts) {
      if (count > most) {
        most = count;
        name = candidate;
      }
    }
    return name;
  };
  std::string scene = given_scene;
  if (scene.empty()) {
    std::map<std::string, std::size_t> per_scene;
    for (const Estimate& row : rows) ++per_scene[row.scene];
    scene = most_common(per_scene);
  }
  std::map<std::string, std::size_t> per_view;
  for (const Estimate& row : rows) {
    if (row.scene == scene) ++per_view[row.view];
  }
  return {scene, most_common(per_view)};
}

std::vector<MethodTrajectory> trajectories_of(std::span<const EstimateFile> files, const std::string& scene,
                                              const std::string& view) {
  std::vector<MethodTrajectory> trajectories;
  std::map<std::string, std::size_t> index_of;
  for (const EstimateFile& file : files) {
    for (std::size_t k = 0; k < file.rows.size(); ++k) {
      const Estimate& row = file.rows[k];
      if (row.scene != scene || row.view != view) continue;
      const std::string& method = file.methods[k];
      const auto [found, added] = index_of.try_emplace(method, trajectories.size());
      if (added) trajectories.push_back(MethodTrajectory{method, {}});
      trajectories[found->second].estimates.push_back(row);
    }
  }
  return trajectories;
}

void write_trajectories(std::span<const TruthPoint> truth, std::span<const MethodTrajectory> methods,
                        const std::string& directory, const std::string& stem, const std::string& title,
                        std::span<const Measurement> measured) {
  std::filesystem::create_directories(directory);
  // One block per object (a blank line between blocks breaks the line), in time order.
  auto write_paths = [&](const std::string& name, std::map<std::string, std::vector<std::pair<double, Vector3d>>> paths) {
    std::string data = "# x y (m), one block per object: " + name + "\n";
    for (auto& [object, points] : paths) {
      std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      data += "# object " + object + "\n";
      for (const auto& [time, position] : points) data += fmt::format("{:.4f} {:.4f}\n", position.x(), position.y());
      data += "\n";
    }
    write_text_file((std::filesystem::path(directory) / (stem + "-" + name + ".dat")).string(), data);
  };
  std::map<std::string, std::vector<std::pair<double, Vector3d>>> truth_paths;
  for (const TruthPoint& point : truth) truth_paths[point.object].emplace_back(point.time, point.position);
  write_paths("truth", truth_paths);
  std::string plot = "plot ";
  if (!measured.empty()) {
    std::string data = "# x y (m) of the measurements drawn\n";
    for (const Measurement& row : measured) data += fmt::format("{:.4f} {:.4f}\n", row.position.mean().x(), row.position.mean().y());
    write_text_file((std::filesystem::path(directory) / (stem + "-measured.dat")).string(), data);
    plot += fmt::format("'{}-measured.dat' with points pt 7 ps 0.3 lc rgb '#b0b0b0' title 'measured', \\\n     ", stem);
  }
  plot += fmt::format("'{}-truth.dat' with lines lw 4 lc rgb '#303030' title 'truth'", stem);
  for (const MethodTrajectory& method : methods) {
    std::map<std::string, std::vector<std::pair<double, Vector3d>>> paths;
    for (const Estimate& estimate : method.estimates) paths[estimate.object].emplace_back(estimate.time, estimate.position.mean());
    write_paths(method.method, paths);
    plot += fmt::format(", \\\n     '{}-{}.dat' with linespoints lw {} pt 7 ps 0.5 lc rgb '{}' title {}", stem,
                        method.method, method.method == "ours" ? 2.5 : 1.5, colour_of(method.method),
                        gnuplot_quoted(method.method));
  }
  const std::string settings = fmt::format(
      "set title {}\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nset size ratio -1\nset grid\nset key outside right\n",
      gnuplot_quoted(title));
  write_text_file((std::filesystem::path(directory) / (stem + ".gp")).string(), script(stem, settings, plot));
}

}  // namespace stgf::cli
