"""A tall shear frame's overlapping upper modes: how many of its modes
``modal identify`` finds with default options (trusted: no ``flag``), how
many trusted rows are spurious, and how many real modes carry only the
spectral witness's ``no spectral peak``.

Records: the fifteen-storey frame of ``_simulation.storey_frame`` (0.31-7.3
Hz, damping 0.8-3 % per mode, each record its own draw of masses and
damping), six of its floors measured (drawn per record), white forces at
every floor, 2 % sensor noise, 20 Hz; 10- and 30-minute records, seeded
``numpy.random.default_rng(record)``. A trusted row matches a true mode
within 2 %; the true modes count below 0.8 times the Nyquist frequency (all
fifteen).

Run (one BLAS thread; the baseline from another checkout with
``PYTHONPATH=that/checkout``)::

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_storeys.py [--records 6]
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import pandas as pd

import modal
from _simulation import simulate, storey_frame

FS = 20.0
MATCH = 0.02


def run(records: int, minutes=(10, 30)) -> pd.DataFrame:
    """One row per record and duration: true modes, found, spurious,
    duplicate, real modes flagged by the witness alone."""
    rows = []
    for r in range(records):
        for length in minutes:
            rng = np.random.default_rng(r)
            m, c, k = storey_frame(rng)
            sensors = sorted(rng.choice(len(m), 6, replace=False))
            acc, f_true, _ = simulate(m, c, k, sensors, 1 / FS, int(length * 60 * FS), rng)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result, _ = modal.identify_record(acc, 1 / FS, "ambient")
            flag = result.modes["flag"].fillna("").astype(str)
            trusted = result.modes.loc[flag == "", "freq_hz"].to_numpy()
            expected = f_true[f_true < 0.8 * FS / 2]
            near = np.abs(trusted[:, None] / expected[None, :] - 1) <= MATCH
            hits = near.sum(axis=0)
            witness = [np.min(np.abs(expected / f - 1)) <= MATCH
                       for f, reason in zip(result.modes["freq_hz"], flag) if reason == "no spectral peak"]
            rows.append({"minutes": length, "record": r, "true": len(expected), "found": int(np.sum(hits > 0)),
                         "spurious": int(np.sum(~near.any(axis=1))), "duplicate": int(np.sum(np.clip(hits - 1, 0, None))),
                         "flagged_real_witness": int(np.sum(witness))})
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=6)
    args = parser.parse_args()
    t = time.perf_counter()
    table = run(args.records)
    print(table.groupby("minutes")[["true", "found", "spurious", "duplicate", "flagged_real_witness"]].sum()
          .to_markdown())
    print(f"\n{len(table)} records in {time.perf_counter() - t:.0f} s")


if __name__ == "__main__":
    main()
