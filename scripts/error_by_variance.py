#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Does an estimate's stated variance follow its error across its whole range? (docs/design.md §1.2)

NEES says whether a covariance is right on average; a filter can meet it with variances too large
where they are large and too small where they are small. This sorts one axis's rows by their stated
variance P_aa into equal bins and prints each bin's mean P_aa against the mean squared error r_a² of
the same rows (r = truth − estimate): a covariance that means what it says has r²/P = 1 in every bin.

The estimates are any `stgf run` output (one row per scene, time and object is scored; a method that
writes one row per measurement, as `ours-l` does, repeats it, and the first is kept); rows whose
(scene, t, object) the truth does not have are left out. For `ours-l`, P is the prediction's
P̂_s + Q and r its error before the update, so the table shows how the prediction's error grows with
the state's.

    stgf run --method ours-l --model build/reproduce/models/mpl.pt \\
        --measurements build/reproduce/benchmarks/mpl/val/measurements.csv --out /tmp/ours-l.csv
    python3 scripts/error_by_variance.py build/reproduce/benchmarks/mpl/val/truth.csv /tmp/ours-l.csv --axis z
"""
import argparse
import csv
import sys

AXES = {"x": 0, "y": 1, "z": 2}
VARIANCE_COLUMNS = ("cov_xx", "cov_yy", "cov_zz")


def read_truth(path):
    truth = {}
    with open(path, newline="") as f:
        for line, row in enumerate(csv.DictReader(f), start=2):
            try:
                truth[(row["scene"], round(float(row["t"]), 6), row["object"])] = [float(row[k]) for k in "xyz"]
            except (KeyError, TypeError, ValueError) as error:
                sys.exit(f"{path}:{line}: not a truth row (scene,t,object,x,y,z): {error}")
    return truth


def read_errors(path, truth, axis):
    errors, variances, seen = [], [], set()
    with open(path, newline="") as f:
        for line, row in enumerate(csv.DictReader(f), start=2):
            try:
                key = (row["scene"], round(float(row["t"]), 6), row["object"])
                if key in seen or key not in truth:
                    continue
                seen.add(key)
                errors.append(truth[key][axis] - float(row["xyz"[axis]]))
                variances.append(float(row[VARIANCE_COLUMNS[axis]]))
            except (KeyError, TypeError, ValueError) as error:
                sys.exit(f"{path}:{line}: not an estimate row (scene,t,object,x,y,z,cov_..): {error}")
    if not errors:
        sys.exit(f"{path}: no row matches the truth")
    return errors, variances


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("truth")
    parser.add_argument("estimates")
    parser.add_argument("--axis", choices=sorted(AXES), default="z")
    parser.add_argument("--bins", type=int, default=8, help="equal-count bins of the stated variance (default 8)")
    args = parser.parse_args()
    if args.bins < 1:
        parser.error("--bins must be at least 1")
    errors, variances = read_errors(args.estimates, read_truth(args.truth), AXES[args.axis])
    order = sorted(range(len(variances)), key=lambda row: variances[row])
    print(f"| bin | rows | mean P_{args.axis}{args.axis} (m²) | mean r_{args.axis}² (m²) | r²/P |")
    print("|---:|---:|---:|---:|---:|")
    for k in range(args.bins):  # bin k: rows [n k / bins, n (k + 1) / bins) of the sorted order
        rows = order[len(order) * k // args.bins:len(order) * (k + 1) // args.bins]
        if not rows:
            continue
        p = sum(variances[row] for row in rows) / len(rows)
        r2 = sum(errors[row] ** 2 for row in rows) / len(rows)
        print(f"| {k + 1} | {len(rows)} | {p:.2e} | {r2:.2e} | {r2 / p:.2f} |")


if __name__ == "__main__":
    main()
