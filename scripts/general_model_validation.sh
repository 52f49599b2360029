#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Records models/general-validation.csv: what the general model shipped with stgf (models/general.pt)
# gives with `ours` on the validation split of each benchmark it was calibrated on (seed 1, default
# sizes, scored from step 2 on), `wls` beside it. The test
# Cli.ShippedGeneralModelKeepsItsValidationNumbers rebuilds the benchmarks it can (mpl and ethucy from
# data/, cad when the KITTI copy is there) and checks these numbers: run this again when the filter
# changes on purpose. About a minute on 2 cores; cad needs the KITTI copy (data/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
out=build/general-model/validation
mkdir -p "$out"
record=$out/general-validation.csv
{
  echo "# Written by scripts/general_model_validation.sh: ours with models/general.pt (and wls) on each"
  echo "# benchmark's validation split, stgf dataset B --seed 1, scored from step 2 (stgf eval --from-step 2)."
  echo "benchmark,method,rows,de,nees_mean"
} > "$record"
for b in mpl ethucy cad; do
  rm -rf "${out:?}/$b"
  build/stgf dataset "$b" --out "$out/$b" --seed 1 -q
  m=$out/$b/val/measurements.csv
  build/stgf run --method wls --measurements "$m" --out "$out/$b-wls.csv" -q
  build/stgf run --method ours --model models/general.pt --measurements "$m" --out "$out/$b-ours.csv" -q
  build/stgf eval --truth "$out/$b/val/truth.csv" --measurements "$m" --estimates "$out/$b-wls.csv" "$out/$b-ours.csv" \
    --from-step 2 --json "$out/$b.json" > /dev/null
  python3 - "$out/$b.json" "$b" >> "$record" <<'PY'
import json, sys
scores = json.load(open(sys.argv[1]))
for method in scores["methods"]:
    print(f'{sys.argv[2]},{method["method"]},{method["overall"]["rows"]},{method["overall"]["de"]:.9g},'
          f'{method["overall"]["nees_mean"]:.9g}')
PY
done
cp "$record" models/general-validation.csv
# The table in models/README.md, between its validation markers.
python3 - models/general-validation.csv models/README.md <<'PY'
import csv, sys
rows = [r for r in csv.reader(l for l in open(sys.argv[1]) if not l.startswith("#"))][1:]
table = ["| benchmark (val split) | rows | wls DE (m) | wls NEES | ours DE (m) | ours NEES |", "|---|---:|---:|---:|---:|---:|"]
by = {}
for b, method, n, de, nees in rows:
    by.setdefault(b, {"rows": n})[method] = (float(de), float(nees))
for b, v in by.items():
    table.append(f"| {b} | {v['rows']} | {v['wls'][0]:.4f} | {v['wls'][1]:.2f} | {v['ours'][0]:.4f} | {v['ours'][1]:.2f} |")
text = open(sys.argv[2]).read()
start = text.index("<!-- validation")
start = text.index("-->", start) + 3
end = text.index("<!-- /validation -->")
open(sys.argv[2], "w").write(text[:start] + "\n" + "\n".join(table) + "\n" + text[end:])
PY
cat models/general-validation.csv
