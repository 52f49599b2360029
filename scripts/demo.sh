#!/usr/bin/env bash
# The main job on built-in data: installs what is missing, builds, makes the mpl benchmark from the
# PETS 2009 data shipped in data/ (seed 1: 4 pedestrians × 7 calibrated cameras per instance, pixel
# noise back-projected to the ground, per-camera calibration error), fuses its test split with every
# method and prints the metrics. Everything it writes goes to build/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null

out=build/demo
seed=1
build/stgf dataset mpl --out "$out/mpl" --seed "$seed"
test_split="$out/mpl/test"
estimates=()
for method in aom wls mmt; do
  build/stgf run --method "$method" --measurements "$test_split/measurements.csv" \
    --config config/methods.yaml --out "$out/estimates-$method.csv"
  estimates+=("$out/estimates-$method.csv")
done
echo
echo "mpl benchmark (PETS 2009 S2L1), seed $seed, test split, scored from step 2 on:"
echo
build/stgf eval --truth "$test_split/truth.csv" --measurements "$test_split/measurements.csv" \
  --estimates "${estimates[@]}" --from-step 2 --json "$out/metrics.json"
