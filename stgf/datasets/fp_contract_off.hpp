// SPDX-License-Identifier: Apache-2.0
#pragma once
// Same seed, same bytes on every machine: keep a·b + c as two rounded operations on every compiler,
// so that files are byte-identical on machines with and without FMA (GCC and Clang contract into
// fused multiply-adds by default when FMA is enabled, e.g. with -march=native). CMake builds this
// layer with -ffp-contract=off; this pragma keeps the promise for any other build of its files.
// Checked: GCC 12 -O0, -O3, -O3 -march=native and Clang 14 -O2 -march=native write identical files.
//
// For the same reason the arithmetic of this layer spells out its dot products and matrix products
// instead of leaving the order of summation to vectorised library code, and draws one random number
// per statement (the order of evaluation of function arguments is unspecified).
//
// Include it in a .cpp file after every other include, in a block of its own (so that include
// sorting leaves it last): the pragma then applies to the file's own functions only.

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")  // GCC ignores the standard pragma in C++
#endif
