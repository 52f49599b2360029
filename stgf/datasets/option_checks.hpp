// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checks of a benchmark builder's options, shared by every builder so that they reject bad options
// with the same words. Every failure throws std::invalid_argument with a message that starts with
// the builder's name and names the option, the rule and the value:
//   "<builder>: <name> must be at least <minimum> (got <value>)"        whole numbers
//   "<builder>: <name> must be <rule> (got <value>)"                    real numbers
//   "<builder>: <low name> (<low>) must not exceed <high name> (<high>)"  pairs of bounds
// A real number that is NaN or infinite fails every rule.

#include <string>
#include <string_view>

namespace stgf {

inline constexpr double kMaxBenchmarkRows = 1e8;

class OptionChecks {
 public:
  // `builder` starts every message, e.g. "synthetic benchmark".
  explicit OptionChecks(std::string_view builder);

  // Throws "<builder>: <what>".
  [[noreturn]] void reject(std::string_view what) const;

  // value ≥ minimum.
  void whole(std::string_view name, int value, int minimum) const;
  // `holds` is the rule evaluated on the value, `rule` says it in words ("in (0, 1)").
  void real(std::string_view name, double value, bool holds, std::string_view rule) const;
  void positive(std::string_view name, double value) const;      // > 0: "positive"
  void not_negative(std::string_view name, double value) const;  // ≥ 0: "zero or positive"
  void probability(std::string_view name, double value) const;   // in [0, 1]: "a probability in [0, 1]"
  // low ≤ high.
  void range(std::string_view low_name, int low, std::string_view high_name, int high) const;
  // A benchmark of at most kMaxBenchmarkRows measurement rows (about 10 GB of CSV): `rows` is the
  // most the options can give, `formula` says how it was counted ("scenes × steps × objects × views").
  void size(double rows, std::string_view formula) const;
  void range(std::string_view low_name, double low, std::string_view high_name, double high) const;

 private:
  std::string builder_;
};

}  // namespace stgf
