#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job on built-in data: installs what is missing, builds, and runs `stgf reproduce --quick`
# on the mpl benchmark made from the PETS 2009 data shipped in data/ (seed 1: 4 pedestrians × 7
# calibrated cameras per instance, pixel noise back-projected to the ground, a per-camera
# calibration error that R does not state). It trains the learned motion model Φ (a few epochs),
# runs all six methods on the test split, prints Table I and writes build/demo/results.md with the
# figures in build/demo/figures/. About 70 s on 2 cores. --portable: generic LibTorch and OpenBLAS
# kernels, so the printed table does not depend on the machine's vector units (README, Reliability).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null
build/stgf reproduce --quick --benchmarks mpl --out build/demo --seed 1 --portable
