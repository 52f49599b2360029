// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checking the InputError (stgf/io/input_error.hpp) that a reader throws.

#include <gtest/gtest.h>

#include <string>

#include "stgf/io/input_error.hpp"

namespace stgf::testing {

// Runs `read` and expects an InputError located at `path`:`line` whose message starts with
// "path:line: " ("path: " for line 0); returns its message ("" when there was none).
template <typename Read>
std::string expect_input_error(Read read, const std::string& path, int line) {
  try {
    read();
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), path);
    EXPECT_EQ(error.line(), line) << error.what();
    const std::string prefix = line > 0 ? path + ":" + std::to_string(line) + ": " : path + ": ";
    EXPECT_EQ(std::string(error.what()).rfind(prefix, 0), 0u) << error.what();
    return error.what();
  }
  ADD_FAILURE() << "no InputError for " << path << ":" << line;
  return "";
}

}  // namespace stgf::testing
