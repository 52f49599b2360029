#!/usr/bin/env bash
# The main job on built-in data: installs what is missing, builds, simulates a multi-view scene
# (synthetic benchmark, seed 7), fuses its test split with every method and prints the metrics.
# Everything it writes goes to build/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null

out=build/demo
seed=7
build/stgf dataset synthetic --out "$out/synthetic" --seed "$seed"
test_split="$out/synthetic/test"
estimates=()
for method in aom wls mmt; do
  build/stgf run --method "$method" --measurements "$test_split/measurements.csv" \
    --config config/methods.yaml --out "$out/estimates-$method.csv"
  estimates+=("$out/estimates-$method.csv")
done
echo
echo "Synthetic benchmark, seed $seed, test split (scored from step 2 on):"
echo
build/stgf eval --truth "$test_split/truth.csv" --measurements "$test_split/measurements.csv" \
  --estimates "${estimates[@]}" --from-step 2 --json "$out/metrics.json"
