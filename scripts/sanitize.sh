#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer, in build-sanitize/: everything
# that does not need LibTorch (core, methods, io, datasets, model — a trained Φ read and run — the
# examples and the CLI; LibTorch itself is not instrumented, so training's tests run under the release
# build only). Any report fails the run. scripts/test.sh (CI) runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/cores.sh
if [ ! -f build-sanitize/CMakeCache.txt ]; then
  # -O1 -g1 (line tables): half the compile time of -O2 -g under the sanitizers, the reports still
  # name file and line.
  cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -g1" -DSTGF_SANITIZE=ON \
    -DSTGF_WITH_LIBTORCH=OFF -DSTGF_BUILD_PYTHON=OFF -DSTGF_BUILD_BENCHMARKS=OFF >/dev/null
fi
cmake --build build-sanitize --parallel "$cores"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-sanitize --output-on-failure --parallel "$cores" -E installed_package "$@"
