// SPDX-License-Identifier: Apache-2.0
#include "suggestions.hpp"

#include <algorithm>
#include <limits>

namespace stgf::cli {
namespace {

// Optimal string alignment distance (Damerau–Levenshtein without repeated edits of a substring).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// The names a user can type to `command`: its subcommands and its options' long and short names.
std::vector<std::string> typeable_names(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::App* sub : command.get_subcommands([](const CLI::App*) { return true; })) {
    names.push_back(sub->get_name());
  }
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_snames()) names.push_back("-" + name);
  }
  return names;
}

}  // namespace

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  const std::size_t allowed = std::max<std::size_t>(2, word.size() / 3);
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best_distance <= allowed ? best : std::string();
}

std::string suggest_for_unexpected_arguments(const CLI::App& app) {
  // The innermost subcommand the user selected gets the arguments CLI11 left over.
  const CLI::App* command = &app;
  while (true) {
    const std::vector<const CLI::App*> selected = command->get_subcommands([](const CLI::App* sub) { return sub->parsed(); });
    if (selected.empty()) break;
    command = selected.front();
  }
  // Options the subcommand does not know fall through to the app, and stay there.
  std::vector<std::string> candidates = typeable_names(*command);
  if (command != &app) {
    const std::vector<std::string> global = typeable_names(app);
    candidates.insert(candidates.end(), global.begin(), global.end());
  }
  std::string text;
  for (const std::string& argument : app.remaining(true)) {
    // "--metod=x" is the option "--metod".
    const std::string word = argument.substr(0, argument.find('='));
    if (word.empty()) continue;
    // A value after a mistyped option is not itself a mistake to point at.
    if (word.front() != '-' && command->get_subcommands([](const CLI::App*) { return true; }).empty()) continue;
    const std::string match = closest_match(word, candidates);
    std::string where = command->get_name();
    for (const CLI::App* parent = command->get_parent(); parent != nullptr; parent = parent->get_parent()) {
      where = parent->get_name() + " " + where;
    }
    text += where + ": unknown argument '" + word + "'";
    text += match.empty() ? std::string(" (see " + where + " --help)") : " (did you mean '" + match + "'?)";
    text += '\n';
  }
  return text;
}

}  // namespace stgf::cli
