"""Automatic mode selection on simulated structures whose modes are known:
how many true modes ``modal identify`` finds (trusted: no ``flag``), how
many trusted rows are spurious or duplicates, how many real modes are
flagged, and the coverage of ``freq_std_hz`` and ``damping_std``.

Records (ambient, default options of ``modal.identify_record``: no
``fmax``, settings from the record), each simulated exactly in state space
(zero-order hold of forces held over a sample) with sensor noise:

- ``frame``: a four-storey shear frame
  (2.46-12.04 Hz), proportional damping 1.2-2 %, white forces;
- ``close``: two modes 0.8 % apart with different shapes (a symmetric
  two-way frame, MAC of the pair about 0);
- ``heavy``: the frame damped 6-10 %;
- ``complex``: a chain with one dashpot at its base (non-proportional
  damping, complex modes);
- ``coloured``: the frame under forces low-passed at its second mode
  (second-order Butterworth: 40 dB/decade less force above it);
- ``random``: chains of 3-6 masses with random masses, stiffnesses and
  damping (0.5-4 %, proportional or one extra dashpot), 2 to 6 sensors,
  white or coloured forces, 1-5 % noise.

Each kind in 2-minute and 20-minute records. A trusted mode matches a true
one within ``MATCH`` (relative frequency); a second trusted mode on the same
true one is a duplicate, a trusted mode on none is spurious. True modes
count when they lie below 0.8 times the Nyquist frequency.

Run (one BLAS thread; the baseline from another checkout with
``PYTHONPATH=that/checkout``)::

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_selection.py [--records 12] [--out table.csv] [--seed 1] [--gains]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pandas as pd
import scipy.linalg

import modal
from _simulation import chain, natural_hz, proportional, simulate, with_dashpot

MATCH = 0.02
KINDS = ("frame", "close", "heavy", "complex", "coloured", "random")
MINUTES = (2, 20)


def structure(kind, rng):
    """``(m, c, k, sensors, colour_hz, noise)`` of one record of ``kind``."""
    frame_m, frame_k = chain([2.0e4, 2.0e4, 2.0e4, 1.5e4], [4.0e7, 3.5e7, 3.0e7, 2.5e7])
    if kind in ("frame", "coloured", "heavy"):
        zeta = [0.06, 0.07, 0.08, 0.1] if kind == "heavy" else [0.012, 0.015, 0.018, 0.02]
        c = proportional(frame_m, frame_k, zeta)
        colour = None
        if kind == "coloured":
            colour = natural_hz(frame_m, frame_k, 1)
        return frame_m, c, frame_k, [0, 1, 2, 3], colour, 0.02
    if kind == "close":  # x and y sway of a two-storey frame, y 0.8 % stiffer in frequency
        m1, k1 = chain([2.0e3, 1.5e3], [1.2e6, 0.8e6])
        m = scipy.linalg.block_diag(m1, m1)
        k = scipy.linalg.block_diag(k1, k1 * 1.008**2)
        c = proportional(m, k, [0.015, 0.015, 0.02, 0.02])
        return m, c, k, [0, 1, 2, 3], None, 0.02
    if kind == "complex":
        m, k = chain([1.0e3] * 4, [4.0e6] * 4)
        c = with_dashpot(proportional(m, k, [0.01] * 4), 0, 4.0e3)  # one dashpot at the base: non-proportional
        return m, c, k, [0, 1, 2, 3], None, 0.02
    n = int(rng.integers(3, 7))
    m, k = chain(rng.uniform(0.5, 2.0, n) * 1e3, rng.uniform(0.5, 2.0, n) * 2e6)
    c = proportional(m, k, rng.uniform(0.005, 0.04, n))
    if rng.random() < 0.3:
        c = with_dashpot(c, 0, rng.uniform(1e3, 4e3))
    sensors = np.sort(rng.choice(n, size=int(rng.integers(min(2, n), n + 1)), replace=False))
    colour = None
    if rng.random() < 0.5:
        colour = natural_hz(m, k, 1)
    return m, c, k, list(sensors), colour, float(rng.uniform(0.01, 0.05))


def score(modes, f_true, z_true, nyquist):
    """Counts of one record: true modes, found, missed, spurious, duplicate,
    flagged real, flagged spurious; and the coverage hits."""
    expected = f_true < 0.8 * nyquist
    flag = modes["flag"].fillna("") if "flag" in modes else pd.Series([""] * len(modes), index=modes.index)
    modes = modes.assign(flag=flag)
    trusted = modes[flag == ""]
    doubtful = modes[flag != ""]
    hits = np.zeros(len(f_true), dtype=int)
    row = {"true": int(expected.sum()), "spurious": 0, "flagged_real": 0, "flagged_spurious": 0,
           "cover_n": 0, "cover_f": 0, "cover_d": 0}
    for f, sf, d, sd in trusted[["freq_hz", "freq_std_hz", "damping", "damping_std"]].to_numpy():
        j = int(np.argmin(np.abs(f_true - f)))
        if abs(f / f_true[j] - 1) > MATCH:
            row["spurious"] += 1
            continue
        hits[j] += 1
        if hits[j] == 1 and np.isfinite(sf):
            row["cover_n"] += 1
            row["cover_f"] += abs(f - f_true[j]) <= 1.96 * sf
            row["cover_d"] += abs(d - z_true[j]) <= 1.96 * sd
    row["flagged_real_witness"] = 0
    for f, flag in zip(doubtful["freq_hz"], doubtful["flag"]):
        real = np.min(np.abs(f_true / f - 1)) <= MATCH
        row["flagged_real" if real else "flagged_spurious"] += 1
        # a real mode whose only reason is the spectral witness's (modal.spectral_support), not the selection's
        row["flagged_real_witness"] += bool(real and flag == "no spectral peak")
    row["found"] = int(np.sum((hits > 0) & expected))
    row["duplicate"] = int(np.sum(np.clip(hits - 1, 0, None)))
    return row


def run(records: int, seed: int = 0, gains: bool = False) -> pd.DataFrame:
    """Identify and score ``records`` records of each kind and duration; with
    ``gains``, each channel is multiplied by ``10^U(-3, 3)`` (channels in
    other units), drawn from its own generator so the records are the same."""
    import warnings

    rows = []
    for kind in KINDS:
        for minutes in MINUTES:
            for r in range(records):
                rng = np.random.default_rng([seed, KINDS.index(kind), minutes, r])
                m, c, k, sensors, colour, noise = structure(kind, rng)
                f_top = natural_hz(m, k, len(m) - 1)
                fs = float(np.round(8 * f_top))
                acc, f_true, z_true = simulate(m, c, k, sensors, 1 / fs, int(minutes * 60 * fs), rng, colour, noise)
                if gains:
                    draw = np.random.default_rng([99, seed, KINDS.index(kind), minutes, r])
                    acc = acc * 10.0 ** draw.uniform(-3, 3, acc.shape[1])
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    try:
                        result, _ = modal.identify_record(acc, 1 / fs, "ambient")
                        modes = result.modes
                    except ValueError:
                        modes = pd.DataFrame(columns=["freq_hz", "freq_std_hz", "damping", "damping_std"])
                rows.append({"kind": kind, "minutes": minutes, "record": r,
                             **score(modes, f_true, z_true, fs / 2)})
    return pd.DataFrame(rows)


def summary(table: pd.DataFrame) -> pd.DataFrame:
    sums = table.groupby(["kind", "minutes"], sort=False)[
        ["true", "found", "spurious", "duplicate", "flagged_real", "flagged_real_witness", "flagged_spurious",
         "cover_n", "cover_f", "cover_d"]].sum()
    total = sums.sum().to_frame("all").T
    sums = pd.concat([sums, total.set_index(pd.MultiIndex.from_tuples([("all", "")]))])
    sums["freq_coverage"] = (sums["cover_f"] / sums["cover_n"]).round(3)
    sums["damping_coverage"] = (sums["cover_d"] / sums["cover_n"]).round(3)
    return sums.drop(columns=["cover_f", "cover_d"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=12, help="records per kind and duration")
    parser.add_argument("--out", help="CSV of every record's counts")
    parser.add_argument("--seed", type=int, default=0, help="seed of the records (0: the documented ones)")
    parser.add_argument("--gains", action="store_true", help="each channel times 10^U(-3, 3) (other units)")
    args = parser.parse_args()
    start = time.perf_counter()
    table = run(args.records, args.seed, args.gains)
    if args.out:
        table.to_csv(args.out, index=False)
    print(summary(table).to_markdown())
    print(f"\n{len(table)} records in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
