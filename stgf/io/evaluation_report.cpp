// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/evaluation_report.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

namespace stgf {
namespace {

std::string cell(double value, int decimals) {
  return std::isnan(value) ? std::string("–") : fmt::format("{:.{}f}", value, decimals);
}

nlohmann::json number_or_null(double value) {
  return std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value);
}

nlohmann::json summary_json(const ErrorSummary& summary) {
  return {{"rows", summary.rows},
          {"de", number_or_null(summary.displacement_error)},
          {"rel_de", number_or_null(summary.relative_displacement_error)},
          {"nees_mean", number_or_null(summary.nees_mean)},
          {"nees_share_in_95", number_or_null(summary.nees_share_in_95)},
          {"nees_horizontal_mean", number_or_null(summary.nees_horizontal_mean)},
          {"nees_vertical_mean", number_or_null(summary.nees_vertical_mean)}};
}

nlohmann::json by_variance_json(const std::array<std::vector<VarianceBin>, 3>& axes) {
  nlohmann::json json = nlohmann::json::object();
  for (int a = 0; a < 3; ++a) {
    nlohmann::json bins = nlohmann::json::array();
    for (const VarianceBin& bin : axes[a]) {
      bins.push_back({{"variance_from", bin.variance_from()},
                      {"variance_to", bin.variance_to()},
                      {"rows", bin.rows},
                      {"mean_variance", bin.mean_variance},
                      {"mean_squared_error", bin.mean_squared_error}});
    }
    json[std::string(1, "xyz"[a])] = bins;
  }
  return json;
}

}  // namespace

std::string error_by_variance_markdown(const Evaluation& evaluation, int axis) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("error_by_variance_markdown: axis must be 0, 1 or 2");
  const char name = "xyz"[axis];
  std::map<int, VarianceBin> octaves;  // every method's octaves, each with its bounds
  for (const MethodScore& score : evaluation.methods) {
    for (const VarianceBin& bin : score.by_variance[axis]) octaves.emplace(bin.octave, bin);
  }
  std::string text = fmt::format(
      "\nr_{0}² / P_{0}{0} by stated variance P_{0}{0} (1 in every bin where the covariance means what it says; "
      "the bin's rows in brackets):\n\n| P_{0}{0} (m²) |",
      name);
  std::string rule = "|---|";
  for (const MethodScore& score : evaluation.methods) {
    text += fmt::format(" {} |", score.method);
    rule += "---:|";
  }
  text += "\n" + rule + "\n";
  for (const auto& [octave, any] : octaves) {
    const int wanted = octave;  // a named copy: clang 14 cannot capture a structured binding
    text += fmt::format("| {:.2e} – {:.2e} |", any.variance_from(), any.variance_to());
    for (const MethodScore& score : evaluation.methods) {
      const auto& bins = score.by_variance[axis];
      const auto bin = std::find_if(bins.begin(), bins.end(), [&](const VarianceBin& b) { return b.octave == wanted; });
      text += bin == bins.end() ? std::string(" – |")
                                : fmt::format(" {:.2f} ({}) |", bin->mean_squared_error / bin->mean_variance, bin->rows);
    }
    text += "\n";
  }
  return text;
}

std::string evaluation_markdown(const Evaluation& evaluation) {
  std::string text;
  // NEES x, y and NEES z: the horizontal and vertical marginals' (2 and 1 when calibrated; metrics.hpp).
  text += "| method | rows | DE (m) | REL-DE | NEES mean | NEES in 95% | NEES x, y | NEES z |\n";
  text += "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  std::set<int> views;
  for (const MethodScore& score : evaluation.methods) {
    const ErrorSummary& s = score.overall;
    text += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", score.method, s.rows, cell(s.displacement_error, 4),
                        cell(s.relative_displacement_error, 4), cell(s.nees_mean, 2),
                        cell(s.nees_share_in_95, 3), cell(s.nees_horizontal_mean, 2), cell(s.nees_vertical_mean, 2));
    for (const auto& [count, summary] : score.by_views) views.insert(count);
  }
  if (views.empty()) return text;
  text += "\nDE (m) by number of views that saw the object:\n\n| method |";
  std::string rule = "|---|";
  for (int count : views) {
    text += fmt::format(" n={} |", count);
    rule += "---:|";
  }
  text += "\n" + rule + "\n";
  for (const MethodScore& score : evaluation.methods) {
    text += fmt::format("| {} |", score.method);
    for (int count : views) {
      const auto it = score.by_views.find(count);
      text += fmt::format(" {} |", it == score.by_views.end() ? std::string("–")
                                                               : cell(it->second.displacement_error, 4));
    }
    text += "\n";
  }
  return text;
}

nlohmann::json evaluation_json(const Evaluation& evaluation) {
  nlohmann::json methods = nlohmann::json::array();
  for (const MethodScore& score : evaluation.methods) {
    nlohmann::json by_views = nlohmann::json::object();
    for (const auto& [count, summary] : score.by_views) by_views[std::to_string(count)] = summary_json(summary);
    methods.push_back({{"method", score.method},
                       {"estimates", score.file},
                       {"overall", summary_json(score.overall)},
                       {"by_views", by_views},
                       {"by_variance", by_variance_json(score.by_variance)}});
  }
  return {{"truth", evaluation.truth_file},
          {"measurements", evaluation.measurements_file.empty() ? nlohmann::json(nullptr)
                                                                 : nlohmann::json(evaluation.measurements_file)},
          {"from_step", evaluation.from_step},
          {"from_time_s", evaluation.from_time_s},
          {"rows_excluded_before_from_step", evaluation.rows_excluded},
          {"nees_interval_95", {kChiSquare3Lower95, kChiSquare3Upper95}},
          {"methods", methods}};
}

}  // namespace stgf
