#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The registration's range scale (design §1.7, `stgf train --range-scale`) measured on the cameras:
# four mpl models trained as scripts/results.sh trains its own (8 epochs, seed 1, --portable) and
# calibrated on mpl val — with one α (the default before 2026-11-28, `--noise-ratio one --no-range-scale`), with per-axis α, with a range scale and one α, and
# with a range scale and per-axis α — each scored by `ours` (and the first and last also with the
# prior's scales learned across scenes, `registration_prior_scale: across-scenes`) on mpl val and
# the 3× and 5× calibration-error proxies' val splits (what the choice is made on), then on their test
# splits. Seed 1. Run scripts/results.sh and scripts/generalization.sh first. Prints a markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/score_ours.sh
bench=build/reproduce/benchmarks/mpl
proxies=build/generalization
[ -d "$bench" ] || { echo "run scripts/results.sh first" >&2; exit 2; }
[ -d "$proxies/mpl-calibration-x5" ] || { echo "run scripts/generalization.sh first" >&2; exit 2; }
out=build/range-scale
mkdir -p "$out"
declare -A options=([default]="--noise-ratio one --no-range-scale" [per-axis]="--noise-ratio per-axis --no-range-scale"
                    [range-scale]="--noise-ratio one --range-scale" [per-axis-range-scale]="--noise-ratio per-axis --range-scale")
for name in default per-axis range-scale per-axis-range-scale; do
  # shellcheck disable=SC2086
  [ -f "$out/$name.pt" ] || build/stgf train --benchmark "$bench" --out "$out/$name.pt" --epochs 8 --seed 1 \
    --threads 2 --portable ${options[$name]} > "$out/$name-train.log" 2>&1
done
printf 'ours:\n  registration_prior_scale: across-scenes\n' > "$out/across-scenes.yaml"
printf 'ours:\n  registration_prior_scale: per-scene\n' > "$out/per-scene.yaml"
echo "| model (calibrated on mpl val) | mpl val | 3× val | 5× val | mpl test | 3× test | 5× test |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for run in default per-axis range-scale per-axis-range-scale default:across-scenes per-axis-range-scale:across-scenes; do
  name=${run%%:*}
  scales=per-scene
  [ "$name" = "$run" ] || scales=${run#*:}
  row="| $name"
  [ "$scales" = per-scene ] || row="$row, κ $scales"
  for split in val test; do
    for dir in "$bench" "$proxies/mpl-calibration-x3" "$proxies/mpl-calibration-x5"; do
      row="$row | $(score_ours "$out/$name.pt" "$dir/$split" "$out/$scales.yaml" "$out")"
    done
  done
  echo "$row |"
done
echo
echo "Calibrations (train logs):"
for name in default per-axis range-scale per-axis-range-scale; do
  echo "- $name: $(grep -o 'translation sigma.*\|range scale sigma.*' "$out/$name-train.log" | tr '\n' ' ')"
done
