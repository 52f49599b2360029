#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Regenerates docs/general-model.md: one model trained on several of the project's real-data
# benchmarks (`stgf train --benchmark A,B`), scored on the test split of the one it did not see
# (leave one dataset out), against the model-free baselines and the held-out benchmark's own model.
# The benchmarks: mpl (PETS 2009 pedestrians, 7 Hz, cameras) and cad (KITTI vehicles, 10 Hz) of
# scripts/results.sh, and ethucy (ETH/UCY pedestrians, 2.5 Hz; scene eth held out as its test split).
# Same epochs (8), seed (1), threads (2) and --portable as results.sh. About 20 minutes on 2 cores.
# Run scripts/results.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/results_models.sh
out=build/general-model
mkdir -p "$out"
[ -f "$out/ethucy/benchmark.json" ] || build/stgf dataset ethucy --out "$out/ethucy" --seed 1 2>/dev/null
folder_of() { case $1 in ethucy) echo "$out/ethucy" ;; *) echo "$benchmarks/$1" ;; esac; }

train() {  # name, benchmarks (comma-separated names)[, more stgf train options]
  local name=$1 list=$2 folders=""
  for b in ${list//,/ }; do folders="$folders${folders:+,}$(folder_of "$b")"; done
  [ -f "$out/$name.pt" ] || build/stgf train --benchmark "$folders" --out "$out/$name.pt" --epochs 8 --seed 1 \
    --threads 2 --portable "${@:3}" 2> "$out/$name-train.log"
}
# Each training graph is turned by a random heading every epoch (--rotate, stgf train's default; design
# §1.1, "The world frame's heading"); said aloud for the models of several benchmarks, as their recipe
# (models/README.md) says it.
train ethucy ethucy
train without-mpl cad,ethucy --rotate
train without-cad mpl,ethucy --rotate
train without-ethucy mpl,cad --rotate
# The model on all three is the general model shipped with stgf, by models/README.md's recipe: it must
# come out byte for byte as models/general.pt (same seed, threads and kernels).
train all mpl,cad,ethucy --no-resume-state --weights float16 --rotate
if ! cmp -s "$out/all.pt" models/general.pt; then
  echo "$out/all.pt differs from models/general.pt: the shipped model is not what its recipe gives" >&2
  exit 1
fi

doc="$out/general-model.md"
{
  echo "# One model for several kinds of data"
  echo
  echo "Produced by \`scripts/general_model.sh\` (seed 1). Each model is trained with"
  echo "\`stgf train --benchmark A,B\` (8 epochs, as \`stgf reproduce\` trains; with \`--rotate\`, the default, each"
  echo "training graph turned by a random heading every epoch) on the train and val splits"
  echo "of the benchmarks it names, and scored on the test split of the one it did not see. \`ours"
  echo "(own)\` is the held-out benchmark's own model (docs/results.md; for ethucy trained here the same"
  echo "way), \`ours (all)\` the model trained on all three: the general model shipped with stgf"
  echo "(models/general.pt, the same recipe and weights; models/README.md). Scored from step 2 on."
} > "$doc"

score() {  # benchmark, leave-one-out model name, own model path
  local b=$1 held_out=$2 own=$3
  local test m
  test="$(folder_of "$b")/test"
  m="$test/measurements.csv"
  for method in wls mmt; do build/stgf run --method "$method" --measurements "$m" --out "$out/$method.csv" 2>/dev/null; done
  build/stgf run --method ours --model "$own" --measurements "$m" --out "$out/ours-own.csv" 2>/dev/null
  sed -i 's/,ours$/,ours (own)/' "$out/ours-own.csv"
  build/stgf run --method ours --model "$out/$held_out.pt" --measurements "$m" --out "$out/ours-held-out.csv" \
    2> "$out/$b-run.log"
  sed -i "s/,ours\$/,ours ($held_out)/" "$out/ours-held-out.csv"
  build/stgf run --method ours --model "$out/all.pt" --measurements "$m" --out "$out/ours-all.csv" 2>/dev/null
  sed -i 's/,ours$/,ours (all)/' "$out/ours-all.csv"
  {
    echo
    echo "## $b test split"
    echo
    build/stgf eval --truth "$test/truth.csv" --measurements "$m" --from-step 2 \
      --estimates "$out/wls.csv" "$out/mmt.csv" "$out/ours-own.csv" "$out/ours-held-out.csv" "$out/ours-all.csv" \
      | sed -n '1,/^$/p'
    echo "\`ours ($held_out)\` on it (\`stgf run\`'s log):"
    echo
    echo '```'
    grep -E "constant velocity predicted better|restarted|Q scaled across scenes|registration prior scaled|kept the registration prior|do not fit the registration prior" "$out/$b-run.log" \
      | sed 's/^stgf: //' || true
    echo '```'
  } >> "$doc"
}
score mpl without-mpl "$models/mpl.pt"
score cad without-cad "$models/cad.pt"
score ethucy without-ethucy "$out/ethucy.pt"

{
  echo
  echo "## What each model was calibrated to"
  echo
  echo "| model | registration prior σ (m) | α | Q in the filter at Δt_ref |"
  echo "|---|---|---:|---|"
  for name in ethucy without-mpl without-cad without-ethucy all; do
    prior=$(sed -n 's/.*translation sigma (\(.*\)) m, noise ratio \(.*\)/(\1) | \2/p' "$out/$name-train.log")
    q=$(grep "Q in the filter on the validation split: " "$out/$name-train.log" | tail -1 | sed 's/.*-> Q at \(.*\)/\1/')
    echo "| $name | $prior | $q |"
  done
} >> "$doc"
cat >> "$doc" <<'NOTES'

## Reading the numbers

The model trained on all three ships with stgf (models/general.pt: what `ours` runs without
`--model`), with its validation numbers in models/README.md. Left out of training, every benchmark
is scored better by the model of the other two than by `wls` and `mmt`, with NEES in [2.5, 3.5]: mpl
0.0383 m against 0.0555 (NEES 2.81), cad 0.3350 against 0.4632 (3.11), ethucy 0.0937 against 0.1032
(2.81). Trained on all three, the model is 1.7 % behind mpl's own model (0.0368 against 0.0362), 1.1 %
ahead of cad's (0.3202 against 0.3239) and level with ethucy's (0.0847 against 0.0847); NEES 2.99, 3.33
and 2.69. The own models are trained with `--rotate` (stgf
train's default since 2026-12-02, design §1.1) and learn Q's scales across the run's scenes, never
below their calibration; before, the general model was within 0.3 % of mpl's own (0.0382), as
accurate as cad's (0.3246) and 1 % ahead of ethucy's (0.0863). How they got there, each step
measured on these test splits when it came in (2026-11-28, and the last four 2026-12-02):
- Q's scales learned across the run's scenes (the default for a model of several benchmarks, design
  §1.2; the `Q scaled across scenes` lines above): without-mpl on mpl 0.0519 → 0.0494 (NEES 1.95 →
  2.22), without-cad on cad 0.4146 → 0.3965 (25.5 → 22.0), without-ethucy on ethucy 0.0946 → 0.0939,
  and the model of all three on mpl 0.0453 → 0.0431 (NEES 1.83 → 2.26), cad 0.3537 → 0.3546 (9.0 →
  8.6), ethucy 0.0944 → 0.0938.
- The registration prior's scales lowered by the run's scenes where together they show smaller
  offsets than its calibration (design §1.7): without-mpl on mpl 0.0494 → 0.0442 (NEES 2.22 → 2.83),
  without-cad on cad 0.3965 → 0.3918 (22.0 → 22.9), without-ethucy on ethucy 0.0939 → 0.0935 (2.61 →
  2.95), and all three on mpl 0.0431 → 0.0409 (2.26 → 2.70), cad 0.3546 → 0.3525 (8.6 → 8.8), ethucy
  0.0938 → 0.0935 (2.64 → 2.94).
- Trained with `--rotate` (each training graph turned by a random heading every epoch: a model for
  data in any world frame, design §1.1): all three on mpl 0.0409 → 0.0409, on mpl turned by 90°
  0.0403 → 0.0407 (within 0.5 % of the split as given, where it was 1.5 %: docs/generalization.md),
  ethucy 0.0935 → 0.0848, cad 0.3525 → 0.3582 (8.8 → 9.0: 83 % of cad's training motion runs along
  +x, which a model without `--rotate` could use); without-cad on cad 0.3918 → 0.3849 (22.9 → 20.9).
- Scenes whose sensors move (cad's vehicles) held at the registration scales that the run's earlier
  scenes show, in a pool of their own (design §1.7): without-cad on cad 0.3849 → 0.3567 (NEES 20.9 →
  3.42), all three 0.3582 → 0.3519 (9.0 → 3.27); the cameras' scenes, whose pool may only lower
  their scales, are as before. Then, instead of being held at the earlier scenes' best scales after
  16 of them, each scene starting from their summed evidence and learning on from its own: without
  cad 0.3567 → 0.3553 (3.42 → 3.32), all three 0.3519 → 0.3513 (3.27). On cad the run's scenes take
  κ_t to about 128 for without-cad (σ 0.35 m, cad's GPS error being 0.3 m; the log above).
- The vertical offsets on a scale of their own, κ_v, and, where a scene starts from the run's
  evidence (the vehicles), δ's components along and across the rays too (design §1.7; `stgf eval`
  now gives NEES on x, y and on z): without-mpl on mpl 0.0437 → 0.0436 (NEES 2.76 → 2.85), all three
  0.0409 → 0.0404 (2.70 → 3.03; the heights had been too uncertain, z 0.6); without-cad on cad
  0.3553 → 0.3408 (3.32 → 3.29), all three 0.3513 → 0.3379 (3.27 → 3.55), cad's own model 0.3396 →
  0.3268; ethucy as before (0.0934 and 0.0848).
- The error of the velocity each forecast reads off the track's history, in its covariance (design
  §1.2): a track's first forecasts, from two or three positions, had been trusted too much. Without
  mpl on mpl 0.0436 → 0.0419 (NEES 2.85 → 2.71), without cad on cad 0.3409 → 0.3325 (3.31 → 3.11),
  without ethucy on ethucy 0.0934 → 0.0934 (2.93 → 2.92); all three on mpl 0.0404 → 0.0382 (3.03 →
  2.68), cad 0.3378 → 0.3243 (3.55 → 3.34), ethucy 0.0848 → 0.0854 (2.61 → 2.48: the heights, z 0.68 →
  0.54); the own models 0.0386 → 0.0382, 0.3268 → 0.3247, 0.0864 → 0.0863.
- The history positions' errors counted with their correlation in that velocity's error (design
  §1.2; independent before): without mpl on mpl 0.0419 → 0.0419 (NEES 2.71 → 2.72), without cad on
  cad 0.3325 → 0.3360 (3.11 → 3.17), without ethucy on ethucy 0.0934 → 0.0933 (2.92 → 2.92); all three
  on mpl 0.0382 → 0.0383 (2.68 → 2.72), cad 0.3243 → 0.3247 (3.34 → 3.35), ethucy 0.0854 → 0.0854
  (2.48 → 2.48); the own models 0.0382 → 0.0382, 0.3247 → 0.3246, 0.0863 → 0.0863.
- The slope's error counted as the forecast carries it (design §1.2) and the offset common to a
  scene's views sized from the run's scenes where the scene's own size is lower (design §1.7; NEES
  only), measured together: without mpl on mpl 0.0419 → 0.0413 (NEES 2.72 → 2.49: x, y 1.67 → 1.47,
  z 1.05 → 1.01), without cad on cad 0.3360 → 0.3350 (3.17 → 3.11), without ethucy on ethucy 0.0933 →
  0.0937 (2.92 → 2.81); all three on mpl 0.0383 → 0.0374 (2.72 → 2.80), cad 0.3247 → 0.3202 (3.35 →
  3.33), ethucy 0.0854 → 0.0847 (2.48 → 2.69, the heights z 0.55 → 0.82); the own models (mpl's and
  cad's those of docs/results.md) 0.0367 → 0.0362, 0.3229 → 0.3239, 0.0853 → 0.0847.
- On fixed sensors the run's scales taken for the offsets in units of the noise either way (κ_n; the
  translations' κ_t still lowered only), over the whole range of their ratio (2^±12, where 2^±8 had
  held the model without mpl's translations four times too wide on mpl's cameras), and Q's λ down to
  2⁻¹⁰ (design §1.7, *The offsets in units of the noise from the run, either way*): without mpl on mpl
  0.0413 → 0.0383 (NEES 2.49 → 2.81: x, y 1.47 → 1.77; κ_t's median 0.06 → 0.02, κ_n's 13.7 → 44.6 in
  the log above), all three on mpl 0.0374 → 0.0368 (2.80 → 2.99); cad and ethucy as before (their
  pools' ratios were within 2^±8, and on vehicles κ was already learned from the run's evidence), and
  the own models unchanged.

A model trained on several benchmarks spaces its history positions
by the fastest one's frame period (design §1.4: cad's 0.1 s here, and for without-ethucy and
without-mpl; mpl's 1/7 s for without-cad). Until 2026-11-28 they were spaced by the median training
interval, ETH/UCY's 0.4 s wherever it was in the mix, so every track on mpl and cad coasted by
constant velocity and Φ was never used there; since Φ is, the models that saw ETH/UCY gained on mpl
and cad (all: mpl 0.0453 → 0.0431, cad 0.3553 → 0.3537; without-cad on cad 0.4273 → 0.4146), but
the model of cad and ethucy alone does worse on mpl than the constant velocity it used to coast by
(0.0492 → 0.0519): a Φ of vehicles and 2.5-Hz pedestrians does not transfer to 7-Hz pedestrians,
and mpl's 3-s scenes are too short for the switch to constant velocity (design §1.13) to find it. One
curve of Q serves data of three rates (its reference interval is mpl's 0.143 s); on the mixed validation
split Φ predicts better than constant velocity every 2nd frame (0.0729 against 0.0822 m at 0.29 s, in
`all-train.log`) and constant velocity better from the 3rd on (0.1172 against 0.1202 m at 0.43 s), so
the model hands ethucy's histories (0.4 s apart) to constant velocity. What the table of calibrations
shows is why one model does not fit all:

- **Q is one matrix for every kind of motion.** Per 0.1 s, the pedestrians' own Q is about
  4·10⁻⁴ m² per axis (mpl and ethucy alike), the vehicles' 0.1 m²: 300 times more. A model
  calibrated on both takes a compromise that is far too large for pedestrians and far too small
  for vehicles. The online scale λ (design §1.2), learned across the run's scenes for these models,
  takes Q most of the way (λ ≈ 0.02 for the model of all three on mpl; on cad 5.7 along x, 23 before
  the forecasts counted the history's velocity error, below), but the first
  scenes of a run start from the compromise (with the registration's, they are part of why the
  first scenes of cad val, of 500, are less honest than the rest; design §1.7). The mixture also skews Δt_ref (0.4 s when ethucy dominates), and Q(Δt) ∝ Δt² then
  carries the compromise to rates it was not measured at. Much of what Q stands for on cad is not
  the objects' motion but the noise of the history Φ reads (range-dependent noise of tens of
  centimetres, against centimetres for the cameras): a Q that scales with the track's own
  uncertainty, not one matrix, is the next step; the forecasts' covariance now counts the error of
  the velocity read off the history's own positions (design §1.2), which took cad's λ on x, y from
  (22.6, 5.66) to (2, 0.016), counting the history positions' correlation to (5.66, 0.016), and the
  slope's error as the forecast carries it to (0.022, 0.016).
- **The registration prior is one shape for every sensor.** The cameras' offsets are a few
  centimetres but grow with their noise, the vehicles' GPS errors 0.3 m whatever their noise:
  calibrated on both, 0.19 m with α 0.1 (without mpl). With one scale κ on that prior, mpl got
  κ ≈ 0.9, the compromise between translations that wanted less and offsets in units of the noise
  that wanted more, and lost the cameras' R-weighting (0.0873 m). Learned as two scales, κ_t median
  0.06 and κ_n 10 there (the logs above: the run's scenes lowered κ_t, each scene raised κ_n). Each
  scene's prior holds its scales within a few times of where they start, so a scene alone cannot
  take a camera's prior to a vehicle's; the run's scenes together do where the sensors move (κ_t
  about 128 for without-cad on cad), and `stgf run` says that the prior does not fit and which way to set it
  (the last line of each log above: on cad, translation σ at least 0.35 m, where cad's own
  calibration is 0.32 m; on mpl, σ at most 0.05 m and α at least 0.32, against mpl's 0.02–0.03 m and
  0.49).
- **Φ reads velocities in units of the training data's typical speed**, one for all (design §1.1):
  with vehicles in the training data it is 3.0–3.9 m/s, and pedestrians (1.0–1.1 m/s alone) move
  at a third of it or less. Its horizon, twice the longest interval of any of the data (1.2 s, from
  ethucy at a third of 2.5 Hz), is then also granted to the vehicles.
NOTES
cp "$doc" docs/general-model.md
echo "wrote docs/general-model.md"
