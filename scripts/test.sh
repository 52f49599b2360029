#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs what is missing, builds, and runs the whole test suite through ctest. Then:
#   - the learned model's tests once more with one OpenMP thread and OpenBLAS on its Haswell kernels
#     (results must not depend on the thread count or the BLAS kernel choice);
#   - the core, the methods and the trained model's reader built and tested without LibTorch and without
#     the general model (build-core/, -DSTGF_WITH_LIBTORCH=OFF -DSTGF_GENERAL_MODEL=OFF), and
#     `stgf run --method ours` run there;
#   - everything that does not need LibTorch (all but training) again under ASan + UBSan
#     (scripts/sanitize.sh, build-sanitize/): any report fails the run;
#   - every reader fuzzed for 10 s (scripts/fuzz.sh: libFuzzer with ASan + UBSan, and the model file's
#     mutation harness).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/cores.sh
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$cores" "$@"

echo "== the learned model's tests with OMP_NUM_THREADS=1 OPENBLAS_CORETYPE=Haswell"
OMP_NUM_THREADS=1 OPENBLAS_CORETYPE=Haswell build/tests/test_learn --gtest_brief=1

echo "== the core, the methods and a trained model without LibTorch (build-core/)"
# Also without the general model (-DSTGF_GENERAL_MODEL=OFF, for builds that must not carry KITTI's terms).
cmake -S . -B build-core -G Ninja -DCMAKE_BUILD_TYPE=Release -DSTGF_WITH_LIBTORCH=OFF -DSTGF_BUILD_PYTHON=OFF \
  -DSTGF_BUILD_BENCHMARKS=OFF -DSTGF_GENERAL_MODEL=OFF >/dev/null
cmake --build build-core --parallel "$cores" --target test_core test_methods test_model stgf_cli
if ldd build-core/tests/test_core build-core/tests/test_methods build-core/tests/test_model build-core/stgf | grep -q libtorch; then
  echo "build-core links LibTorch" >&2
  exit 1
fi
build-core/tests/test_core --gtest_brief=1
build-core/tests/test_methods --gtest_brief=1
build-core/tests/test_model --gtest_brief=1
# A trained model runs without LibTorch: `ours` with the tests' small model on a small synthetic benchmark.
rm -rf build-core/sample && build-core/stgf dataset synthetic --out build-core/sample --seed 1 --scenes 2 --steps 20 -q
build-core/stgf run --method ours --model tests/model/data/tiny-motion-model.pt \
  --measurements build-core/sample/test/measurements.csv --out build-core/sample/ours.csv -q
# Without the general model, ours needs --model, and says so.
if build-core/stgf run --method ours --measurements build-core/sample/test/measurements.csv \
  --out build-core/sample/ours-general.csv 2> build-core/sample/general.err ||
  ! grep -q "built without its general model" build-core/sample/general.err; then
  echo "build-core: ours without --model and without the general model did not stop with the reason" >&2
  exit 1
fi

echo "== the suite under AddressSanitizer + UndefinedBehaviorSanitizer (scripts/sanitize.sh, build-sanitize/)"
scripts/sanitize.sh

echo "== a short fuzzing run of every reader (scripts/fuzz.sh; longer runs: scripts/fuzz.sh SECONDS)"
scripts/fuzz.sh 10
