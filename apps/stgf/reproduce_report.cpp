// SPDX-License-Identifier: Apache-2.0
#include "reproduce_report.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "stgf/io/evaluation_report.hpp"

namespace stgf::cli {
namespace {

// Paper Table I order, then the method beyond the paper.
const std::vector<std::string> kTableOrder = {"aom", "mmt", "sttp", "ours-l", "ours", "wls"};

// The paper's ratios (Table I): ours / aom and ours / mmt DE on its CAD and MPL data.
struct PaperRatio {
  std::string benchmark;
  double ours_over_aom;
  double ours_over_mmt;
};
const std::vector<PaperRatio> kPaperRatios = {{"cad", 0.45, 0.54}, {"mpl", 0.47, 0.55}};

const MethodScore* find_method(const BenchmarkResult& result, const std::string& method) {
  for (const MethodScore& score : result.evaluation.methods) {
    if (score.method == method) return &score;
  }
  return nullptr;
}

std::string number(double value, int decimals) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals) : std::string("–");
}

std::optional<double> ratio(const BenchmarkResult& result, const std::string& numerator, const std::string& denominator) {
  const MethodScore* top = find_method(result, numerator);
  const MethodScore* bottom = find_method(result, denominator);
  if (top == nullptr || bottom == nullptr) return std::nullopt;
  return top->overall.displacement_error / bottom->overall.displacement_error;
}

nlohmann::json summary_json(const ErrorSummary& s) {
  auto value = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"rows", s.rows},
          {"de", value(s.displacement_error)},
          {"rel_de", value(s.relative_displacement_error)},
          {"nees_mean", value(s.nees_mean)},
          {"nees_share_in_95", value(s.nees_share_in_95)}};
}

}  // namespace

std::string table_one_markdown(const std::vector<BenchmarkResult>& results, const std::vector<std::string>& variants) {
  std::string header = "| method |";
  std::string rule = "|---|";
  for (const BenchmarkResult& result : results) {
    header += fmt::format(" {0} DE (m) | {0} REL-DE | {0} NEES | {0} NEES in 95% |", result.name);
    rule += "---:|---:|---:|---:|";
  }
  std::string text = header + "\n" + rule + "\n";
  std::vector<std::string> rows = kTableOrder;
  rows.insert(rows.end(), variants.begin(), variants.end());
  for (const std::string& method : rows) {
    text += "| " + method + " |";
    for (const BenchmarkResult& result : results) {
      const MethodScore* score = find_method(result, method);
      if (score == nullptr) {
        text += " – | – | – | – |";
        continue;
      }
      // Bold: the lowest DE among the six methods.
      bool best = std::find(variants.begin(), variants.end(), method) == variants.end();
      for (const std::string& other : kTableOrder) {
        const MethodScore* rival = find_method(result, other);
        if (rival != nullptr && rival->overall.displacement_error < score->overall.displacement_error) best = false;
      }
      const ErrorSummary& s = score->overall;
      const std::string de = number(s.displacement_error, 4);
      text += fmt::format(" {} | {} | {} | {} |", best ? "**" + de + "**" : de, number(s.relative_displacement_error, 4),
                          number(s.nees_mean, 2), number(s.nees_share_in_95, 3));
    }
    text += "\n";
  }
  return text;
}

