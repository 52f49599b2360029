// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/random.hpp"

#include <cmath>
#include <limits>

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

// Domain separators, so that a label whose hash equals some index still gives a different child.
constexpr std::uint64_t kLabelDomain = 0x6c6162656c000001ULL;
constexpr std::uint64_t kIndexDomain = 0x696e646578000002ULL;

std::uint64_t derive_key(std::uint64_t parent_key, std::uint64_t tag) {
  return splitmix64(splitmix64(parent_key) ^ splitmix64(tag));
}

constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;  // 2⁻⁵³

// ln 2 split into a high part with trailing zero bits (so k·high is exact for |k| < 2¹¹) and the rest.
constexpr double kLn2High = 6.93147180369123816490e-01;
constexpr double kLn2Low = 1.90821492927058770002e-10;
constexpr double kInverseLn2 = 1.44269504088896338700e+00;
// π/2 split likewise (k·high exact for |k| < 2²⁰).
constexpr double kHalfPiHigh = 1.57079632673412561417e+00;
constexpr double kHalfPiLow = 6.07710050650619224932e-11;
constexpr double kTwoOverPi = 6.36619772367581382433e-01;

// sin r and cos r for |r| ≤ π/4 from their Taylor series in nested form:
//   sin r = r (1 − r²/(2·3) (1 − r²/(4·5) (1 − …)))
//   cos r = 1 − r²/(1·2) (1 − r²/(3·4) (1 − …))
// Twelve levels leave a truncation error below r²⁶/26! < 1e-28.
portable::SineCosine sin_cos_reduced(double r) {
  const double r2 = r * r;
  constexpr int kLevels = 12;
  double sine = 1.0;
  double cosine = 1.0;
  for (int level = kLevels; level >= 1; --level) {
    const double even = 2.0 * level;
    sine = 1.0 - r2 / (even * (even + 1.0)) * sine;
    cosine = 1.0 - r2 / ((even - 1.0) * even) * cosine;
  }
  return {r * sine, cosine};
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t value) {
  std::uint64_t mixed = value + 0x9e3779b97f4a7c15ULL;
  mixed = (mixed ^ (mixed >> 30)) * 0xbf58476d1ce4e5b9ULL;
  mixed = (mixed ^ (mixed >> 27)) * 0x94d049bb133111ebULL;
  return mixed ^ (mixed >> 31);
}

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t hash = 14695981039346656037ULL;
  for (const char byte : bytes) {
    hash ^= static_cast<unsigned char>(byte);
    hash *= 1099511628211ULL;
  }
  return hash;
}

RandomStream::RandomStream(std::uint64_t key) : key_(key), engine_(splitmix64(key)) {}

RandomStream RandomStream::child(std::string_view label) const {
  return RandomStream(derive_key(key_, fnv1a64(label) ^ kLabelDomain));
}

RandomStream RandomStream::child(std::uint64_t index) const {
  return RandomStream(derive_key(key_, splitmix64(index) ^ kIndexDomain));
}

std::uint64_t RandomStream::next_word() { return engine_(); }

double RandomStream::uniform01() { return static_cast<double>(next_word() >> 11) * kTwoToMinus53; }

double RandomStream::uniform(double low, double high) { return low + (high - low) * uniform01(); }

double RandomStream::normal() {
  if (spare_normal_) {
    const double value = *spare_normal_;
    spare_normal_.reset();
    return value;
  }
  while (true) {
    const double p = uniform(-1.0, 1.0);
    const double q = uniform(-1.0, 1.0);
    const double s = p * p + q * q;
    if (s <= 0.0 || s >= 1.0) continue;
    const double factor = std::sqrt(-2.0 * portable::log(s) / s);
    spare_normal_ = q * factor;
    return p * factor;
  }
}

double RandomStream::normal(double mean, double standard_deviation) {
  return mean + standard_deviation * normal();
}

bool RandomStream::bernoulli(double probability) { return uniform01() < probability; }

namespace portable {

// x = m·2ᵉ with m ∈ [√½, √2) (frexp is exact), then with s = (m − 1)/(m + 1), |s| ≤ 0.172:
//   ln m = 2 atanh s = 2 (s + s³/3 + s⁵/5 + …)
// Fourteen terms leave a truncation error below s²⁹ < 1e-22.
double log(double x) {
  if (std::isnan(x) || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return -std::numeric_limits<double>::infinity();
  if (std::isinf(x)) return x;
  int exponent = 0;
  double mantissa = std::frexp(x, &exponent);  // [0.5, 1)
  if (mantissa < 0.70710678118654752440) {
    mantissa *= 2.0;
    exponent -= 1;
  }
  const double s = (mantissa - 1.0) / (mantissa + 1.0);
  const double s2 = s * s;
  constexpr int kTerms = 14;
  double series = 1.0 / (2.0 * kTerms + 1.0);
  for (int term = kTerms - 1; term >= 0; --term) series = 1.0 / (2.0 * term + 1.0) + s2 * series;
  const double k = static_cast<double>(exponent);
  return k * kLn2High + (k * kLn2Low + 2.0 * s * series);
}

// x = k ln 2 + r with k the nearest integer to x/ln 2 and |r| ≤ 0.35, then
//   eˣ = 2ᵏ · eʳ,   eʳ = 1 + r (1 + r/2 (1 + r/3 (1 + …)))
// to the r¹⁸ term (truncation below 0.35¹⁹/19! < 1e-25).
double exp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.78) return std::numeric_limits<double>::infinity();
  if (x < -745.2) return 0.0;
  const double k = std::floor(x * kInverseLn2 + 0.5);
  const double r = (x - k * kLn2High) - k * kLn2Low;
  constexpr int kTerms = 18;
  double series = 1.0;
  for (int term = kTerms; term >= 1; --term) series = 1.0 + r / term * series;
  // Scale in two halves so that 2ᵏ itself never overflows or underflows before the product does.
  const int half = static_cast<int>(k) / 2;
  return std::ldexp(std::ldexp(series, half), static_cast<int>(k) - half);
}

// θ = q·π/2 + r with q the nearest integer to 2θ/π (Cody–Waite reduction, |r| ≤ π/4), then the
// quadrant q mod 4 picks the signs and swaps sine and cosine.
SineCosine sin_cos(double radians) {
  if (!std::isfinite(radians)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  const double q = std::floor(radians * kTwoOverPi + 0.5);
  const double r = (radians - q * kHalfPiHigh) - q * kHalfPiLow;
  const SineCosine reduced = sin_cos_reduced(r);
  const long long quadrant = ((static_cast<long long>(q) % 4) + 4) % 4;
  switch (quadrant) {
    case 0:
      return {reduced.sine, reduced.cosine};
    case 1:
      return {reduced.cosine, -reduced.sine};
    case 2:
      return {-reduced.sine, -reduced.cosine};
    default:
      return {-reduced.cosine, reduced.sine};
  }
}

}  // namespace portable
}  // namespace stgf
