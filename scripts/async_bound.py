#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""How much accuracy can any live estimate lose when views stop sharing a clock? (docs/results.md)

A model small enough to solve exactly: every object moves in the plane with a nearly constant
velocity (white acceleration of spectral density q per axis), n views measure its position with
independent noise sigma per axis, one message per view and frame period T. Synchronous: every view at
t_k = kT. Asynchronous: view j at kT + phase_j, one phase per view and scene, uniform in [0, T) (as
`stgf dataset ... --asynchronous`, without the 2 ms jitter). The estimator is the exact Kalman filter
of that model, the best causal estimate there is when the model is known; each measured time is
scored with the estimate after every measurement up to it (the live answer, as docs/design.md §1.8
defines a row's estimate).

With --offset S each view also has a constant offset per scene (N(0, S^2) per axis) in its
measurements, and the filter estimates the offsets with the motion (state: position, velocity, every
view's offset), as `ours` does with its registration offsets.

Printed per q (and offset): mean 2D error of the filtered estimate ("ours"), of the prediction before the update
("ours-l") and of the views' mean at that time ("wls"), synchronous and asynchronous. The ratios
wls/ours and ours-l/ours on the synchronous rows place a real benchmark on the q axis; async/sync is
what the best live estimator loses there. Only q T^3 / sigma^2 and n matter, so sigma is fixed.

    python3 scripts/async_bound.py --views 7 --period 0.142857 --q 0.01 0.03 0.1 0.3   # mpl-like
    python3 scripts/async_bound.py --views 4 --period 0.1 --q 0.01 0.03 0.1 0.3        # cad-like
"""
import argparse

import numpy as np


def transition(dt):
    f = np.eye(4)
    f[0, 2] = f[1, 3] = dt
    return f


def process_noise(dt, q):
    block = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    m = np.zeros((4, 4))
    m[np.ix_([0, 2], [0, 2])] = block
    m[np.ix_([1, 3], [1, 3])] = block
    return m


def run(q, sigma, views, period, steps, scenes, asynchronous, seed, offset=0.0):
    rng = np.random.default_rng(seed)
    errors = {"ours": [], "ours-l": [], "wls": []}
    # The filter's state: position and velocity, then each view's offset when views have one.
    size = 4 + (2 * views if offset > 0 else 0)
    r = sigma**2 * np.eye(2)
    for _ in range(scenes):
        phases = rng.uniform(0.0, period, views) if asynchronous else np.zeros(views)
        offsets = rng.normal(0.0, offset, (views, 2)) if offset > 0 else np.zeros((views, 2))
        # Every (time, view) message of the scene, in time order; views at one time form one event.
        messages = sorted((k * period + phases[j], j) for k in range(steps) for j in range(views))
        events = []
        for t, j in messages:
            if events and abs(events[-1][0] - t) < 1e-12:
                events[-1][1].append(j)
            else:
                events.append((t, [j]))
        state = np.concatenate([np.zeros(2), rng.normal(0.0, 1.0, 2)])  # truth: position, velocity
        mean = covariance = None
        last = 0.0
        for t, seen in events:
            dt = t - last
            if dt > 0:
                state = transition(dt) @ state + rng.multivariate_normal(np.zeros(4), process_noise(dt, q))
            z = [state[:2] + offsets[j] + rng.normal(0.0, sigma, 2) for j in seen]
            if mean is None:  # first event: position from the measurements, velocity unknown
                mean = np.zeros(size)
                mean[:2] = np.mean(z, 0)
                covariance = np.zeros((size, size))
                covariance[:4, :4] = np.diag([sigma**2 / len(z)] * 2 + [4.0, 4.0])
                if offset > 0:  # the offsets' prior; the first position holds the mean offset of the views seen
                    covariance[4:, 4:] = offset**2 * np.eye(2 * views)
                    covariance[:2, :2] += offset**2 / len(z) * np.eye(2)
                    for j in seen:
                        covariance[:2, 4 + 2 * j:6 + 2 * j] = covariance[4 + 2 * j:6 + 2 * j, :2] = offset**2 / len(z) * np.eye(2)
                last = t
                continue
            f = np.eye(size)
            f[:4, :4] = transition(t - last)
            noise = np.zeros((size, size))
            noise[:4, :4] = process_noise(t - last, q)
            mean, covariance = f @ mean, f @ covariance @ f.T + noise
            last = t
            scored = t > 3 * period  # after the filter has settled, as the benchmarks score from step 2
            if scored:
                errors["ours-l"].append(np.linalg.norm(mean[:2] - state[:2]))
            for j, measurement in zip(seen, z):
                h = np.zeros((2, size))
                h[0, 0] = h[1, 1] = 1.0
                if offset > 0:
                    h[:, 4 + 2 * j:6 + 2 * j] = np.eye(2)
                gain = covariance @ h.T @ np.linalg.inv(h @ covariance @ h.T + r)
                mean = mean + gain @ (measurement - h @ mean)
                covariance = (np.eye(size) - gain @ h) @ covariance
            if scored:
                errors["ours"].append(np.linalg.norm(mean[:2] - state[:2]))
                errors["wls"].append(np.linalg.norm(np.mean(z, 0) - state[:2]))
    return {name: float(np.mean(values)) for name, values in errors.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--views", type=int, default=7)
    parser.add_argument("--period", type=float, default=1 / 7)
    parser.add_argument("--sigma", type=float, default=0.1, help="noise per axis and view (m)")
    parser.add_argument("--offset", type=float, nargs="+", default=[0.0],
                        help="sigma per axis of each view's constant offset (m), drawn per scene; the filter estimates the offsets with the motion")
    parser.add_argument("--q", type=float, nargs="+", default=[0.01, 0.03, 0.1, 0.3])
    parser.add_argument("--steps", type=int, default=30)
    parser.add_argument("--scenes", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    print(f"{args.views} views, period {args.period:.4f} s, sigma {args.sigma} m, {args.scenes} scenes x {args.steps} frames, seed {args.seed}")
    print()
    print("| q (m²/s³) | offset (m) | sync ours | sync ours-l | sync wls | wls / ours | ours-l / ours | async ours | async / sync |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for offset in args.offset:
        for q in args.q:
            sync = run(q, args.sigma, args.views, args.period, args.steps, args.scenes, False, args.seed, offset)
            unsync = run(q, args.sigma, args.views, args.period, args.steps, args.scenes, True, args.seed, offset)
            print(f"| {q:g} | {offset:g} | {sync['ours']:.4f} | {sync['ours-l']:.4f} | {sync['wls']:.4f} | "
                  f"{sync['wls'] / sync['ours']:.2f} | {sync['ours-l'] / sync['ours']:.2f} | {unsync['ours']:.4f} | "
                  f"{unsync['ours'] / sync['ours']:.3f} |", flush=True)

if __name__ == "__main__":
    main()
