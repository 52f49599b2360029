// SPDX-License-Identifier: Apache-2.0
// stgf eval --truth T --estimates E [E2 ...] [--measurements M] [--from-step K | --from-time S] [--json OUT]
//           [--by-variance x,y,z]
//
// The files are read scene by scene when they are grouped by scene in one order, else whole
// (stgf/io/evaluation_files.hpp); the numbers are the same either way.

#include <cstdio>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "input_guard.hpp"
#include "stgf/io/evaluation_files.hpp"
#include "stgf/io/evaluation_report.hpp"
#include "stgf/io/output_file.hpp"

namespace stgf::cli {
namespace {

struct EvalOptions {
  std::string truth;
  std::vector<std::string> estimates;
  std::string measurements;
  ScoringStart start;
  std::string json;
  std::vector<std::string> by_variance;  // axes: x, y, z
};

void eval(const EvalOptions& options) {
  std::vector<std::string> inputs = options.estimates;
  inputs.push_back(options.truth);
  inputs.push_back(options.measurements);
  refuse_output_over_input("--json", options.json, inputs);
  std::string read_whole_because;
  const Evaluation evaluation =
      evaluate_files(options.truth, options.estimates, options.measurements, options.start, &read_whole_because);
  if (!read_whole_because.empty()) {
    spdlog::info("eval: the files were read whole, not scene by scene ({}); group them by scene in one order to "
                 "score them in the memory of one scene",
                 read_whole_because);
  }
  if (!options.json.empty()) write_text_file(options.json, evaluation_json(evaluation).dump(2) + "\n");
  std::string text = evaluation_markdown(evaluation);
  for (const std::string& axis : options.by_variance) {
    text += error_by_variance_markdown(evaluation, static_cast<int>(axis[0] - 'x'));
  }
  std::fputs(text.c_str(), stdout);
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* command = app.add_subcommand(
      "eval", "Score estimate files against the truth: DE, REL-DE, NEES, overall and by number of views.");
  command->add_option("--truth", options->truth, "truth CSV (scene,t,object,x,y,z)")->required();
  command->add_option("--estimates", options->estimates, "one or more estimates CSVs (one row per method in the table)")
      ->required();
  command->add_option("--measurements", options->measurements,
                      "the measurements the estimates came from: fixes the scored rows, counts views, gives sensor "
                      "positions for REL-DE");
  CLI::Option* from_step =
      command->add_option("--from-step", options->start.from_step, "leave out each scene's first K steps (for every method)")
          ->check(CLI::NonNegativeNumber);
  command
      ->add_option("--from-time", options->start.from_time_s,
                   "leave out each scene's rows earlier than its first measured time + S seconds (for every method; "
                   "on asynchronous data, where each view adds its own times, use this rather than --from-step)")
      ->check(CLI::NonNegativeNumber)
      ->excludes(from_step);
  command->add_option("--json", options->json, "also write the results as JSON here");
  command
      ->add_option("--by-variance", options->by_variance,
                   "also print, per axis given (x, y, z), each octave of the stated variance with the squared error's "
                   "mean over it: 1 in every octave where the covariance means what it says (the JSON always has it)")
      ->delimiter(',')
      ->check(CLI::IsMember({"x", "y", "z"}));
  command->callback([options] { eval(*options); });
}

}  // namespace stgf::cli
