// SPDX-License-Identifier: Apache-2.0
// The option checks every benchmark builder uses (datasets/option_checks.hpp): each rule passes the
// values it allows, and fails the others with the message the builders' users read.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "stgf/datasets/option_checks.hpp"

namespace stgf {
namespace {

const OptionChecks kCheck("test benchmark");
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The message of the std::invalid_argument that `check` throws ("" when it throws none).
std::string message_of(const std::function<void()>& check) {
  try {
    check();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(OptionChecks, RejectPrefixesTheBuilder) {
  EXPECT_EQ(message_of([] { kCheck.reject("views must name at least one camera"); }),
            "test benchmark: views must name at least one camera");
}

TEST(OptionChecks, WholeNumbersHaveAMinimum) {
  EXPECT_EQ(message_of([] { kCheck.whole("steps", 2, 2); }), "");
  EXPECT_EQ(message_of([] { kCheck.whole("steps", 1, 2); }),
            "test benchmark: steps must be at least 2 (got 1)");
}

TEST(OptionChecks, RealNumbersFollowTheirRuleAndAreFinite) {
  EXPECT_EQ(message_of([] { kCheck.real("val_fraction", 0.5, true, "in (0, 1)"); }), "");
  EXPECT_EQ(message_of([] { kCheck.real("val_fraction", 1.5, false, "in (0, 1)"); }),
            "test benchmark: val_fraction must be in (0, 1) (got 1.5)");
  // NaN and infinity fail even when the rule (wrongly) holds.
  EXPECT_EQ(message_of([] { kCheck.real("rate_hz", std::nan(""), true, "positive"); }),
            "test benchmark: rate_hz must be positive (got nan)");
  EXPECT_EQ(message_of([] { kCheck.real("rate_hz", kInfinity, true, "positive"); }),
            "test benchmark: rate_hz must be positive (got inf)");
}

TEST(OptionChecks, NamedRulesSayWhatTheyCheck) {
  EXPECT_EQ(message_of([] { kCheck.positive("range_noise_m", 1e-9); }), "");
  EXPECT_EQ(message_of([] { kCheck.positive("range_noise_m", 0.0); }),
            "test benchmark: range_noise_m must be positive (got 0)");
  EXPECT_EQ(message_of([] { kCheck.not_negative("stop_rate_per_s", 0.0); }), "");
  EXPECT_EQ(message_of([] { kCheck.not_negative("stop_rate_per_s", -0.25); }),
            "test benchmark: stop_rate_per_s must be zero or positive (got -0.25)");
  EXPECT_EQ(message_of([] { kCheck.probability("detection_probability", 0.0); }), "");
  EXPECT_EQ(message_of([] { kCheck.probability("detection_probability", 1.0); }), "");
  EXPECT_EQ(message_of([] { kCheck.probability("detection_probability", 1.5); }),
            "test benchmark: detection_probability must be a probability in [0, 1] (got 1.5)");
  EXPECT_NE(message_of([] { kCheck.probability("detection_probability", -kInfinity); }), "");
}

TEST(OptionChecks, RangesNeedLowAtMostHigh) {
  EXPECT_EQ(message_of([] { kCheck.range("min_objects", 2, "max_objects", 2); }), "");
  EXPECT_EQ(message_of([] { kCheck.range("min_objects", 3, "max_objects", 2); }),
            "test benchmark: min_objects (3) must not exceed max_objects (2)");
  EXPECT_EQ(message_of([] { kCheck.range("min_stop_s", 1.0, "max_stop_s", 4.0); }), "");
  EXPECT_EQ(message_of([] { kCheck.range("min_stop_s", 4.5, "max_stop_s", 4.0); }),
            "test benchmark: min_stop_s (4.5) must not exceed max_stop_s (4)");
  EXPECT_NE(message_of([] { kCheck.range("min_stop_s", std::nan(""), "max_stop_s", 4.0); }), "");
}

}  // namespace
}  // namespace stgf
