#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# What learning the filter's online scales across a run's scenes does (design §1.2 and §1.7): `ours`
# DE / NEES on validation splits with Q's λ and the registration prior's κ learned per scene, Q's
# across scenes (`process_noise_scale: across-scenes`), the registration's across scenes
# (`registration_prior_scale: across-scenes`), both, Q `auto` with the registration's scales
# lowered across scenes (`shrink-across-scenes`), and the defaults (both `auto`: for a model of several
# benchmarks Q across scenes, κ held across scenes where the sensors move and lowered across scenes
# where they stand still; per scene for a model of one) — for each benchmark's own model, the general
# model and the leave-one-dataset-out models, on their own and on others' data, and on the camera
# proxies. Validation splits only: what the defaults are chosen on. Seed 1. Run scripts/results.sh,
# scripts/generalization.sh and scripts/general_model.sh first. Prints a markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/score_ours.sh
models=build/reproduce/models
benchmarks=build/reproduce/benchmarks
proxies=build/generalization
general=build/general-model
for need in "$models/mpl.pt" "$proxies/mpl-calibration-x5" "$general/without-cad.pt"; do
  [ -e "$need" ] || { echo "$need is missing: run scripts/results.sh, generalization.sh and general_model.sh first" >&2; exit 2; }
done
out=build/across-scenes
mkdir -p "$out"
configs=(per-scene q-across registration-across both-across q-auto-shrink defaults)
printf 'ours:\n  process_noise_scale: per-scene\n  registration_prior_scale: per-scene\n' > "$out/per-scene.yaml"
printf 'ours:\n  process_noise_scale: across-scenes\n  registration_prior_scale: per-scene\n' > "$out/q-across.yaml"
printf 'ours:\n  process_noise_scale: per-scene\n  registration_prior_scale: across-scenes\n' > "$out/registration-across.yaml"
printf 'ours:\n  process_noise_scale: across-scenes\n  registration_prior_scale: across-scenes\n' > "$out/both-across.yaml"
printf 'ours:\n  process_noise_scale: auto\n  registration_prior_scale: shrink-across-scenes\n' > "$out/q-auto-shrink.yaml"
printf 'ours:\n  process_noise_scale: auto\n  registration_prior_scale: auto\n' > "$out/defaults.yaml"
echo "| model | validation split | Q, κ per scene | Q across scenes | κ across scenes | both across scenes | Q auto, κ lowered across scenes | the defaults (Q, κ auto) |"
echo "|---|---|---:|---:|---:|---:|---:|---:|"
row() {  # MODEL_NAME MODEL SPLIT_NAME SPLIT_DIR
  local line="| $1 | $3"
  for config in "${configs[@]}"; do line="$line | $(score_ours "$2" "$4" "$out/$config.yaml" "$out")"; done
  echo "$line |"
}
row mpl "$models/mpl.pt" mpl "$benchmarks/mpl/val"
row mpl "$models/mpl.pt" "mpl, 3× calibration error" "$proxies/mpl-calibration-x3/val"
row mpl "$models/mpl.pt" "mpl, 5× calibration error" "$proxies/mpl-calibration-x5/val"
row mpl "$models/mpl.pt" "mpl, no calibration error" "$proxies/mpl-calibration-x0/val"
row mpl "$models/mpl.pt" ethucy "$proxies/ethucy/val"
row cad "$models/cad.pt" cad "$benchmarks/cad/val"
row cad "$models/cad.pt" ethucy "$proxies/ethucy/val"
row general models/general.pt mpl "$benchmarks/mpl/val"
row general models/general.pt cad "$benchmarks/cad/val"
row general models/general.pt ethucy "$general/ethucy/val"
row general models/general.pt "mpl, own clocks" "$benchmarks/mpl-async/val"
row general models/general.pt "cad, own clocks" "$benchmarks/cad-async/val"
row general models/general.pt "mpl, 3× calibration error" "$proxies/mpl-calibration-x3/val"
row general models/general.pt "mpl, 5× calibration error" "$proxies/mpl-calibration-x5/val"
row general models/general.pt "mpl, no calibration error" "$proxies/mpl-calibration-x0/val"
row "without mpl (cad + ethucy)" "$general/without-mpl.pt" mpl "$benchmarks/mpl/val"
row "without cad (mpl + ethucy)" "$general/without-cad.pt" cad "$benchmarks/cad/val"
row "without ethucy (mpl + cad)" "$general/without-ethucy.pt" ethucy "$general/ethucy/val"