std::string results_markdown(const ReproduceSummary& summary, const std::vector<BenchmarkResult>& results) {
  std::string text = "# stgf reproduce: results\n\n";
  text += fmt::format(
      "Produced by `{}` ({} benchmarks, {} training epochs, seed {}). Every method is scored on the same "
      "rows of the test split, from each scene's step {} on (the history a learned method needs). DE and "
      "REL-DE as in the paper; NEES is the normalised estimation error squared (3 when the covariance is "
      "right, larger when the method is overconfident); \"NEES in 95%\" is the share of rows inside the 95% "
      "interval of χ²(3). Bold: the lowest DE of the six methods.\n\n",
      summary.command, summary.quick ? "quick (smaller)" : "full-size", summary.epochs, summary.seed, summary.from_step);

  text += "## Table I\n\n" + table_one_markdown(results, summary.variant_labels()) + "\n";
  text += fmt::format(
      "`{}` is `ours` with its registration-error handling turned off (below); `{}` is `ours` with the paper's "
      "per-view tracks (each view tracks each object on its own, with the measurements of every view at its "
      "times) instead of one track per object.\n\n",
      summary.registration_off_label, summary.per_view_label);

  text += "## Against the paper\n\nThe paper's data are not public and ours differ, so compare ratios of DE:\n\n";
  text += "| benchmark | ours / aom (paper) | ours / aom (here) | ours / mmt (paper) | ours / mmt (here) |\n";
  text += "|---|---:|---:|---:|---:|\n";
  for (const BenchmarkResult& result : results) {
    for (const PaperRatio& paper : kPaperRatios) {
      if (paper.benchmark != result.name) continue;
      const auto over_aom = ratio(result, "ours", "aom");
      const auto over_mmt = ratio(result, "ours", "mmt");
      text += fmt::format("| {} | {:.2f} | {} | {:.2f} | {} |\n", result.name, paper.ours_over_aom,
                          over_aom ? number(*over_aom, 2) : "–", paper.ours_over_mmt,
                          over_mmt ? number(*over_mmt, 2) : "–");
    }
  }

  text += "\n## Registration error\n\n";
  text += "Each view's registration error (calibration or GPS pose error, not in R) as calibrated on the "
          "validation split, and `ours` with its handling on (online per-view offsets, their uncertainty kept "
          "in the covariance) and off:\n\n";
  text += "| benchmark | translation σ (m) | noise ratio α | DE on | NEES on | NEES in 95% on | DE off | NEES off | NEES in 95% off |\n";
  text += "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const BenchmarkResult& result : results) {
    const MethodScore* on = find_method(result, "ours");
    const MethodScore* off = find_method(result, summary.registration_off_label);
    if (on == nullptr || off == nullptr) continue;
    std::string sigma = "–";
    std::string ratio_text = "–";
    if (result.registration.contains("translation_sigma_m")) {
      const auto& s = result.registration.at("translation_sigma_m");
      sigma = fmt::format("({:.3f}, {:.3f}, {:.3f})", s[0].get<double>(), s[1].get<double>(), s[2].get<double>());
      const auto& ratio = result.registration.at("noise_ratio");
      ratio_text = ratio.is_array() ? fmt::format("({:.3f}, {:.3f}, {:.3f})", ratio[0].get<double>(),
                                                  ratio[1].get<double>(), ratio[2].get<double>())
                                    : fmt::format("{:.3f}", ratio.get<double>());
    }
    text += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", result.name, sigma, ratio_text,
                        number(on->overall.displacement_error, 4), number(on->overall.nees_mean, 2),
                        number(on->overall.nees_share_in_95, 3), number(off->overall.displacement_error, 4),
                        number(off->overall.nees_mean, 2), number(off->overall.nees_share_in_95, 3));
  }

  for (const BenchmarkResult& result : results) {
    text += "\n## " + result.name + ": every method, and DE by number of views\n\n";
    text += evaluation_markdown(result.evaluation);
    if (!result.figures.empty()) text += "\n";
    for (const std::string& stem : result.figures) text += fmt::format("![{0}](figures/{0}.svg)\n", stem);
  }

  bool any_variant = false;
  for (const BenchmarkResult& result : results) any_variant = any_variant || !result.clock_variants.empty();
  if (any_variant) {
    text += "\n## Asynchronous views\n\n";
    text += "The same test splits with each view on its own clock (`stgf dataset … --asynchronous`: a phase "
            "uniform in one frame period per view and scene, 2 ms jitter per message, every measurement taken at "
            "its own time, the truth at every measured time), without and with message latency (`--latency "
            "0.15`: rows arrive 0–150 ms after they were measured and are fused in arrival order; each row's "
            "estimate is what was known of its object at its time when the row arrived). Scored from two frame "
            "periods after each scene's first measurement; the models are those of Table I, trained on the "
            "synchronous data. Last column: DE against `ours` on the synchronous split.\n\n";
    text += "| benchmark | clocks | method | DE (m) | NEES | NEES in 95% | DE / ours synchronous |\n";
    text += "|---|---|---|---:|---:|---:|---:|\n";
    for (const BenchmarkResult& result : results) {
      const MethodScore* synchronous = find_method(result, "ours");
      for (const auto& variant : result.clock_variants) {
        const std::string clocks = variant.latency_s > 0.0 ? fmt::format("own clocks, latency 0–{:.0f} ms", 1000 * variant.latency_s)
                                                           : std::string("own clocks");
        for (const MethodScore& score : variant.evaluation.methods) {
          const double relative = synchronous == nullptr ? std::nan("")
                                                         : score.overall.displacement_error /
                                                               synchronous->overall.displacement_error;
          const std::string de = number(score.overall.displacement_error, 4);
          text += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", result.name, clocks, score.method,
                              score.method == "ours" ? "**" + de + "**" : de, number(score.overall.nees_mean, 2),
                              number(score.overall.nees_share_in_95, 3), number(relative, 2));
        }
      }
    }
  }

  text += "\n## Timings\n\n| benchmark | stage | seconds |\n|---|---|---:|\n";
  for (const BenchmarkResult& result : results) {
    for (const auto& [stage, seconds] : result.timings) text += fmt::format("| {} | {} | {:.1f} |\n", result.name, stage, seconds);
  }
  text += "\n\"(reused)\": made by an earlier run with the same recipe; the time is what making it took then.\n";
  return text;
}

nlohmann::json results_json(const ReproduceSummary& summary, const std::vector<BenchmarkResult>& results) {
  nlohmann::json json = {{"command", summary.command},
                         {"seed", summary.seed},
                         {"quick", summary.quick},
                         {"epochs", summary.epochs},
                         {"from_step", summary.from_step},
                         {"benchmarks", nlohmann::json::object()}};
  for (const BenchmarkResult& result : results) {
    nlohmann::json methods = nlohmann::json::object();
    for (const MethodScore& score : result.evaluation.methods) {
      nlohmann::json by_views = nlohmann::json::object();
      for (const auto& [count, summary_of_count] : score.by_views) by_views[std::to_string(count)] = summary_json(summary_of_count);
      methods[score.method] = {{"overall", summary_json(score.overall)}, {"by_views", by_views}};
    }
    nlohmann::json variants = nlohmann::json::object();
    for (const auto& variant : result.clock_variants) {
      nlohmann::json of_variant = nlohmann::json::object();
      for (const MethodScore& score : variant.evaluation.methods) of_variant[score.method] = summary_json(score.overall);
      variants[variant.suffix] = {{"latency_s", variant.latency_s}, {"methods", of_variant}};
    }
    json["benchmarks"][result.name] = {{"methods", methods},
                                       {"asynchronous", variants},
                                       {"registration", result.registration},
                                       {"timings_s", result.timings},
                                       {"figures", result.figures}};
  }
  return json;
}

}  // namespace stgf::cli
