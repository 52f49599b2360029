#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Fusing a small stream of measurements from Python, and drawing it.

Two fixed cameras watch one pedestrian walking a slow curve. Each camera measures the pedestrian's
position on the ground with its own noise: "east" is precise along x and poor along y (it looks
along y, so depth is its weak direction), "north" the other way round. The cameras run on their
own clocks (north 40 ms after east), and one of north's messages arrives late, after east's next
one. stgf's streaming filter takes every message as it arrives and returns, for each, the fused
estimate of the pedestrian with its covariance.

    PYTHONPATH=build/python python3 examples/python/fuse_stream.py --out build/examples/python

writes fuse_stream.svg: the true path (black), each camera's measurements (dots), the fused track
(blue) and its 95 % ellipses, which should hold the true path about 95 % of the time.
"""

import argparse
import math
import os

import numpy as np

import stgf

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default=".", help="folder for fuse_stream.svg")
arguments = parser.parse_args()

# ── 1. Simulate the stream ──────────────────────────────────────────────────────────────────────
# The truth: 1.2 m/s along a 15 m circle, 5 frames per second per camera, 4 seconds.
rng = np.random.default_rng(7)
SPEED, RADIUS, RATE = 1.2, 15.0, 5.0


def truth_at(t):
    angle = SPEED * t / RADIUS
    return np.array([RADIUS * math.sin(angle), RADIUS * (1.0 - math.cos(angle)), 0.0])


# Each camera's measurement covariance R (m²): 5 cm along its good axis, 40 cm along its poor one,
# and 1 cm in height (the ground plane).
R_EAST = np.diag([0.05**2, 0.40**2, 0.01**2])
R_NORTH = np.diag([0.40**2, 0.05**2, 0.01**2])
CAMERAS = {"east": (0.0, R_EAST), "north": (0.04, R_NORTH)}  # clock offset (s), R

messages = []  # (arrival time, measurement time, view, z, R)
for k in range(int(4 * RATE)):
    for view, (offset, R) in CAMERAS.items():
        t = k / RATE + offset
        z = rng.multivariate_normal(truth_at(t), R)
        delay = 0.01
        if view == "north" and k == 10:
            delay = 0.25  # a message stuck in a queue: it arrives after east's next frame
        messages.append((t + delay, t, view, z, R))
messages.sort(key=lambda m: m[0])  # the order the fuser receives them in

# ── 2. Fuse them as they arrive ─────────────────────────────────────────────────────────────────
# No model file: the filter predicts with constant velocity (Q = 0.5 m²/s² per s², a pedestrian's
# typical speed of 1.4 m/s for a new track). With a model from `stgf train`: stgf.Filter("model.pt").
fuser = stgf.Filter()
fused = {}  # measurement time → (mean, covariance), the latest word on that time
for arrival, t, view, z, R in messages:
    out = fuser.fuse(time=[t], view=[view], object="walker", z=z[None], R=R[None])
    fused[t] = (out["mean"][0], out["covariance"][0])

times = np.array(sorted(fused))
means = np.array([fused[t][0] for t in times])
covariances = np.array([fused[t][1] for t in times])
truth = np.array([truth_at(t) for t in times])
print(f"{len(messages)} messages fused; late ones fused in place: {fuser.rewinds}; left out: {fuser.late_measurements}")

# ── 3. Check the covariance is honest ───────────────────────────────────────────────────────────
# NEES = (x̂ − x)ᵀ P⁻¹ (x̂ − x) averages 3 for a covariance that tells the truth (3 dimensions).
scores = stgf.metrics(means, covariances, truth)
print(f"fused: DE {scores['de']:.3f} m, NEES {scores['nees_mean']:.2f} (3 is honest), "
      f"{100 * scores['nees_in_95']:.0f} % inside the 95 % region")
for view, (_, R) in CAMERAS.items():
    own = [(m[3], m[1]) for m in messages if m[2] == view]
    error = np.mean([np.linalg.norm(z - truth_at(t)) for z, t in own])
    print(f"camera {view} alone: DE {error:.3f} m")


# ── 4. Draw it (plain SVG: no plotting library needed) ──────────────────────────────────────────
def ellipse_points(mean, covariance, chi2=5.991, n=36):
    """The 95 % region of the x–y marginal: mean + √χ² · L · (cos θ, sin θ), L Lᵀ = P_xy."""
    L = np.linalg.cholesky(covariance[:2, :2])
    angles = np.linspace(0.0, 2.0 * math.pi, n + 1)
    return mean[:2][None] + math.sqrt(chi2) * (L @ np.stack([np.cos(angles), np.sin(angles)])).T


def write_svg(path):
    points = np.concatenate([truth[:, :2], means[:, :2]] + [m[3][None, :2] for m in messages])
    low, high = points.min(axis=0) - 0.5, points.max(axis=0) + 0.5
    scale = 700.0 / max(high - low)
    width, height = (high - low) * scale

    def xy(p):
        return f"{(p[0] - low[0]) * scale:.1f},{height - (p[1] - low[1]) * scale:.1f}"

    def polyline(ps, style):
        return f'<polyline points="{" ".join(xy(p) for p in ps)}" style="fill:none;{style}"/>'

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height + 30:.0f}">',
             '<rect width="100%" height="100%" fill="white"/>',
             polyline(truth[:, :2], "stroke:black;stroke-width:2")]
    colours = {"east": "#d95f02", "north": "#1b9e77"}
    for _, t, view, z, _ in messages:
        parts.append(f'<circle cx="{xy(z).split(",")[0]}" cy="{xy(z).split(",")[1]}" r="3" fill="{colours[view]}"/>')
    for mean, covariance in zip(means[::2], covariances[::2]):
        parts.append(polyline(ellipse_points(mean, covariance), "stroke:#377eb8;stroke-width:1;opacity:0.7"))
    parts.append(polyline(means[:, :2], "stroke:#377eb8;stroke-width:2"))
    parts.append(f'<text x="10" y="{height + 20:.0f}" font-family="sans-serif" font-size="13">black: truth; '
                 'dots: camera east (orange), north (green); blue: fused track and its 95 % ellipses</text>')
    parts.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(parts))


os.makedirs(arguments.out, exist_ok=True)
svg = os.path.join(arguments.out, "fuse_stream.svg")
write_svg(svg)
print(f"wrote {svg}")
