"""Coverage of the uncertainty ``modal identify`` reports: how often the
true frequency (and damping) of a simulated structure lies within ±1.96
standard deviations (``freq_std_hz``, ``damping_std``) of the estimate.

Records: the four-storey shear frame of :mod:`modal.campaign` (1.59, 4.21,
6.24, 7.84 Hz), 2 % sensor noise, at 50 Hz, each with its own seed
(``numpy.random.default_rng([seed, case, minutes, record])``), simulated
exactly in state space (``_simulation.py``); four cases:

- ``white``: proportional damping 1.2-2 %, independent white forces at
  every floor (the simulator's first case, as before);
- ``coloured``: the same forces low-passed at the second mode (second-order
  Butterworth): modes 3 and 4 excited 10-20 dB less;
- ``dashpot``: a dashpot at the first floor added to 1 % proportional
  damping: non-proportional damping, complex modes (damping 2.3-3.5 %);
- ``both``: the dashpot and the coloured forces.

Identified with ``fmax`` 10 Hz and orders up to 40. Each trusted row (no
``flag``) within 5 % of a true mode counts once (the first on that mode);
the true damping is ``-Re lambda / |lambda|`` of the state matrix's
eigenvalue, the true frequency ``|lambda| / 2 pi``.

Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_uncertainty.py [--records 20] [--minutes 2 20]
[--cases white coloured dashpot both]``
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import pandas as pd

import modal
from _simulation import from_modes, natural_hz, proportional, simulate, with_dashpot
from modal.campaign import shear_frame_modes

DAMPING = (0.012, 0.015, 0.018, 0.02)
CASES = ("white", "coloured", "dashpot", "both")
FS = 50.0
#: The dashpot of the non-proportional cases (N s/m, first floor to the ground).
DASHPOT = 1.0e4


def structure(case):
    """``(m, c, k, colour_hz)`` of the shear frame in ``case``."""
    m, k = from_modes(*shear_frame_modes())
    if case in ("dashpot", "both"):
        c = with_dashpot(proportional(m, k, [0.01] * 4), 0, DASHPOT)
    else:
        c = proportional(m, k, DAMPING)
    return m, c, k, natural_hz(m, k, 1) if case in ("coloured", "both") else None


def coverage(case: str, n_records: int, minutes: float, seed: int = 0, z: float = 1.96) -> dict:
    """Coverage of ``±z`` std over ``n_records`` simulated records of ``case``."""
    m, c, k, colour = structure(case)
    hits_f = hits_d = n = 0
    errors, stds = [], []
    for r in range(n_records):
        rng = np.random.default_rng([seed, CASES.index(case), int(minutes * 60), r])
        acc, f_true, z_true = simulate(m, c, k, [0, 1, 2, 3], 1 / FS, int(minutes * 60 * FS), rng, colour)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result, _ = modal.identify_record(acc, 1 / FS, "ambient", max_order=40, fmax=10)
        seen = set()
        for f, sf, d, sd in result.trusted_modes[["freq_hz", "freq_std_hz", "damping", "damping_std"]].to_numpy():
            j = int(np.argmin(np.abs(f_true - f)))
            if abs(f / f_true[j] - 1) > 0.05 or not np.isfinite(sf) or j in seen:
                continue
            seen.add(j)
            n += 1
            hits_f += abs(f - f_true[j]) <= z * sf
            hits_d += abs(d - z_true[j]) <= z * sd
            errors.append((d - z_true[j]) / z_true[j])
            stds.append(sd / z_true[j])
    return {"case": case, "minutes": minutes, "records": n_records, "estimates": n,
            "freq_coverage": round(hits_f / n, 3) if n else np.nan,
            "damping_coverage": round(hits_d / n, 3) if n else np.nan,
            "damping_rms_rel_error": round(float(np.sqrt(np.mean(np.square(errors)))), 3) if n else np.nan,
            "damping_rms_rel_std": round(float(np.sqrt(np.mean(np.square(stds)))), 3) if n else np.nan}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=20, help="records per case and duration")
    parser.add_argument("--minutes", type=float, nargs="+", default=[2.0, 20.0])
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    args = parser.parse_args()
    t = time.perf_counter()
    table = pd.DataFrame([coverage(case, args.records, minutes) for case in args.cases for minutes in args.minutes])
    print(table.to_markdown(index=False))
    print(f"\n({time.perf_counter() - t:.0f} s)")


if __name__ == "__main__":
    main()
