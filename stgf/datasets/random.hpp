// SPDX-License-Identifier: Apache-2.0
#pragma once
// A random source that gives the same numbers on every platform, for benchmarks that must be
// reproducible from a seed (DESIGN §5).
//
// Why not <random> alone: std::mt19937_64 is specified bit for bit by the C++ standard, but the
// distributions (std::uniform_real_distribution, std::normal_distribution, ...) are not — each
// standard library may turn the same engine output into different numbers. And std::log, std::sin,
// std::exp may differ in the last bit between C libraries. So RandomStream takes only the raw
// 64-bit engine output and builds everything else from + − × ÷ and sqrt, which IEEE 754 rounds
// identically everywhere:
//
//   uniform01   u = ⌊w / 2¹¹⌋ · 2⁻⁵³  for a raw 64-bit word w: the top 53 bits, exactly representable,
//               every value k·2⁻⁵³ (k = 0 … 2⁵³−1) equally likely, u ∈ [0, 1).
//   uniform     a + (b − a)·u.
//   normal      Marsaglia's polar method: draw (p, q) uniform in [−1, 1)² until s = p² + q² ∈ (0, 1);
//               then p·√(−2 ln s / s) and q·√(−2 ln s / s) are two independent N(0, 1) values (the
//               second is kept for the next call).
//   bernoulli   u < probability.
//
// Independent child streams: a stream is identified by a 64-bit key; child(label) and child(index)
// derive a new key from the parent's key (never from how many numbers the parent has drawn), so
//   RandomStream(seed).child("train").child(3)
// is the same stream whatever else was generated before. Keys are mixed with the splitmix64
// finaliser, labels hashed with 64-bit FNV-1a.
//
// Floating-point contraction (a·b + c → one fused multiply-add) would change results between
// machines with and without FMA; the .cpp files of this layer turn it off with a pragma (Clang's
// STDC FP_CONTRACT, GCC's optimize("fp-contract=off"), since GCC contracts by default in C++),
// included from fp_contract_off.hpp.

#include <cstdint>
#include <optional>
#include <random>
#include <string_view>

namespace stgf {

class RandomStream {
 public:
  explicit RandomStream(std::uint64_t key);

  std::uint64_t key() const { return key_; }

  // Independent streams derived from this stream's key (not its state).
  RandomStream child(std::string_view label) const;
  RandomStream child(std::uint64_t index) const;

  std::uint64_t next_word();                // raw engine output
  double uniform01();                       // [0, 1), 53-bit resolution
  double uniform(double low, double high);  // [low, high) (high when low == high)
  double normal();                          // N(0, 1)
  double normal(double mean, double standard_deviation);
  bool bernoulli(double probability);  // true with `probability` (≤ 0 never, ≥ 1 always); one draw

 private:
  std::uint64_t key_;
  std::mt19937_64 engine_;
  std::optional<double> spare_normal_;
};

// The splitmix64 finaliser: a bijective 64-bit mix in which every input bit affects every output bit.
std::uint64_t splitmix64(std::uint64_t value);

// 64-bit FNV-1a of `bytes`: hashes the labels of child streams, and identifies source files.
std::uint64_t fnv1a64(std::string_view bytes);

// Elementary functions built only from + − × ÷, sqrt and exact power-of-two scaling, so that they
// return the same bits on every IEEE 754 platform. Accurate to a few units in the last place, which
// is all a simulation needs; their purpose is reproducibility, not speed.
namespace portable {

double log(double x);  // natural logarithm, x > 0 (NaN otherwise)
double exp(double x);  // e^x; 0 below −745, +∞ above 709.8
struct SineCosine {
  double sine;
  double cosine;
};
SineCosine sin_cos(double radians);  // |radians| up to ~1e6 keeps full accuracy

inline constexpr double kPi = 3.141592653589793238462643383279502884;

}  // namespace portable

}  // namespace stgf
