// SPDX-License-Identifier: Apache-2.0
// stgf — multi-view collaborative object localization.
//
// Exit status: 0 on success, 2 on bad input or usage (the message names the file and line), 1 on
// any other failure. Output files are written whole or not at all.

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "stgf/io/input_error.hpp"

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("stgf"));
  spdlog::set_pattern("stgf: %v");

  CLI::App app{
      "stgf fuses the 3D measurements that several views (fixed cameras, connected vehicles) make of the\n"
      "same objects into one position estimate per object, with its covariance.\n"
      "Files and formats: see the README. Exit status: 0 ok, 2 bad input or usage, 1 other failure.",
      "stgf"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "stgf 0.1.0");
  stgf::cli::add_dataset_command(app);
  stgf::cli::add_train_command(app);
  stgf::cli::add_reproduce_command(app);
  stgf::cli::add_run_command(app);
  stgf::cli::add_eval_command(app);
  stgf::cli::add_plot_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    return status == 0 ? 0 : 2;
  } catch (const stgf::InputError& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "stgf: %s\n", error.what());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "stgf: error: %s\n", error.what());
    return 1;
  }
  return 0;
}
