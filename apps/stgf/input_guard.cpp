// SPDX-License-Identifier: Apache-2.0
#include "input_guard.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace stgf::cli {
namespace {

namespace fs = std::filesystem;

// The path with links and "." / ".." resolved, as far as it exists.
fs::path resolved(const std::string& path) {
  std::error_code error;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(path, error), error);
  return error ? fs::absolute(path).lexically_normal() : canonical;
}

// Where an input lives: the path itself (a link as a link) and what it resolves to.
std::vector<fs::path> locations(const std::string& input) {
  const fs::path absolute = fs::absolute(input).lexically_normal();
  const fs::path own = absolute.has_parent_path() ? resolved(absolute.parent_path().string()) / absolute.filename()
                                                  : absolute;
  return {own, resolved(input)};
}

bool is_at_or_under(const fs::path& path, const fs::path& folder) {
  const auto [folder_end, path_end] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
  return folder_end == folder.end();
}

[[noreturn]] void refuse(const std::string& option, const std::string& output, const std::string& input) {
  throw std::invalid_argument(option + " " + output + " would overwrite the input " + input +
                              ": writing there would destroy it; choose another output path");
}

}  // namespace

void refuse_output_over_input(const std::string& option, const std::string& output,
                              const std::vector<std::string>& inputs) {
  std::error_code error;
  if (output.empty() || !fs::exists(output, error)) return;
  for (const std::string& input : inputs) {
    if (input.empty() || !fs::exists(input, error)) continue;
    if (fs::equivalent(output, input, error)) {
      throw std::invalid_argument(option + " " + output + " is the input file " + input +
                                  ": writing there would destroy it; choose another output path");
    }
  }
}

void refuse_outputs_over_inputs(const std::string& option, const std::vector<std::string>& written,
                                const std::vector<std::string>& inputs) {
  for (const std::string& output : written) {
    if (output.empty()) continue;
    const fs::path target = resolved(output);
    for (const std::string& input : inputs) {
      if (input.empty()) continue;
      for (const fs::path& location : locations(input)) {
        if (is_at_or_under(location, target)) refuse(option, output, input);
      }
    }
  }
}

void refuse_prefixed_outputs_over_inputs(const std::string& option, const std::string& folder,
                                         const std::string& prefix, const std::vector<std::string>& inputs) {
  const fs::path target = resolved(folder);
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    for (const fs::path& path : locations(input)) {
      if (path.parent_path() == target && path.filename().string().starts_with(prefix)) {
        refuse(option, (fs::path(folder) / (prefix + "*")).string(), input);
      }
    }
  }
}

}  // namespace stgf::cli
