# SPDX-License-Identifier: Apache-2.0
# Sourced by the scripts that build on what scripts/results.sh made: sets `models` and `benchmarks`
# and stops, with the advice, when the mpl and cad models are not there yet.
models=build/reproduce/models
benchmarks=build/reproduce/benchmarks
for b in mpl cad; do
  [ -f "$models/$b.pt" ] || { echo "run scripts/results.sh first ($models/$b.pt)" >&2; exit 2; }
done
