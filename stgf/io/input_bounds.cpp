// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/input_bounds.hpp"

namespace stgf {

std::string quoted_excerpt(const std::string& text) {
  if (text.size() <= kMaxQuotedField) return "'" + text + "'";
  return "'" + text.substr(0, kMaxQuotedField - 20) + "…' (" + std::to_string(text.size()) + " characters)";
}

}  // namespace stgf
