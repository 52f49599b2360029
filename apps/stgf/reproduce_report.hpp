// SPDX-License-Identifier: Apache-2.0
#pragma once
// What stgf reproduce writes: Table I (DE, REL-DE and NEES per method and benchmark), the comparison
// with the paper's ratios, the effect of the registration-error handling, DE by number of views, the
// figures and the timings — as Markdown (results.md) and JSON (results.json).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stgf/io/evaluation.hpp"

namespace stgf::cli {

struct BenchmarkResult {
  std::string name;                       // mpl, cad
  Evaluation evaluation;                  // the six methods, then `ours` without registration handling
  nlohmann::json registration;            // the registration prior `ours` ran with (model metadata)
  std::map<std::string, double> timings;  // seconds per stage
  std::vector<std::string> figures;       // stems of the figures drawn (in figures/)
  // The test split with each view on its own clock (and with message latency), every method.
  struct ClockVariantResult {
    std::string suffix;        // async, async-latency
    double latency_s = 0.0;    // the largest message delay
    Evaluation evaluation;
  };
  std::vector<ClockVariantResult> clock_variants;
};

struct ReproduceSummary {
  std::string command;
  std::uint64_t seed = 1;
  bool quick = false;
  int epochs = 0;
  int from_step = 0;
  std::string registration_off_label;  // the method name of `ours` without registration handling
  std::string per_view_label;          // the method name of `ours` with per-view tracks
  std::vector<std::string> variant_labels() const { return {registration_off_label, per_view_label}; }
};

// Table I: one row per method (paper order, then wls), DE / REL-DE / NEES / NEES in 95% per benchmark.
// Variants of `ours` follow, not bolded.
std::string table_one_markdown(const std::vector<BenchmarkResult>& results, const std::vector<std::string>& variants);

std::string results_markdown(const ReproduceSummary& summary, const std::vector<BenchmarkResult>& results);
nlohmann::json results_json(const ReproduceSummary& summary, const std::vector<BenchmarkResult>& results);

}  // namespace stgf::cli
