#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Regenerates docs/faulty-views.md: the full-size mpl and cad test splits (and their validation splits) of scripts/results.sh with
# one view made faulty by `stgf inject-fault` (seed 1) — (a) a 1 m calibration jump in the middle of
# each scene, (b) its covariance understated 100×, (c) 2 % gross outliers of 5–20 m — and wls, mmt
# and ours (the models of scripts/results.sh) on each, scored against the clean truth from step 2 on.
# Every method runs without (the default) and with its gate (config/methods.yaml: gate), and ours
# also without its cross-view weights (cross_view_weights: false). Run scripts/results.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
models=build/reproduce/models
benchmarks=build/reproduce/benchmarks
[ -f "$models/mpl.pt" ] && [ -f "$models/cad.pt" ] || { echo "run scripts/results.sh first ($models)" >&2; exit 2; }
out=${STGF_FAULTS_OUT:-build/faulty-views}
mkdir -p "$out"
printf 'wls:\n  gate: true\nmmt:\n  gate: true\nours:\n  gate: true\n' > "$out/gated.yaml"
printf 'ours:\n  cross_view_weights: false\n' > "$out/unweighted.yaml"

# The faulty view: mpl's view1 (the first in name order, so it starts the tracks of what it sees),
# cad's v3 (a vehicle whose objects the others also see; v0, the ego vehicle, sees 46 % of the rows
# and many objects alone, where no method can tell a fault from the truth).
# And, as a proxy for a view the gate cannot judge, cad's validation split with v1 made faulty: a
# vehicle that sees 36 % of that split's rows, many objects alone.
cases=("mpl test view1" "mpl val view1" "cad test v3" "cad val v1")
faults=(clean jump understated-noise outliers)

de_nees() {  # estimates CSV, truth, measurements → "DE|NEES"
  build/stgf eval --truth "$2" --measurements "$3" --from-step 2 --estimates "$1" --json "$out/eval.json" >/dev/null
  /usr/bin/python3 -c 'import json,sys; m=json.load(open(sys.argv[1]))["methods"][0]["overall"]; print("%.4f|%.2f" % (m["de"], m["nees_mean"]))' "$out/eval.json"
}

{
  echo "# A faulty view"
  echo
  echo "Produced by \`scripts/faulty_views.sh\` (seed 1) with the models and benchmark splits of \`scripts/results.sh\`."
  echo "One view of each split is made faulty by \`stgf inject-fault\`; every method is scored against the"
  echo "clean truth from step 2 on. DE in metres; NEES is 3 for an honest covariance. \`(gated)\`: the method"
  echo "with \`gate: true\` (off by default; design §1.12). \`ours (no cross-view weights)\`: \`ours\` with"
  echo "\`cross_view_weights: false\` (on by default: a measurement that three or more views of its object at"
  echo "its time place far off is fused with its noise scaled up; design §1.12)."
} > "$out/faulty-views.md"

for case in "${cases[@]}"; do
  read -r benchmark split view <<< "$case"
  folder=$benchmarks/$benchmark/$split
  {
    echo
    echo "## $benchmark $split split (faulty view: $view)"
    echo
    echo "| method | clean DE | clean NEES | jump 1 m DE | NEES | R understated 100× DE | NEES | 2 % outliers DE | NEES |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  } >> "$out/faulty-views.md"
  declare -A cells=()
  for fault in "${faults[@]}"; do
    m=$out/$benchmark-$split-$fault.csv
    if [ "$fault" = clean ]; then
      cp "$folder/measurements.csv" "$m"
    else
      build/stgf -q inject-fault --measurements "$folder/measurements.csv" --view "$view" --kind "$fault" --seed 1 --out "$m"
    fi
    for method in wls mmt ours wls-gated mmt-gated ours-gated ours-unweighted; do
      case $method in
        wls|mmt) build/stgf -q run --method "$method" --measurements "$m" --out "$out/estimates.csv" ;;
        ours-unweighted) build/stgf -q run --method ours --model "$models/$benchmark.pt" --config "$out/unweighted.yaml" --measurements "$m" --out "$out/estimates.csv" ;;
        ours) build/stgf -q run --method ours --model "$models/$benchmark.pt" --measurements "$m" --out "$out/estimates.csv" ;;
        ours-gated) build/stgf -q run --method ours --model "$models/$benchmark.pt" --config "$out/gated.yaml" --measurements "$m" --out "$out/estimates.csv" ;;
        *-gated) build/stgf -q run --method "${method%-gated}" --config "$out/gated.yaml" --measurements "$m" --out "$out/estimates.csv" ;;
      esac
      cells[$method,$fault]=$(de_nees "$out/estimates.csv" "$folder/truth.csv" "$m")
    done
  done
  for method in wls wls-gated mmt mmt-gated ours ours-gated ours-unweighted; do
    row="| ${method/-gated/ (gated)}"
    row=${row/-unweighted/ (no cross-view weights)}
    for fault in "${faults[@]}"; do row+="|${cells[$method,$fault]}"; done
    echo "$row|" >> "$out/faulty-views.md"
  done
  unset cells
