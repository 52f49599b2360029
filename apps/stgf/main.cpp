// SPDX-License-Identifier: Apache-2.0
// stgf — multi-view collaborative object localization.
//
// Exit status: 0 on success, 2 on bad input or usage (the message names the file and line), 1 on
// any other failure. Output files are written whole or not at all.
//
// This main() serves both executables of the CLI (learned_seam.hpp): `stgf`, and `stgf-learned`
// with the learned motion model linked in.

#include <cstdio>
#include <cstring>
#include <exception>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "learned_seam.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/version.hpp"
#include "suggestions.hpp"

namespace {

// -q/--quiet and -v/--verbose set the log level before any command runs (the commands run inside
// CLI::App::parse, so the flags are read off the command line first; they take no value).
void set_log_level(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--") == 0) break;
    if (std::strcmp(argv[i], "-q") == 0 || std::strcmp(argv[i], "--quiet") == 0) spdlog::set_level(spdlog::level::warn);
    if (std::strcmp(argv[i], "-v") == 0 || std::strcmp(argv[i], "--verbose") == 0) spdlog::set_level(spdlog::level::debug);
  }
}

}  // namespace

int main(int argc, char** argv) {
  stgf::cli::remember_command_line(argc, argv);
  spdlog::set_default_logger(spdlog::stderr_color_mt("stgf"));
  spdlog::set_pattern("stgf: %v");
  set_log_level(argc, argv);

  CLI::App app{
      "stgf fuses the 3D measurements that several views (fixed cameras, connected vehicles) make of the\n"
      "same objects into one position estimate per object, with its covariance.\n"
      "Files and formats: see the README. Exit status: 0 ok, 2 bad input or usage, 1 other failure.",
      "stgf"};
  app.require_subcommand(1);
  app.fallthrough();  // -q and -v may follow the subcommand
  app.set_version_flag("--version", std::string("stgf ") + stgf::kVersion);
  bool quiet = false;
  bool verbose = false;
  CLI::Option* quiet_flag = app.add_flag("-q,--quiet", quiet, "log warnings and errors only");
  app.add_flag("-v,--verbose", verbose, "log debugging detail too")->excludes(quiet_flag);
  stgf::cli::add_dataset_command(app);
  stgf::cli::add_train_command(app);
  stgf::cli::add_reproduce_command(app);
  stgf::cli::add_run_command(app);
  stgf::cli::add_eval_command(app);
  stgf::cli::add_plot_command(app);
  stgf::cli::add_inject_fault_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    if (status != 0) std::fputs(stgf::cli::suggest_for_unexpected_arguments(app).c_str(), stderr);
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
