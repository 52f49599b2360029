#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Regenerates docs/without-truth.md: `stgf train` on the mpl and cad benchmarks of scripts/results.sh
# with their train/ and val/ truth taken away (measurements only, as a user's own recordings are),
# against the models results.sh trained with the truth. Same epochs (8), seed (1), threads (2) and
# --portable as results.sh. The test splits keep their truth, to score both. About 8 minutes on 2
# cores. Run scripts/results.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/results_models.sh
out=build/without-truth
mkdir -p "$out"
doc="$out/without-truth.md"
{
  echo "# Training without ground truth"
  echo
  echo "Produced by \`scripts/without_truth.sh\` (seed 1). Each benchmark of docs/results.md is copied"
  echo "without its train and val truth, and \`stgf train\` (8 epochs, as \`stgf reproduce\` trains) learns"
  echo "from the measurements alone (\`--supervision auto\` finds no truth.csv): Φ predicts the next"
  echo "fused measurement, Q is calibrated from the innovations, the registration prior from what the"
  echo "views disagree on (design §1.14). \`ours (no truth)\` runs with that model, \`ours (truth)\`"
  echo "with the model docs/results.md used; both on the same test split, scored against its truth"
  echo "from step 2 on."
} > "$doc"

for b in mpl cad; do
  folder="$out/$b"
  mkdir -p "$folder/train" "$folder/val"
  for split in train val; do cp "$benchmarks/$b/$split/measurements.csv" "$folder/$split/"; done
  if [ ! -f "$out/$b.pt" ]; then
    build/stgf train --benchmark "$folder" --out "$out/$b.pt" --epochs 8 --seed 1 --threads 2 --portable \
      2> "$out/$b-train.log"
  fi
  test="$benchmarks/$b/test"
  m="$test/measurements.csv"
  for method in wls mmt; do build/stgf run --method "$method" --measurements "$m" --out "$out/$method.csv" 2>/dev/null; done
  build/stgf run --method ours --model "$out/$b.pt" --measurements "$m" --out "$out/ours-no-truth.csv" 2>/dev/null
  sed -i 's/,ours$/,ours (no truth)/' "$out/ours-no-truth.csv"
  build/stgf run --method ours --model "$models/$b.pt" --measurements "$m" --out "$out/ours-truth.csv" 2>/dev/null
  sed -i 's/,ours$/,ours (truth)/' "$out/ours-truth.csv"
  # The truth-trained model with the registration prior the measurements gave (from the training log:
  # σ, α as one number or along, across and vertical to the rays, and the range scale's σ if any).
  calibration=$(grep "registration error on the validation split" "$out/$b-train.log")
  sigma=$(sed 's/.*translation sigma (\([^)]*\)) m.*/\1/' <<< "$calibration")
  alpha=$(sed -e 's/.*vertical to the rays (\([^)]*\)).*/[\1]/' -e 's/.*noise ratio \([0-9.e+-]*\)$/\1/' <<< "$calibration")
  range_scale=$(sed -n 's/.*registration range scale sigma \(.*\)/\1/p' "$out/$b-train.log")
  {
    printf 'ours:\n  registration_translation_sigma_m: [%s]\n  registration_noise_ratio: %s\n' "$sigma" "$alpha"
    printf '  registration_range_scale_sigma: %s\n' "${range_scale:-0}"
  } > "$out/$b-prior.yaml"
  build/stgf run --method ours --model "$models/$b.pt" --config "$out/$b-prior.yaml" --measurements "$m" \
    --out "$out/ours-truth-prior.csv" 2>/dev/null
  sed -i 's/,ours$/,ours (truth; prior without truth)/' "$out/ours-truth-prior.csv"
  # ... and the model trained without truth with the prior the truth gave (from the model file).
  registration=$(grep -a -o '"registration":{[^}]*}' "$models/$b.pt" | head -1)
  alpha=$(sed 's/.*"noise_ratio":\(\[[^]]*\]\|[^,}]*\).*/\1/' <<< "$registration")
  sigma=$(sed 's/.*"translation_sigma_m":\[\([^]]*\)\].*/\1/' <<< "$registration")
  range_scale=$(sed -n 's/.*"range_scale_sigma":\([^,}]*\).*/\1/p' <<< "$registration")
  printf 'ours:\n  registration_translation_sigma_m: [%s]\n  registration_noise_ratio: %s\n  registration_range_scale_sigma: %s\n' \
    "$sigma" "$alpha" "${range_scale:-0}" > "$out/$b-truth-prior.yaml"
  build/stgf run --method ours --model "$out/$b.pt" --config "$out/$b-truth-prior.yaml" --measurements "$m" \
    --out "$out/ours-no-truth-prior.csv" 2>/dev/null
  sed -i 's/,ours$/,ours (no truth; prior from the truth)/' "$out/ours-no-truth-prior.csv"
  {
    echo
    echo "## $b test split"
    echo
    build/stgf eval --truth "$test/truth.csv" --measurements "$m" --from-step 2 \
      --estimates "$out/wls.csv" "$out/mmt.csv" "$out/ours-truth.csv" "$out/ours-no-truth.csv" "$out/ours-truth-prior.csv" \
      "$out/ours-no-truth-prior.csv" \
      | sed -n '1,/^$/p'
    echo "What training found (\`stgf train\`'s log):"
    echo
    echo '```'
    grep -E "registration error|best epoch|Q in the filter on the validation split: " "$out/$b-train.log" | sed -n '1,2p;$p' | sed 's/^stgf: //'
    echo '```'
    echo
    echo "The model trained with the truth (\`$models/$b.pt\`) has the prior:"
    echo
    echo '```'
    grep -a -o '"registration":{[^}]*}' "$models/$b.pt" | head -1
    echo '```'
  } >> "$doc"
