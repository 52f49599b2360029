// SPDX-License-Identifier: Apache-2.0
#pragma once
// What stgf's readers accept, so that no later step overflows, underflows or turns singular: a value
// outside these bounds is an InputError at its file and line (README "Files"; DESIGN §3.7).
//
//   times (t, arrival)             |t| ≤ 1e10 s         Unix time in seconds fits (to the year 2286);
//                                                       written with 6 decimals, a time keeps 1 µs
//   coordinates (x, y, z, sensor)  |x| ≤ 1e7 m          Earth-centred (ECEF) coordinates fit
//   covariance diagonal            1e-12 ≤ C_ii ≤ 1e12 m²   σ from 1 µm to 1000 km; with the condition
//                                                       number ≤ 1e12 (gaussian.hpp) every eigenvalue
//                                                       then lies in [1e-24, 3e12] m², far from
//                                                       subnormal numbers and from overflow in Λ = C⁻¹
//
// Messages quote at most kMaxQuotedField characters of a field.

#include <string>

namespace stgf {

inline constexpr double kMaxAbsTime = 1e10;
inline constexpr double kMaxAbsCoordinate = 1e7;
inline constexpr double kMinVariance = 1e-12;
inline constexpr double kMaxVariance = 1e12;
inline constexpr std::size_t kMaxQuotedField = 80;

// 'text' in quotes, or its first characters and its length when longer than kMaxQuotedField.
std::string quoted_excerpt(const std::string& text);

}  // namespace stgf
