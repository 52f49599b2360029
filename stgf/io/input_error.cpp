// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

std::string located(const std::string& file, int line, const std::string& what) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + what : file + ": " + what;
}

}  // namespace

InputError::InputError(const std::string& file, int line, const std::string& what)
    : std::runtime_error(located(file, line, what)), file_(file), line_(line) {}

}  // namespace stgf
