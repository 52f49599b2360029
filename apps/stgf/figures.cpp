// SPDX-License-Identifier: Apache-2.0
#include "figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>

#include <Eigen/Eigenvalues>
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

// Double-quoted for gnuplot, so that "\n" breaks the line (a backslash and a quote are escaped).
std::string gnuplot_double_quoted(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '\n') {
      quoted += "\\n";
      continue;
    }
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

// How a method is drawn in every figure: its colour, gnuplot point type and dash type. No two
// methods share a point type or a colour, so lines that coincide (wls and mmt often do) still tell
// apart; the filter (ours) is a solid red line with filled circles and stands out.
struct MethodStyle {
  std::string colour;
  int point_type;  // pngcairo/svg: 4 □ 5 ■ 6 ○ 7 ● 9 ▲ 11 ▼ 12 ◇ 13 ◆
  int dash_type;   // 1 solid, 2 dashed, 3 short dashes, 4 dash-dot, 5 dash-dot-dot
};

MethodStyle style_of(const std::string& method) {
  static const std::map<std::string, MethodStyle> styles = {
      {"aom", {"#7b3294", 5, 1}},
      {"wls", {"#1b9e77", 6, 2}},
      {"mmt", {"#56b4e9", 9, 1}},
      {"sttp", {"#e69f00", 11, 1}},
      {"ours-l", {"#a6761d", 13, 4}},
      {"ours", {"#d7191c", 7, 1}},
      {"ours-registration-off", {"#e7298a", 4, 3}},
      {"ours-per-view", {"#0072b2", 12, 5}}};
  const auto found = styles.find(method);
  if (found != styles.end()) return found->second;
  // Another method: a grey-ish colour and an open triangle, picked by its name so it is the same
  // in every figure.
  static const std::vector<std::string> fallback = {"#666666", "#8da0cb", "#66a61e", "#b3a000", "#999999"};
  std::size_t hash = 0;
  for (const char c : method) hash = hash * 31 + static_cast<unsigned char>(c);
  return {fallback[hash % fallback.size()], 8, 1 + static_cast<int>(hash % 5)};
}

