// SPDX-License-Identifier: Apache-2.0
// stgf inject-fault --measurements M --view V --kind jump|understated-noise|outliers --out OUT [options]

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "input_guard.hpp"
#include "stgf/datasets/view_faults.hpp"
#include "stgf/io/measurement_file.hpp"

namespace stgf::cli {
namespace {

struct InjectFaultOptions {
  std::string measurements;
  std::string out;
  ViewFaultOptions fault;
  std::string kind;
  std::vector<double> outlier_range_m{5.0, 20.0};
};

void inject_fault(InjectFaultOptions options) {
  refuse_output_over_input("--out", options.out, {options.measurements});
  options.fault.kind = options.kind == "jump"                ? ViewFaultKind::kJump
                       : options.kind == "understated-noise" ? ViewFaultKind::kUnderstatedNoise
                                                             : ViewFaultKind::kOutliers;
  options.fault.outlier_min_m = options.outlier_range_m.at(0);
  options.fault.outlier_max_m = options.outlier_range_m.at(1);
  check_view_fault_options(options.fault);
  MeasurementFile file = read_measurements(options.measurements);
  const ViewFaultSummary summary = inject_view_fault(file.rows, options.fault);
  if (summary.view_rows == 0) {
    throw std::invalid_argument("view '" + options.fault.view + "' has no rows in " + options.measurements);
  }
  write_measurements(options.out, file.rows);
  spdlog::info("{}: view '{}' made faulty ({}) in {} scene(s): {} of its {} rows changed", options.out,
               options.fault.view, view_fault_name(options.fault.kind), summary.scenes, summary.changed_rows,
               summary.view_rows);
}

}  // namespace

void add_inject_fault_command(CLI::App& app) {
  auto options = std::make_shared<InjectFaultOptions>();
  CLI::App* command = app.add_subcommand(
      "inject-fault",
      "Make one view of a measurements file faulty (a calibration jump, understated noise or gross outliers), "
      "to test how a method copes; the truth of the clean file scores the result.");
  command->add_option("--measurements", options->measurements, "measurements CSV to start from")->required();
  command->add_option("--out", options->out, "where to write the faulty measurements CSV")->required();
  command->add_option("--view", options->fault.view, "the view to make faulty")->required();
  command
      ->add_option("--kind", options->kind,
                   "jump: its positions move by --jump-m from each scene's middle time on; understated-noise: its "
                   "covariances are divided by --understatement; outliers: a share --outlier-fraction of its rows "
                   "move by a size in --outlier-range-m (horizontal directions, seeded)")
      ->required()
      ->check(CLI::IsMember({"jump", "understated-noise", "outliers"}));
  command->add_option("--jump-m", options->fault.jump_m, "jump: size of the step (m)")->capture_default_str();
  command->add_option("--understatement", options->fault.understatement, "understated-noise: the factor")->capture_default_str();
  command->add_option("--outlier-fraction", options->fault.outlier_fraction, "outliers: probability of a row")->capture_default_str();
  command->add_option("--outlier-range-m", options->outlier_range_m, "outliers: smallest and largest error (m)")
      ->expected(2)
      ->capture_default_str();
  command->add_option("--seed", options->fault.seed, "random seed (directions, which rows)")->capture_default_str();
  command->callback([options] { inject_fault(*options); });
}

}  // namespace stgf::cli
