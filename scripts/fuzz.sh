#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets (fuzz/: one per reader, the model file's LibTorch-free reader included:
# trained_model) with clang, ASan and UBSan in build-fuzz/,
# and runs each for SECONDS (default 15) from its seed corpus (fuzz/corpus/TARGET, plus what earlier
# runs found, kept in build-fuzz/corpus/TARGET). Any crash, sanitizer report, hang (>10 s per input)
# or exception other than stgf::InputError fails the run and leaves the input in build-fuzz/.
# LibTorch's reading of the model file ("model") is fuzzed by build/fuzz/fuzz_model_file, a mutation
# harness (fuzz/mutate_model_file.cpp), for 20 × SECONDS mutated files.
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: measurements truth estimates config trained_model model
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/cores.sh
seconds=${1:-15}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(measurements truth estimates config trained_model model)

if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CXX=clang++ CC=clang cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTGF_BUILD_FUZZERS=ON \
    -DSTGF_BUILD_TESTS=OFF -DSTGF_BUILD_BENCHMARKS=OFF -DSTGF_BUILD_PYTHON=OFF >/dev/null
fi
text_targets=()
for target in "${targets[@]}"; do [ "$target" != model ] && text_targets+=("$target"); done
[ ${#text_targets[@]} -gt 0 ] && cmake --build build-fuzz --parallel "$cores" $(printf -- '--target fuzz_%s ' "${text_targets[@]}")

if [[ " ${targets[*]} " == *" model "* ]]; then
  # A small model file as the seed (a model file is binary: made here, not stored).
  scripts/build.sh >/dev/null
  mkdir -p build-fuzz/seed
  if [ ! -f build-fuzz/seed/model.pt ]; then
    build/stgf dataset synthetic --out build-fuzz/seed/bench --seed 1 --scenes 2 --objects 2 --views 2 --steps 12 -q
    build/stgf train --benchmark build-fuzz/seed/bench --out build-fuzz/seed/model.pt --epochs 1 --threads 1 -q
  fi
  echo "== fuzz_model_file: $((20 * seconds)) mutated model files"
  build/fuzz/fuzz_model_file build-fuzz/seed/model.pt $((20 * seconds)) 1
fi

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for target in "${text_targets[@]}"; do
  corpus=build-fuzz/corpus/$target
  mkdir -p "$corpus"
  [ -d "fuzz/corpus/$target" ] && cp -n fuzz/corpus/"$target"/* "$corpus"/ 2>/dev/null || true
  [ "$target" = trained_model ] && cp -n tests/model/data/*.pt models/general.pt "$corpus"/ 2>/dev/null || true
  echo "== fuzz_$target for ${seconds} s"
  # A fixed seed and a fixed number of inputs (about SECONDS on this machine): the same run every
  # time, so CI does not turn red at random; longer runs explore further.
  (cd build-fuzz && fuzz/fuzz_"$target" -seed=1 -runs=$((seconds * 5000)) -max_total_time=$((seconds * 10)) -timeout=10 -rss_limit_mb=4096 -max_len=65536 \
    -print_final_stats=1 "corpus/$target" 2>&1 | grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|==|SUMMARY|ERROR|Done)" || true)
  # libFuzzer's exit status is lost in the pipe above; a finding leaves crash-*, leak-*, timeout-* or oom-*.
  if compgen -G "build-fuzz/crash-*" >/dev/null || compgen -G "build-fuzz/leak-*" >/dev/null ||
     compgen -G "build-fuzz/timeout-*" >/dev/null || compgen -G "build-fuzz/oom-*" >/dev/null; then
    echo "fuzz_$target found a failing input:" >&2
    ls build-fuzz/crash-* build-fuzz/leak-* build-fuzz/timeout-* build-fuzz/oom-* 2>/dev/null >&2
    exit 1
  fi
done
echo "fuzzing: no finding"
