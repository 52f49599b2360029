#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The installed package as a user gets it: `cmake --install` into a temporary prefix, then
#   1. a core-only consumer (find_package(stgf 0.2), stgf::core) builds, has no LibTorch on its link
#      line, and runs;
#   2. a consumer of stgf::stgf streams measurements through the filter with a model file;
#   3. the installed CLI, moved away from the build tree, finds its shipped data and its LibTorch half;
#   4. the installed Python module imports from the prefix (when built).
# Usage: test_installed_package.sh BUILD_DIR SOURCE_DIR WITH_LIBTORCH(0|1)
set -euo pipefail
build=$1
source=$2
with_libtorch=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/stgf-package.XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >"$work/install.log"
# Nothing installed names the build or source tree.
if grep -rlF -e "$build" -e "$source" "$prefix" --exclude='*.cmake' >"$work/leaks.txt"; then
  echo "installed files name the build or source tree:" >&2
  cat "$work/leaks.txt" >&2
  exit 1
fi

consumers=(core_consumer)
[ "$with_libtorch" = 1 ] && consumers+=(filter_consumer)
for consumer in "${consumers[@]}"; do
  cmake -S "$source/tests/package/$consumer" -B "$work/$consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" >"$work/$consumer.configure.log" || { cat "$work/$consumer.configure.log" >&2; exit 1; }
  cmake --build "$work/$consumer" --verbose >"$work/$consumer.build.log" 2>&1 || { cat "$work/$consumer.build.log" >&2; exit 1; }
done
if grep -E "torch|c10|stgf_learn" "$work/core_consumer.build.log" >/dev/null; then
  echo "the core-only consumer's link line names LibTorch or stgf_learn:" >&2
  grep -E "torch|c10|stgf_learn" "$work/core_consumer.build.log" >&2
  exit 1
fi
"$work/core_consumer/core_consumer"
[ "$with_libtorch" = 1 ] && "$work/filter_consumer/filter_consumer" "$work/model.pt"

# The installed CLI, run from an unrelated directory.
cd "$work"
"$prefix/bin/stgf" --version
"$prefix/bin/stgf" dataset mpl --out "$work/mpl" --train 2 --val 1 --test 2 --steps 8 --pedestrians 2 -q
"$prefix/bin/stgf" run --method wls --measurements "$work/mpl/test/measurements.csv" --out "$work/wls.csv" -q
# The general model is part of the installed library: ours runs without a model file.
"$prefix/bin/stgf" run --method ours --measurements "$work/mpl/test/measurements.csv" --out "$work/ours-general.csv" \
  2> "$work/ours-general.log"
grep -q "no --model given: stgf's general model" "$work/ours-general.log" || { cat "$work/ours-general.log" >&2; exit 1; }
if [ "$with_libtorch" = 1 ]; then
  "$prefix/bin/stgf" train --benchmark "$work/mpl" --out "$work/trained.pt" --epochs 1 --threads 1 -q
  "$prefix/bin/stgf" run --method ours --model "$work/trained.pt" --measurements "$work/mpl/test/measurements.csv" \
    --out "$work/ours.csv" -q
  "$prefix/bin/stgf" eval --truth "$work/mpl/test/truth.csv" --estimates "$work/ours.csv" "$work/wls.csv" >/dev/null
else
  "$prefix/bin/stgf" eval --truth "$work/mpl/test/truth.csv" --estimates "$work/wls.csv" >/dev/null
fi

if [ -n "${STGF_PYTHON_EXECUTABLE:-}" ]; then
  PYTHONPATH=$(echo "$prefix"/lib/python3*/site-packages) "$STGF_PYTHON_EXECUTABLE" -c \
    "import stgf; assert stgf.__version__.startswith('0.2'), stgf.__version__; \
assert stgf.general_model().metadata['input'] == 'fused'; print('python', stgf.__version__)"
fi
echo "installed package: ok"
