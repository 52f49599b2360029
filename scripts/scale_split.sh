#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Makes an N-fold copy of a benchmark split, for measuring how `stgf run` and `stgf eval` scale with
# the file (bench/README.md):
#
#   scripts/scale_split.sh SPLIT N OUT      e.g. scripts/scale_split.sh build/reproduce/benchmarks/mpl/test 16 /tmp/mpl-x16
#
# OUT/measurements.csv and OUT/truth.csv are SPLIT's files N times over: the first copy as it is, copy k
# (k = 2..N) with "-copyk" after every scene name, so that every scene stays unique and both files stay
# grouped by scene, in one scene order. Every other field is kept byte for byte. Assumes what stgf's
# benchmarks write: no quoted field holds a comma.
set -euo pipefail
if [ $# -ne 3 ] || ! [[ $2 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 SPLIT N OUT   (SPLIT holds measurements.csv and truth.csv; N >= 1)" >&2
  exit 2
fi
split=$1 copies=$2 out=$3
mkdir -p "$out"
for name in measurements truth; do
  input=$split/$name.csv
  [ -f "$input" ] || { echo "$0: no $input" >&2; exit 2; }
  # The scene column's position, from the header (columns may come in any order).
  column=$(head -n 1 "$input" | tr -d '\r' | tr ',' '\n' | grep -nx 'scene' | cut -d: -f1)
  [ -n "$column" ] || { echo "$0: $input has no scene column" >&2; exit 2; }
  {
    cat "$input"
    for ((k = 2; k <= copies; ++k)); do
      tail -n +2 "$input" | awk -F, -v OFS=, -v column="$column" -v suffix="-copy$k" 'NF { $column = $column suffix } { print }'
    done
  } > "$out/$name.csv.partial"
  mv "$out/$name.csv.partial" "$out/$name.csv"
done
echo "$out: $copies copies of $split ($(($(wc -l < "$out/measurements.csv") - 1)) measurement rows)"
