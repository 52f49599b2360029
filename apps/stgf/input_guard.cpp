// SPDX-License-Identifier: Apache-2.0
#include "input_guard.hpp"

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace stgf::cli {

void refuse_output_over_input(const std::string& option, const std::string& output,
                              const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
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

}  // namespace stgf::cli
