// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/option_checks.hpp"

#include <cstdio>

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace stgf {
namespace {

template <typename Number>
void check_range(const OptionChecks& check, std::string_view low_name, Number low, std::string_view high_name,
                 Number high) {
  if (!(low <= high))
    check.reject(fmt::format("{} ({}) must not exceed {} ({})", low_name, low, high_name, high));
}

}  // namespace

OptionChecks::OptionChecks(std::string_view builder) : builder_(builder) {}

void OptionChecks::reject(std::string_view what) const {
  throw std::invalid_argument(fmt::format("{}: {}", builder_, what));
}

void OptionChecks::whole(std::string_view name, int value, int minimum) const {
  if (value < minimum) reject(fmt::format("{} must be at least {} (got {})", name, minimum, value));
}

void OptionChecks::real(std::string_view name, double value, bool holds, std::string_view rule) const {
  if (!std::isfinite(value) || !holds) reject(fmt::format("{} must be {} (got {})", name, rule, value));
}

void OptionChecks::positive(std::string_view name, double value) const {
  real(name, value, value > 0.0, "positive");
}

void OptionChecks::not_negative(std::string_view name, double value) const {
  real(name, value, value >= 0.0, "zero or positive");
}

void OptionChecks::probability(std::string_view name, double value) const {
  real(name, value, value >= 0.0 && value <= 1.0, "a probability in [0, 1]");
}

void OptionChecks::range(std::string_view low_name, int low, std::string_view high_name, int high) const {
  check_range(*this, low_name, low, high_name, high);
}

void OptionChecks::range(std::string_view low_name, double low, std::string_view high_name,
                         double high) const {
  check_range(*this, low_name, low, high_name, high);
}

void OptionChecks::size(double rows, std::string_view formula) const {
  if (rows <= kMaxBenchmarkRows) return;
  char text[64];
  std::snprintf(text, sizeof text, "%.3g", rows);
  reject(std::string(formula) + " allows up to " + text +
         " measurement rows, more than the 1e8 a benchmark may have (about 10 GB of CSV)");
}

}  // namespace stgf
