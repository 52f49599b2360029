#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Configures (once) and builds stgf into build/. The CLI ends up at build/stgf.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/cores.sh
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build --parallel "$cores"
