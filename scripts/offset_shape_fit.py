#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""How well shapes of a view's registration offset fit a benchmark's true offsets (design §1.7).

For each (scene, view) of a split with truth, the horizontal residuals z - p of its measurements are
fitted by generalised least squares (weights R⁻¹, the xy block of each row's covariance) with a
constant per (scene, view) of the chosen shape, and the weighted residual's χ² per degree of freedom
is printed: about 1 when the shape holds the offsets, above 1 by what it misses. Shapes, combined by
letters: t a translation (2), d δ along and across the ray in units of the noise (2: F = G L(GᵀRG),
view_registration.hpp), e a range scale ε (1: z - s), w a camera rotation seen on the ground plane
(3: (I - d e_zᵀ / d_z)(ω × d), d = z - s). "-" is no offset at all.

    scripts/offset_shape_fit.py build/generalization/mpl-calibration-x5/val -,td,tde,tw,twe
"""
import collections
import sys

import numpy as np


def read(split):
    m = np.genfromtxt(f"{split}/measurements.csv", delimiter=",", names=True, dtype=None, encoding=None)
    t = np.genfromtxt(f"{split}/truth.csv", delimiter=",", names=True, dtype=None, encoding=None)
    truth = {(s, round(time, 4), o): (x, y) for s, time, o, x, y in zip(t["scene"], t["t"], t["object"], t["x"], t["y"])}
    p = np.array([truth[(s, round(time, 4), o)] for s, time, o in zip(m["scene"], m["t"], m["object"])])
    return m, np.stack([m["x"], m["y"]], 1) - p


def columns(rows, shape):
    n = len(rows)
    dx, dy, dz = rows["x"] - rows["sensor_x"], rows["y"] - rows["sensor_y"], -rows["sensor_z"]
    one, zero = np.ones(n), np.zeros(n)
    cols = []
    if "t" in shape:
        cols += [np.stack([one, zero], 1), np.stack([zero, one], 1)]
    if "e" in shape:
        cols += [np.stack([dx, dy], 1)]
    if "d" in shape:
        h = np.hypot(dx, dy)
        c, s = dx / h, dy / h
        xx, xy, yy = rows["cov_xx"], rows["cov_xy"], rows["cov_yy"]
        along = c * c * xx + 2 * c * s * xy + s * s * yy  # GᵀRG in the ray's frame
        cross = -s * c * xx + (c * c - s * s) * xy + c * s * yy
        across = s * s * xx - 2 * c * s * xy + c * c * yy
        l11 = np.sqrt(along)
        l21 = cross / l11
        l22 = np.sqrt(np.maximum(across - l21 ** 2, 1e-12))
        cols += [np.stack([c * l11 - s * l21, s * l11 + c * l21], 1), np.stack([-s * l22, c * l22], 1)]
    if "w" in shape:
        # -[d]x by rows, then the ground plane's projection of the turned ray.
        r0 = np.stack([zero, np.full(n, dz), -dy], 1)
        r1 = np.stack([np.full(n, -dz), zero, dx], 1)
        r2 = np.stack([dy, -dx, zero], 1)
        p0, p1 = r0 - (dx / dz)[:, None] * r2, r1 - (dy / dz)[:, None] * r2
        cols += [np.stack([p0[:, k], p1[:, k]], 1) for k in range(3)]
    return np.stack(cols, 2)


def chi2_per_dof(m, residual, shape):
    groups = collections.defaultdict(list)
    for k, key in enumerate(zip(m["scene"], m["view"])):
        groups[key].append(k)
    chi2 = dof = 0.0
    for rows_of in groups.values():
        idx = np.array(rows_of)
        rows, r = m[idx], residual[idx]
        cov = np.stack([np.stack([rows["cov_xx"], rows["cov_xy"]], 1), np.stack([rows["cov_xy"], rows["cov_yy"]], 1)], 1)
        w = np.linalg.inv(cov)
        if shape != "-":
            h = columns(rows, shape)
            a = np.einsum("nip,nij,njq->pq", h, w, h)
            b = np.einsum("nip,nij,nj->p", h, w, r)
            r = r - np.einsum("nip,p->ni", h, np.linalg.lstsq(a, b, rcond=None)[0])
            dof -= h.shape[2]
        chi2 += np.einsum("ni,nij,nj->", r, w, r)
        dof += 2 * len(idx)
    return chi2 / dof


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    m, residual = read(sys.argv[1])
    for shape in sys.argv[2].split(","):
        print(f"{shape}\t{chi2_per_dof(m, residual, shape):.3f}")


if __name__ == "__main__":
    main()
