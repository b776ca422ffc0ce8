"""Impact tests whose damping falls with the amplitude: how often ``modal
identify --free-decay`` trusts a row between the two modes of a close pair
(a broad fit across both, not a mode), and how often it keeps the pair.

Records (``_simulation.falling_damping_decays``): 182, 187, 515 and 2270 Hz
on three channels at 12.8 kHz, damping 0.6-0.8 % at the end of the decay
and four times that at the blow, 0.1 % noise, each from its own seed;
identified with default options.

Run (the baseline from another checkout with ``PYTHONPATH=that/checkout``)::

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_impact.py [--records 10] [--seconds 1.5 3]
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import pandas as pd

import modal
from _simulation import falling_damping_decays

FS = 12800.0
FREQ_HZ = [182.0, 187.0, 515.0, 2270.0]
DAMPING = [0.006, 0.007, 0.008, 0.006]
SHAPES = np.array([[1.0, 0.6, -0.4], [0.3, -1.0, 0.8], [1.0, -0.2, 0.5], [0.4, 0.9, 1.0]]).T
#: A trusted row within this relative distance of a true mode is that mode.
MATCH = 0.005


def score(seconds: float, records: int) -> dict:
    """Per duration: records with a trusted row strictly between the pair,
    records with both modes of the pair trusted, and the blends flagged."""
    between = pair = flagged = 0
    for seed in range(records):
        y = falling_damping_decays(FREQ_HZ, DAMPING, SHAPES, 1 / FS, int(seconds * FS), seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result, _ = modal.identify_record(y, 1 / FS, "free_decay")
        f = result.modes["freq_hz"].to_numpy()
        flags = result.modes["flag"].to_numpy()
        trusted = f[flags == ""]
        near = np.abs(trusted[:, None] / np.asarray(FREQ_HZ[:2])[None, :] - 1) <= MATCH
        between += bool(np.any((trusted > FREQ_HZ[0]) & (trusted < FREQ_HZ[1]) & ~near.any(axis=1)))
        pair += bool(near.any(axis=0).all())
        flagged += sum("blend of" in flag for flag in flags)
    return {"seconds": seconds, "records": records, "trusted_between": between, "pair_trusted": pair,
            "blend_flags": flagged}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=10)
    parser.add_argument("--seconds", type=float, nargs="+", default=[1.5, 3.0])
    args = parser.parse_args()
    t = time.perf_counter()
    print(pd.DataFrame([score(s, args.records) for s in args.seconds]).to_markdown(index=False))
    print(f"\n({time.perf_counter() - t:.0f} s)")


if __name__ == "__main__":
    main()
