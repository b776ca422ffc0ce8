"""Benchmark the ERA beside its peers (not a test; prints a markdown table).

One process, single-threaded BLAS, round-robin: every round times each
implementation once on the same record, beside one thin
``numpy.linalg.svd(H(0), full_matrices=False)`` of its 480 x 2000 Hankel matrix
(12 sensors, 20 000 samples, 40 block rows x 2 000 block columns, order 24), and
reports the median over rounds of time / SVD time. A machine shared with other
work makes absolute times noisy; the ratios, measured side by side, much less so.

Peers (optional: ``pip install -e .[bench]``): python-control's
``eigensys_realization`` and era-algorithm's ``ERA.era_method2``; each is run to
its state matrix and that matrix's eigenvalues (the poles every ERA ends with).

Run: ``.venv/bin/python benchmarks/bench_era_peers.py [--rounds 15]``
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # before numpy is imported: BLAS reads them at load

import argparse  # noqa: E402
import importlib  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import modal  # noqa: E402

decompose = modal.decompose

N_CHANNELS, N_SAMPLES, ROWS, COLS, N_MODES, DT = 12, 20_000, 40, 2000, 12, 0.005


def record():
    """12 modes seen by 12 sensors, 0.5 % damping, 2 % noise (the engine benchmark's record)."""
    rng = np.random.default_rng(0)
    w = np.linspace(5.0, 300.0, N_CHANNELS)
    rec = modal.impulse_response(w, rng.standard_normal((N_CHANNELS, N_CHANNELS)), np.ones(N_CHANNELS),
                                 0.005, N_SAMPLES, 0.01)
    return modal.with_noise(rec, 0.02, 1).acceleration


def candidates(y):
    """name -> zero-argument callable returning the discrete poles (or None)."""
    h0 = modal.hankel(y, ROWS, COLS)
    runs = {
        "thin `numpy.linalg.svd` of H(0) (reference)": lambda: np.linalg.svd(h0, full_matrices=False),
        '`modal.era` (svd="auto": Gram route)': lambda: modal.era(y, DT, N_MODES, ROWS, COLS).eigenvalues,
        '`modal.era` (svd="full")': lambda: modal.era(y, DT, N_MODES, ROWS, COLS, svd="full").eigenvalues,
        "`decompose(H(0), 60)` (a stabilisation diagram's one decomposition)":
            lambda: decompose(h0, 60, block=(N_CHANNELS, 1)),
        "`decompose(H(0), 120)`": lambda: decompose(h0, 120, block=(N_CHANNELS, 1)),
    }
    try:
        import control

        yy = y.T[:, None, :]  # (outputs, inputs, time)
        runs["python-control `eigensys_realization`"] = lambda: np.linalg.eigvals(
            control.eigensys_realization(yy, 2 * N_MODES, m=ROWS, n=COLS, dt=DT)[0].A)
    except ImportError:
        print("python-control not installed: pip install -e .[bench]")
    try:
        import ERA  # era-algorithm

        markov = y.T  # (outputs, time)
        runs["era-algorithm `era_method2`"] = lambda: np.linalg.eigvals(
            ERA.era_method2(markov[:, : ROWS + COLS + 1], ROWS, COLS, 1, N_CHANNELS, 2 * N_MODES)[1])
    except ImportError:
        print("era-algorithm not installed: pip install -e .[bench]")
    return runs


def agreement(runs):
    """Largest relative deviation of each ERA's natural frequencies |ln z| / dt
    from the full-SVD ``modal.era``'s."""
    def omega(z):
        z = np.asarray(z)
        z = z[z.imag > 0]
        return np.sort(np.abs(np.log(z)) / DT)

    ref = omega(runs['`modal.era` (svd="full")']())
    out = {}
    for name, run in runs.items():
        if "reference" not in name and "decompose" not in name:
            got = omega(run())
            out[name] = np.max(np.abs(got / ref - 1)) if got.shape == ref.shape else np.nan
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=15)
    args = parser.parse_args()
    y = record()
    with threadpool_limits(limits=1):
        runs = candidates(y)
        deviation = agreement(runs)
        for run in runs.values():  # warm-up: imports, caches
            run()
        times = {name: [] for name in runs}
        for _ in range(args.rounds):
            for name, run in runs.items():
                t0 = time.perf_counter()
                run()
                times[name].append(time.perf_counter() - t0)
    reference = np.array(times[next(iter(runs))])
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"# {platform.machine()}, {os.cpu_count()} cores, load average {load:.2f}, numpy {np.__version__}, "
          f"single-threaded BLAS, {args.rounds} rounds, 480 x 2000 Hankel, order 24\n")
    print("| implementation | median ms | time / thin SVD (median of rounds) "
          "| max rel. freq. deviation from full-SVD ERA |")
    print("|---|---|---|---|")
    for name, t in times.items():
        t = np.array(t)
        dev = deviation.get(name)
        dev = "" if dev is None else f"{dev:.1e}"
        print(f"| {name} | {1e3 * np.median(t):.1f} | {np.median(t / reference):.2f} x | {dev} |")


if __name__ == "__main__":
    main()
