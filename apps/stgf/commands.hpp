// SPDX-License-Identifier: Apache-2.0
#pragma once
// The subcommands of the stgf CLI. Each adds itself to the app; its callback does the work and
// throws stgf::InputError for bad input (exit status 2).

#include <CLI/CLI.hpp>

namespace stgf::cli {

void add_run_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_dataset_command(CLI::App& app);
void add_train_command(CLI::App& app);
void add_reproduce_command(CLI::App& app);
void add_plot_command(CLI::App& app);

}  // namespace stgf::cli
