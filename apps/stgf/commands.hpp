// SPDX-License-Identifier: Apache-2.0
#pragma once
// The subcommands of the stgf CLI. Each adds itself to the app; its callback does the work and
// throws stgf::InputError for bad input (exit status 2).

#include <CLI/CLI.hpp>

namespace stgf::cli {

// Shared by the commands' two homes (stgf lists them, stgf-learned runs them; learned_seam.hpp).
inline constexpr const char* kTrainDescription =
    "Train the learned motion model Φ on a benchmark folder's train split, validating on val.";
inline constexpr const char* kReproduceDescription =
    "The paper's experiments end to end: build the benchmarks, train the models, run all six methods on the test "
    "splits, and write Table I, the number-of-views curve and trajectory plots.";

void add_run_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_dataset_command(CLI::App& app);
void add_train_command(CLI::App& app);
void add_reproduce_command(CLI::App& app);
void add_plot_command(CLI::App& app);
void add_inject_fault_command(CLI::App& app);

}  // namespace stgf::cli