// The order to draw `methods` in: the solid lines first, then the dashed ones (each group in the
// given order), so a dashed line drawn over a solid one it coincides with leaves both in sight.
std::vector<std::size_t> drawing_order(const std::vector<std::string>& methods) {
  std::vector<std::size_t> order(methods.size());
  for (std::size_t m = 0; m < order.size(); ++m) order[m] = m;
  std::stable_partition(order.begin(), order.end(), [&](std::size_t m) { return style_of(methods[m]).dash_type == 1; });
  return order;
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
  // Method m's points sit (m − (M − 1)/2)·0.06 views off the whole number, so equal numbers of two
  // methods show side by side; each has its own point type and dash pattern too.
  const std::size_t method_count = evaluation.methods.size();
  const double spread = 0.06;
  std::string plot = fmt::format(
      "# Each method's points are shifted sideways by a multiple of {} views (the .dat keeps the whole\n"
      "# numbers) so that methods with equal DE, like wls and mmt, do not hide one another; dashed lines\n"
      "# are drawn after solid ones.\nplot ",
      spread);
  std::vector<std::string> names;
  for (const MethodScore& method : evaluation.methods) names.push_back(method.method);
  for (const std::size_t m : drawing_order(names)) {
    if (!plot.ends_with("plot ")) plot += ", \\\n     ";
    const std::string& method = names[m];
    const MethodStyle style = style_of(method);
    const double offset = (static_cast<double>(m) - 0.5 * static_cast<double>(method_count - 1)) * spread;
    plot += fmt::format(
        "{} using ($1{:+.2f}):{} with linespoints lw {} dt {} pt {} ps 1.3 lc rgb '{}' title {} noenhanced",
        gnuplot_quoted(stem + ".dat"), offset, m + 2, method == "ours" ? 3 : 2, style.dash_type, style.point_type,
        style.colour, gnuplot_quoted(method));
  }
  const int lowest = counts.empty() ? 1 : *counts.begin();
  const int highest = counts.empty() ? 1 : *counts.rbegin();
  const double margin = 0.25 + 0.5 * spread * static_cast<double>(method_count);
  const std::string settings = fmt::format(
      "set title {} noenhanced\nset xlabel 'number of views that saw the object'\nset ylabel 'DE (m)'\n"
      "set logscale y\nset grid\nset key outside right\nset xrange [{}:{}]\nset xtics 1\n",
      gnuplot_quoted(title), lowest - margin, highest + margin);
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

std::vector<Eigen::Vector2d> covariance_ellipse(const Eigen::Vector2d& mean, const Eigen::Matrix2d& covariance,
                                                int points, double chi_square) {
  const Eigen::Matrix2d symmetric = 0.5 * (covariance + covariance.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
  eigen.computeDirect(symmetric);
  // Eigen sorts the eigenvalues up: column 1 is the major axis. Rounding can leave a tiny negative.
  const Eigen::Vector2d major = std::sqrt(chi_square * std::max(eigen.eigenvalues()(1), 0.0)) * eigen.eigenvectors().col(1);
  const Eigen::Vector2d minor = std::sqrt(chi_square * std::max(eigen.eigenvalues()(0), 0.0)) * eigen.eigenvectors().col(0);
  std::vector<Eigen::Vector2d> ellipse;
  ellipse.reserve(static_cast<std::size_t>(std::max(points, 0)));
  for (int j = 0; j < points; ++j) {
    const double angle = 2.0 * std::numbers::pi * j / points;
    ellipse.push_back(mean + std::cos(angle) * major + std::sin(angle) * minor);
  }
  return ellipse;
}

std::vector<std::size_t> ellipse_indices(std::size_t count) {
  const std::size_t every = std::max<std::size_t>(1, count / 10);
  std::vector<std::size_t> indices;
  for (std::size_t k = 0; k < count; k += every) indices.push_back(k);
  return indices;
}

void write_trajectories(std::span<const TruthPoint> truth, std::span<const MethodTrajectory> methods,
                        const std::string& directory, const std::string& stem, const std::string& title,
                        std::span<const Measurement> measured) {
  namespace fs = std::filesystem;
  using Path = std::vector<std::pair<double, Vector3d>>;  // (time, position) in time order
  fs::create_directories(directory);
  const auto data_file = [&](const std::string& name) { return stem + "-" + name + ".dat"; };
  const auto in_time_order = [](auto& rows, auto time_of) {
    std::stable_sort(rows.begin(), rows.end(), [&](const auto& a, const auto& b) { return time_of(a) < time_of(b); });
  };

  // The plot's range holds every path point and measurement, not the ellipses, which can be wide.
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low, y_low = x_low, y_high = -x_low;
  const auto widen = [&](const Vector3d& point) {
    x_low = std::min(x_low, point.x());
    x_high = std::max(x_high, point.x());
    y_low = std::min(y_low, point.y());
    y_high = std::max(y_high, point.y());
  };
  std::map<std::string, Path> truth_paths;
  for (const TruthPoint& point : truth) {
    truth_paths[point.object].emplace_back(point.time, point.position);
    widen(point.position);
  }
  for (const Measurement& row : measured) widen(row.position.mean());
  // Each method's tracks, one per object, in time order.
  std::vector<std::map<std::string, std::vector<const Estimate*>>> tracks(methods.size());
  for (std::size_t m = 0; m < methods.size(); ++m) {
    for (const Estimate& estimate : methods[m].estimates) {
      tracks[m][estimate.object].push_back(&estimate);
      widen(estimate.position.mean());
    }
    for (auto& [object, track] : tracks[m]) in_time_order(track, [](const Estimate* row) { return row->time; });
  }
  const bool anything = std::isfinite(x_low);
  const double span = anything ? std::max(x_high - x_low, y_high - y_low) : 0.0;
  const double margin = std::max(0.5, 0.05 * span);

  // One block per object (a blank line between blocks breaks the line).
  auto write_paths = [&](const std::string& name, std::map<std::string, Path> paths) {
    std::string data = "# x y (m), one block per object: " + name + "\n";
    for (auto& [object, points] : paths) {
      in_time_order(points, [](const auto& point) { return point.first; });
      data += "# object " + object + "\n";
      for (const auto& [time, position] : points) data += fmt::format("{:.4f} {:.4f}\n", position.x(), position.y());
      data += "\n";
    }
    write_text_file((fs::path(directory) / data_file(name)).string(), data);
  };
  write_paths("truth", truth_paths);
  std::string plot = "plot ";
  if (!measured.empty()) {
    std::string data = "# x y (m) of the measurements drawn\n";
    for (const Measurement& row : measured) {
      data += fmt::format("{:.4f} {:.4f}\n", row.position.mean().x(), row.position.mean().y());
    }
    write_text_file((fs::path(directory) / data_file("measured")).string(), data);
    plot += fmt::format("{} with points pt 7 ps 0.3 lc rgb '#b0b0b0' title 'measured', \\\n     ",
                        gnuplot_quoted(data_file("measured")));
  }
  // Each method's 95 % ellipses, under the paths: one block of kEllipsePoints + 1 rows (the first
  // point again closes the line) per ellipse, a blank line after each. An ellipse whose major
  // semi-axis is wider than half the plot (a track's uninformed start, say) would only cross the
  // plot as stray arcs: it is left out, and named in the file.
  const double widest = 0.5 * (span + 2.0 * margin);
  std::vector<std::string> paths_plot(methods.size());  // each method's path, drawn after every ellipse
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const std::string& method = methods[m].method;
    std::map<std::string, Path> paths;
    std::string ellipses;
    std::string left_out;
    for (const auto& [object, track] : tracks[m]) {
      for (const Estimate* estimate : track) paths[object].emplace_back(estimate->time, estimate->position.mean());
      for (const std::size_t k : ellipse_indices(track.size())) {
        const Estimate& estimate = *track[k];
        const Eigen::Vector2d mean = estimate.position.mean().head<2>();
        const std::vector<Eigen::Vector2d> ellipse =
            covariance_ellipse(mean, estimate.position.covariance().topLeftCorner<2, 2>());
        const double major = (ellipse.front() - mean).norm();  // the first point ends the major axis
        if (major > widest) {
          left_out += fmt::format("#   object {} t {} (major semi-axis {:.2f} m)\n", object, estimate.time, major);
          continue;
        }
        ellipses += fmt::format("# object {} t {}\n", object, estimate.time);
        for (std::size_t j = 0; j <= ellipse.size(); ++j) {
          const Eigen::Vector2d& point = ellipse[j % ellipse.size()];
          ellipses += fmt::format("{:.4f} {:.4f}\n", point.x(), point.y());
        }
        ellipses += "\n";
      }
    }
    write_paths(method, paths);
    std::string header = fmt::format(
        "# x y (m): the 95 % region (chi-square 2 dof, {:.3f}) of the x-y covariance of every k-th estimate of {},\n"
        "# k = max(1, floor(track length / 10)); one block of {} points per ellipse (the first repeated at the end)\n",
        kChiSquare2Dof95, method, kEllipsePoints + 1);
    if (!left_out.empty()) {
      header += fmt::format("# left out, wider than half the plot ({:.2f} m):\n", widest) + left_out;
    }
    write_text_file((fs::path(directory) / data_file("ellipses-" + method)).string(), header + ellipses);
    const MethodStyle style = style_of(method);
    plot += fmt::format("{} with lines lw 0.8 dt 1 lc rgb '{}' notitle, \\\n     ",
                        gnuplot_quoted(data_file("ellipses-" + method)), style.colour);
    paths_plot[m] = fmt::format(", \\\n     {} with linespoints lw {} dt {} pt {} ps 0.6 lc rgb '{}' title {} noenhanced",
                                gnuplot_quoted(data_file(method)), method == "ours" ? 2.5 : 1.5, style.dash_type,
                                style.point_type, style.colour, gnuplot_quoted(method));
  }
  plot += fmt::format("{} with lines lw 4 lc rgb '#303030' title 'truth'", gnuplot_quoted(data_file("truth")));
  std::vector<std::string> names;
  for (const MethodTrajectory& method : methods) names.push_back(method.method);
  for (const std::size_t m : drawing_order(names)) plot += paths_plot[m];
  const std::string range =
      anything ? fmt::format("set xrange [{:.4f}:{:.4f}]\nset yrange [{:.4f}:{:.4f}]\n", x_low - margin,
                             x_high + margin, y_low - margin, y_high + margin)
               : std::string();
  const std::string settings = fmt::format(
      "set title {} noenhanced\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nset size ratio -1\nset grid\n"
      "set key outside right\n"
      "# The range holds the paths and measurements; an ellipse reaching past it is clipped.\n{}",
      gnuplot_double_quoted(title + (methods.empty() ? "" : "\nellipses: 95% region of the estimate's covariance")),
      range);
  write_text_file((fs::path(directory) / (stem + ".gp")).string(), script(stem, settings, plot));
}

}  // namespace stgf::cli