done
cat >> "$doc" <<'NOTES'

## Reading the numbers

- **Within 10 % of the truth-trained model on both** (issue 11's target): on mpl `ours (no truth)`
  is 2.5 % less accurate (0.0371 against 0.0362 m) with NEES 3.05; on cad 3.8 % less accurate
  (0.3361 against 0.3239 m) with NEES 2.72 (both trained with `--rotate`, stgf train's default since
  2026-12-02: 2.6 % and 3.4 % before; until the vehicles learned their offsets' along- and
  across-ray sizes apart, design §1.7, the truth-trained model was at 0.3396 and the other 0.8 %
  ahead of it).
- **The registration prior from the disagreements** on mpl (α per axis and a range scale, the
  default for one benchmark of cameras, design §1.7) matches the truth's translation σ (0.0223, 0.0223,
  0) m against (0.0222, 0.0222, 0) (σ_x = σ_y: a model trained with `--rotate` knows no heading), and
  α across the rays, 0.72 both, but not along them: 6.61 and a
  range scale of 0.087 against 0.32 and 0.0087. Differences of views cannot tell an offset along the
  ray in units of the noise from one in proportion to range (both grow with distance along the same
  ray), and the disagreements' maximum sits far along that ridge; run with it, the truth-trained
  model is 0.0374 m (NEES 3.22), and the model trained without truth with the truth's prior 0.0358:
  here too the prior, not Φ, makes the difference. (With one α, as until 2026-11-28, the two fits
  agreed: σ (0.039, 0.025, 0) against (0.034, 0.021, 0) m, α 0.49 both.) On cad the translation σ agree (0.34 against 0.32 m) but α is 0.01 against 1.10. cad's
  offsets are GPS pose errors: a position error, and a heading error that moves a measurement by
  its range times the angle, across the line of sight. stgf's offset model (a translation, and an
  offset in units of the view's own noise, design §1.7) describes the heading part only roughly,
  and the two fits settle that approximation differently. That is where cad's difference comes
  from: the truth-trained model with the prior from the disagreements gives 0.3354 m with NEES 3.08,
  and the model trained without truth, run with the truth's prior, 0.3247 m: Φ learnt from
  measurements predicts as well as Φ learnt from the truth, and the prior's α is what differs (with
  the run's evidence the along- and across-ray offsets are scaled apart, which α = 1.10 leaves room
  for and α = 0.01 does not).
- **Q**: calibrated inside the filter against the fused measurements, with their covariance taken
  out, the predictions' NEES on the validation split ends at 2.53 (mpl) and 2.30 (cad), and the test
  NEES of `ours (no truth)` is 3.05 and 2.72.
- The benchmarks' measurements are simulated with exactly the noise their R states, so the fused
  measurement is an honest target here; with sensors whose R understates their noise, Q and the
  prior come out too small (design §1.14).
NOTES
cp "$doc" docs/without-truth.md
echo "wrote docs/without-truth.md"