done
{
  echo
  echo "## Reading it"
  echo
  echo "- The gate (design §1.12) keeps gross outliers out for every method that has it; \`ours\` also keeps"
  echo "  its covariance honest under them. On clean data it costs \`ours\` a little DE (a few good"
  echo "  measurements fail the gate, and a healthy view is now and then found disagreeing); on data unlike"
  echo "  the model's training data it can cost much more (design §1.12), which is why it is off by default."
  echo "- Ungated, the other views outvote a gross error where three or more see its object at its time"
  echo "  (cross-view weights, design §1.12): on mpl test with 2 % outliers \`ours\` has 0.0432 m against 0.2966"
  echo "  without them (\`wls\` 0.1128), after a 1 m jump 0.0572 against 0.1420, with R understated 0.0806"
  echo "  against 0.1660. Fused as it was, an outlier moved its view's offset, most for the far measurements"
  echo "  where the offset has a range scale (design §1.7). What the weights do not do: judge a measurement"
  echo "  seen by fewer than three views (cad's vehicles: test outliers 0.3717 against 0.4192, gated 0.3284),"
  echo "  or learn that a view is faulty — each of its measurements is outvoted on its own, where the gate"
  echo "  re-opens its offset or learns its noise (mpl test: jump 0.0382, R understated 0.0383, outliers 0.0364)."
  echo "  An outlier that passes also raises Q's scales, which a file's later scenes start from (design"
  echo "  §1.2): learned per scene (\`process_noise_scale: per-scene\`) the outliers cost less, mpl test 0.0395,"
  echo "  cad test 0.3637."
  echo "- A jump is found by the view's disagreement with the other views; \`ours\` then re-opens the view's"
  echo "  offset, which the other views teach. \`wls\` and \`mmt\` have no offsets: their gate only leaves"
  echo "  out what is far off. On cad a 1 m jump is within the size of the vehicles' normal pose error"
  echo "  (0.3 m per axis) and a scene is 1 s long: it is found after three disagreements, if at all."
  echo "- Understated noise is found only by the view's disagreements with the other views. Once its"
  echo "  scale is learnt (and when a jump is found), \`ours\` goes back over its lag window and fuses what"
  echo "  came since again with it (design §1.12, level 4), so what the view taught the tracks and the"
  echo "  offsets before it was found does not stay. Rows estimated before keep their estimates."
  echo "- Where a faulty view sees an object alone, only the object's own track can tell its fault from"
  echo "  the truth. cad's validation split with v1 made faulty shows it: v1 sees many objects alone."
  echo "  Gross outliers are far from the track's prediction, and the gated \`ours\` stays near its clean"
  echo "  run. A jump or understated noise is not told from the truth, and no method keeps DE near the"
  echo "  clean run. There the gate even costs \`ours\` under understated noise: v1's measurements fail"
  echo "  the gate against a prediction its own understated R made overconfident, and objects only it"
  echo "  sees are left to the prediction until their tracks start again."
} >> "$out/faulty-views.md"
cp "$out/faulty-views.md" docs/faulty-views.md
cat docs/faulty-views.md
