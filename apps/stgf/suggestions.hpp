// SPDX-License-Identifier: Apache-2.0
#pragma once
// "Did you mean …?" for a mistyped subcommand or option.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace stgf::cli {

// The candidate closest to `word` in edit distance (insertions, deletions, substitutions and swaps
// of neighbours each cost 1), if it is within max(2, |word| / 3); "" otherwise.
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

// For a parse error over `app`: a line naming each argument CLI11 did not expect and the closest
// subcommand or option of the (sub)command it was given to, e.g.
//   "stgf: unknown argument 'rn' (did you mean 'run'?)". "" when there is nothing to add.
std::string suggest_for_unexpected_arguments(const CLI::App& app);

}  // namespace stgf::cli
