// SPDX-License-Identifier: Apache-2.0
// The `stgf` executable's side of the seam in learned_seam.hpp: training (train, reproduce) hands the
// command line over to stgf-learned. The subcommands below exist so that
// `stgf --help` lists them; their options, help and work are stgf-learned's.

#include <memory>

#include "commands.hpp"
#include "learned_seam.hpp"

namespace stgf::cli {
namespace {

void add_handed_over_command(CLI::App& app, const std::string& name, const std::string& description) {
  CLI::App* command = app.add_subcommand(name, description);
  // Every argument, --help included, goes to stgf-learned as given.
  command->prefix_command();
  command->set_help_flag();
  command->fallthrough(false);
  command->callback([name] { hand_over_to_learned_cli("stgf " + name); });
}

}  // namespace

void add_train_command(CLI::App& app) {
  add_handed_over_command(app, "train", kTrainDescription);
}

void add_reproduce_command(CLI::App& app) {
  add_handed_over_command(app, "reproduce", kReproduceDescription);
}

}  // namespace stgf::cli
