# SPDX-License-Identifier: Apache-2.0
# Sourced by the scripts that tabulate `ours` over models and splits (scripts/range_scale.sh,
# scripts/across_scenes.sh): score_ours MODEL SPLIT_DIR CONFIG OUT_DIR prints "DE / NEES" of `ours`
# with MODEL and CONFIG on SPLIT_DIR's measurements.csv against its truth.csv, scored from step 2 on.
score_ours() {
  local estimates="$4/estimates.csv"
  rm -f "$estimates"
  build/stgf run --method ours --model "$1" --config "$3" --measurements "$2/measurements.csv" --out "$estimates" 2>/dev/null
  build/stgf eval --truth "$2/truth.csv" --estimates "$estimates" --measurements "$2/measurements.csv" \
    --from-step 2 2>/dev/null | awk -F'|' '$2 ~ /^ *ours *$/ { gsub(/ /, "", $4); gsub(/ /, "", $6); print $4 " / " $6; exit }'
  rm -f "$estimates"
}
