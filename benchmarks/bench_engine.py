"""Benchmark the engine's kernels (not a test; prints a table).

Times era, tcm and cera at the thesis's sizes (Sec. 6.1: 6 sensors, 3594
samples, ERA r = 24, s = 100; CERA s = 360), and era on a 12-sensor,
20 000-sample record with a 480 x 2000 Hankel matrix and order 24, beside a
bare ``numpy.linalg.svd(H, full_matrices=False)`` of that matrix, with
single-threaded BLAS (threadpoolctl), as the ERA's budget is stated: with
two BLAS threads the 480 x 2000 SVD gains more than the ERA (0.30 x instead
of 0.23 x on this project's 2 cores).

Run: ``.venv/bin/python benchmarks/bench_engine.py``
"""

from __future__ import annotations

import platform
import time

import numpy as np
from threadpoolctl import threadpool_limits

import modal


def best_of(fn, repeat=7):
    """Smallest wall time of ``repeat`` calls, in seconds."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main():
    beam = modal.SimplySupportedBeam(5, 30, 1)
    omega = beam.natural_frequencies(6)
    dt = 2 * np.pi / omega[-1] / 10
    rec = modal.with_noise(modal.beam_impulse_response(beam, 6, 10 / 7, beam.stations(7), dt, 3594, 0.01), 0.03, 0)
    rows = [
        ("tcm, 6 ch x 3594, lag 0", best_of(lambda: modal.tcm(rec.acceleration, dt, vel=rec.velocity))),
        ("tcm, 6 ch x 3594, integrated vel", best_of(lambda: modal.tcm(rec.acceleration, dt))),
        ("era, 6 ch, r=24 s=100, n=6", best_of(lambda: modal.era(rec.acceleration, dt, 6, 24, 100))),
        ("cera, 6 ch, s=360, n=6", best_of(lambda: modal.cera(rec.acceleration, dt, 6, 360))),
    ]

    rng = np.random.default_rng(0)
    w = np.linspace(5.0, 300.0, 12)
    big = modal.with_noise(
        modal.impulse_response(w, rng.standard_normal((12, 12)), np.ones(12), 0.005, 20000, 0.01), 0.02, 1
    ).acceleration
    h = modal.hankel(big[None], 40, 2000)
    t_svd = best_of(lambda: np.linalg.svd(h, full_matrices=False))
    t_era = best_of(lambda: modal.era(big, 0.005, 12, 40, 2000))
    rows += [
        ("numpy.linalg.svd of the 480 x 2000 Hankel", t_svd),
        ("era, 12 ch x 20000, 480 x 2000, order 24", t_era),
    ]
    print(f"# {platform.processor() or platform.machine()}, numpy {np.__version__}, single-threaded BLAS")
    print("| kernel | best of 7 (ms) |\n|---|---|")
    for name, t in rows:
        print(f"| {name} | {1e3 * t:.1f} |")
    print(f"\nERA / SVD ratio: {t_era / t_svd:.2f} (target <= 0.25)")


if __name__ == "__main__":
    with threadpool_limits(1):
        main()
