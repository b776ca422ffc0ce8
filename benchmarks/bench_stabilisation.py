"""Benchmark of the stabilisation diagram (not a test; prints a table).

On the Palisaden fixture (tests/data, 30 min at 20 Hz, six channels, high-pass
0.5 Hz), single-threaded BLAS (threadpoolctl), in one process:

- one thin SVD of ``H(0)`` (``numpy.linalg.svd(h0, full_matrices=False)``);
- ``modal.stabilisation`` to order 60 from the correlation functions
  (one ``decompose``, 30 eigenproblems, indicators, stability, clustering);
- both again on a taller Hankel (120 block rows: 720 x 726);
- the whole ``modal identify`` pipeline on the record (correlations too);
- pyOMA2's SSI-cov on the same preprocessed record with the same Hankel size
  (``br = 60``: 360 x 360) and the same orders (2 ... 60, step 2), if the
  optional ``bench`` extra (``pyoma-2``) is installed.

The issue's budget: the diagram costs at most 1.5 x one thin SVD of its
Hankel matrix. The SVD and the diagram are timed alternately, ``ROUNDS``
times; each round gives a ratio, and the table shows the median time and
the median ratio with its quartiles (the machine is shared: absolute times
follow the load, the ratios much less). The load average is printed with the table.

Run: ``.venv/bin/python benchmarks/bench_stabilisation.py``
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

import modal

FIXTURE = Path(__file__).resolve().parents[1] / "tests" / "data" / "palisaden_20hz_30min.npy"
ROWS, MAX_ORDER, ROUNDS = 60, 60, 21


def _seconds(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def side_by_side(reference, candidate, rounds=ROUNDS):
    """Median times of ``reference`` and ``candidate`` run alternately, and
    the quartiles of their per-round ratio (first, median, third)."""
    pairs = np.array([(_seconds(reference), _seconds(candidate)) for _ in range(rounds)])
    return np.median(pairs[:, 0]), np.median(pairs[:, 1]), np.percentile(pairs[:, 1] / pairs[:, 0], [25, 50, 75])


def main():
    acc, dt = modal.load_record(FIXTURE, fs=20)
    y = modal.zero_phase_filter(modal.detrend(acc), dt, highpass_hz=0.5)
    rows = []
    with threadpool_limits(1):
        for block_rows in (ROWS, 2 * ROWS):
            r = modal.correlations(y, 2 * block_rows + 1)
            h0 = modal.hankel(r, block_rows + 1, block_rows + 1)[: -y.shape[1]]
            modal.stabilisation(r, dt, MAX_ORDER, block_rows)  # warm-up
            t_svd, t_stab, ratio = side_by_side(lambda: np.linalg.svd(h0, full_matrices=False),
                                                lambda: modal.stabilisation(r, dt, MAX_ORDER, block_rows))
            rows.append((f"thin SVD of H(0) {h0.shape[0]} x {h0.shape[1]} ({block_rows} block rows)", t_svd, [1.0] * 3))
            rows.append((f"modal.stabilisation on it, orders 2..{MAX_ORDER}", t_stab, ratio))
            if block_rows == ROWS:
                t_svd_small = t_svd
                _, t_all, ratio_all = side_by_side(
                    lambda: np.linalg.svd(h0, full_matrices=False),
                    lambda: modal.identify_record(acc, dt, "ambient", MAX_ORDER, fmax=5, rows=ROWS, highpass_hz=0.5),
                    rounds=7)
                rows.append(("modal.identify_record (filter, correlations, diagram, selection)", t_all, ratio_all))
        try:
            from pyoma2.algorithms import SSI
            from pyoma2.setup import SingleSetup
        except ImportError:
            SSI = None
        if SSI is not None:
            def pyoma2_ssicov():
                setup = SingleSetup(y, fs=1 / dt)
                setup.add_algorithms(SSI(name="SSIcov", method="cov", br=ROWS, ordmin=2, ordmax=MAX_ORDER, step=2))
                setup.run_by_name("SSIcov")

            t_pyoma = min(_seconds(pyoma2_ssicov) for _ in range(3))
            rows.append(("pyOMA2 SSI-cov, same Hankel size and orders", t_pyoma, [t_pyoma / t_svd_small] * 3))
    width = max(len(name) for name, *_ in rows)
    print(f"load average {' '.join(f'{x:.1f}' for x in os.getloadavg())} on {os.cpu_count()} CPUs")
    print(f"{'step':<{width}}  seconds  x the SVD above it: median (quartiles)")
    for name, seconds, (q1, median, q3) in rows:
        print(f"{name:<{width}}  {seconds:7.4f}  {median:6.2f} ({q1:.2f}-{q3:.2f})")


if __name__ == "__main__":
    main()
