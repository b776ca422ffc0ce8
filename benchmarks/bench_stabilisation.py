"""Benchmark of the stabilisation diagram (not a test; prints a table).

On the Palisaden fixture (tests/data, 30 min at 20 Hz, six channels, high-pass
0.5 Hz), times in one process, best of 5:

- one thin SVD of ``H(0)`` (``numpy.linalg.svd(h0, full_matrices=False)``);
- ``modal.stabilisation`` to order 60 from the correlation functions
  (one ``decompose`` and 30 ``realise`` calls, stability, clustering);
- the whole ``modal identify`` pipeline on the record (correlations too);
- pyOMA2's SSI-cov on the same preprocessed record with the same Hankel size
  (``br = 60``: 360 x 360) and the same orders (2 ... 60, step 2), if the
  optional ``bench`` extra (``pyoma-2``) is installed.

The issue's budget: the diagram costs at most 1.5 x one thin SVD of its
Hankel matrix. Timings on a shared machine are noisy; the ratios, measured
in one process, are what to compare.

Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_stabilisation.py``
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

import numpy as np
from bench_engine import best_of as best_of_7  # run as a script: benchmarks/ is on sys.path

import modal

best_of = partial(best_of_7, repeat=5)

FIXTURE = Path(__file__).resolve().parents[1] / "tests" / "data" / "palisaden_20hz_30min.npy"
ROWS, MAX_ORDER = 60, 60


def main():
    acc, dt = modal.load_record(FIXTURE, fs=20)
    y = modal.zero_phase_filter(modal.detrend(acc), dt, highpass_hz=0.5)
    r = modal.correlations(y, 2 * ROWS + 1)
    h0 = modal.hankel(r, ROWS + 1, ROWS + 1)[: -y.shape[1]]
    rows = []
    t_svd = best_of(lambda: np.linalg.svd(h0, full_matrices=False))
    rows.append((f"thin SVD of H(0) {h0.shape[0]} x {h0.shape[1]}", t_svd))
    t_stab = best_of(lambda: modal.stabilisation(r, dt, MAX_ORDER, ROWS))
    rows.append((f"modal.stabilisation, orders 2..{MAX_ORDER}", t_stab))
    # The per-order work (eigenvalues, modal amplitude coherence) does not grow
    # with the Hankel matrix; the SVD does: the ratio on a taller Hankel.
    r2 = modal.correlations(y, 4 * ROWS + 1)
    h0_2 = modal.hankel(r2, 2 * ROWS + 1, 2 * ROWS + 1)[: -y.shape[1]]
    t_svd2 = best_of(lambda: np.linalg.svd(h0_2, full_matrices=False))
    t_stab2 = best_of(lambda: modal.stabilisation(r2, dt, MAX_ORDER, 2 * ROWS))
    rows.append((f"thin SVD of H(0) {h0_2.shape[0]} x {h0_2.shape[1]} (rows = {2 * ROWS})", t_svd2))
    rows.append((f"modal.stabilisation on it, orders 2..{MAX_ORDER} ({t_stab2 / t_svd2:.2f} x its SVD)", t_stab2))
    t_all = best_of(lambda: modal.identify_record(acc, dt, "ambient", MAX_ORDER, fmax=5, rows=ROWS, highpass_hz=0.5))
    rows.append(("modal.identify_record (filter, correlations, diagram, selection)", t_all))
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

        t_pyoma = best_of(pyoma2_ssicov, repeat=3)
        rows.append(("pyOMA2 SSI-cov, same Hankel size and orders", t_pyoma))
    width = max(len(name) for name, _ in rows)
    print(f"{'step':<{width}}  seconds  x thin SVD")
    for name, seconds in rows:
        print(f"{name:<{width}}  {seconds:7.4f}  {seconds / t_svd:6.2f}")


if __name__ == "__main__":
    main()
