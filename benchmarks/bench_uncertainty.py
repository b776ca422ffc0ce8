"""Coverage of the uncertainty ``modal identify`` reports: how often the
true frequency (and damping) of a simulated structure lies within ±1.96
standard deviations (``freq_std_hz``, ``damping_std``) of the estimate.

Records: the four-storey shear frame of :mod:`modal.campaign` (modes 1.59,
4.21, 6.24, 7.84 Hz, damping 1.2-2 %), ambient white forces at every floor,
2 % noise, ``--minutes`` long at 50 Hz, each with its own seed; identified
with ``fmax`` 10 Hz and orders up to 40. A frequency estimate is matched to
the nearest true mode within 5 %.

Run: ``.venv/bin/python benchmarks/bench_uncertainty.py [--records 200] [--minutes 10]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import modal
from modal.campaign import shear_frame_modes

DAMPING = (0.012, 0.015, 0.018, 0.02)


def coverage(n_records: int, minutes: float, seed: int = 0, z: float = 1.96) -> dict:
    """Coverage of ``±z`` std over ``n_records`` simulated records."""
    omega, modes = shear_frame_modes()
    f_true = omega / (2 * np.pi)
    fs = 50.0
    rng = np.random.default_rng(seed)
    hits_f, hits_d, n, errors, stds = 0, 0, 0, [], []
    for r in range(n_records):
        acc = modal.ambient_response(omega, DAMPING, modes, modes, int(minutes * 60 * fs), 1 / fs, seed=seed + 1 + r,
                                     force_rms=100.0)
        acc += 0.02 * acc.std(axis=0) * rng.standard_normal(acc.shape)
        result, _ = modal.identify_record(acc, 1 / fs, "ambient", max_order=40, fmax=10)
        for f, sf, d, sd in result.modes[["freq_hz", "freq_std_hz", "damping", "damping_std"]].to_numpy():
            k = int(np.argmin(np.abs(f_true - f)))
            if abs(f / f_true[k] - 1) > 0.05 or not np.isfinite(sf):
                continue
            n += 1
            hits_f += abs(f - f_true[k]) <= z * sf
            hits_d += abs(d - DAMPING[k]) <= z * sd
            errors.append((f - f_true[k]) / f_true[k])
            stds.append(sf / f_true[k])
    return {"estimates": n, "freq_coverage": hits_f / n, "damping_coverage": hits_d / n,
            "rms_rel_error": float(np.sqrt(np.mean(np.square(errors)))),
            "rms_rel_std": float(np.sqrt(np.mean(np.square(stds))))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=200)
    parser.add_argument("--minutes", type=float, default=10.0)
    args = parser.parse_args()
    t = time.perf_counter()
    c = coverage(args.records, args.minutes)
    print(f"{args.records} records of {args.minutes:g} min, {c['estimates']} frequency estimates "
          f"({time.perf_counter() - t:.0f} s):")
    print(f"  ±1.96 freq_std_hz covers the true frequency in {100 * c['freq_coverage']:.1f} %")
    print(f"  ±1.96 damping_std covers the true damping in {100 * c['damping_coverage']:.1f} %")
    print(f"  rms relative frequency error {c['rms_rel_error']:.2e}, rms relative std {c['rms_rel_std']:.2e}")


if __name__ == "__main__":
    main()
