// SPDX-License-Identifier: Apache-2.0
#pragma once
// The contract every fuzz target checks: a reader given any bytes either returns or throws
// stgf::InputError ("FILE:LINE: …", with a bounded message). Anything else — another exception, a
// crash, a sanitizer report, a hang — is a finding.

#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <exception>
#include <string>
#include <string_view>

#include "stgf/io/input_error.hpp"

namespace stgf::fuzz {

template <typename Reader>
int check_reader(const std::uint8_t* data, std::size_t size, Reader&& read) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    read(text);
  } catch (const InputError& error) {
    // Messages quote at most ~80 characters of a field: never the whole input.
    if (std::string_view(error.what()).size() > 2000) {
      std::fprintf(stderr, "error message of %zu characters\n", std::string_view(error.what()).size());
      std::abort();
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "not an InputError: %s\n", error.what());
    std::abort();
  }
  return 0;
}

}  // namespace stgf::fuzz
