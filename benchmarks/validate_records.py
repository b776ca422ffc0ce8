"""Validation of ``modal identify`` on public measured records.

Reads the records under ``../shared/data`` (never copied into the project:
the Weimar frame is GPL-3.0, the cantilever CC BY-SA 4.0; see each
SOURCE.md) and compares the automatically selected modes with the published
ones:

- Weimar steel frame, setup 1, channels 0-4, references 3 and 4 (ambient):
  the eight reference modes below 10 Hz (pyOMA PoGER, SOURCE.md), within 0.5 %;
- Palisaden CLT building, full 90-min record (ambient): 1.88, 2.42, 2.68 Hz
  (pyOMA2 documentation) within 0.5 %, and four trusted modes in all (the
  weak one near 3.6 Hz once, not split in two: issue 21);
- USC steel cantilever (impact, free decay, LabVIEW .lvm): the modes below
  150 Hz against the peaks of its amplitude spectrum after the impact (no
  published modal results), within 0.5 %.

Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/validate_records.py [DATA_DIR]``.
Compares the trusted modes (no ``flag``, issue 32); lists the doubtful ones with
their reasons. Prints one Markdown table per record and exits non-zero if a
target is missed.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

import modal


def _shared_data() -> Path:
    """``../shared/data`` beside the project (or beside any folder above it, for worktrees)."""
    for folder in Path(__file__).resolve().parents[1:]:
        if (folder / "shared" / "data").is_dir():
            return folder / "shared" / "data"
    raise SystemExit("no shared/data folder found above the project: pass its path")


DATA = Path(sys.argv[1]) if len(sys.argv) > 1 else _shared_data()
TOLERANCE = 0.005

WEIMAR_REFERENCE = [1.229, 1.436, 2.100, 4.017, 4.769, 6.683, 7.614, 9.664]  # PoGER, 15 setups
PALISADEN_REFERENCE = [1.88, 2.42, 2.68]


def spectrum_peaks(acc, dt, fmax, prominence=0.02):
    """Frequencies of the prominent peaks of the amplitude spectrum below ``fmax``."""
    from scipy.signal import find_peaks

    freqs, amplitude = modal.amplitude_spectrum(acc, dt)
    band = (freqs > 0) & (freqs < fmax)
    curve = np.sqrt(np.mean(amplitude[band] ** 2, axis=1))
    peaks, _ = find_peaks(curve, prominence=prominence * curve.max())
    return freqs[band][peaks]


def flagged(result):
    """The doubtful modes of a result: frequency (Hz) and the reason."""
    modes = result.modes[result.modes["flag"] != ""]
    return [f"{f:.4g} Hz ({why})" for f, why in zip(modes["freq_hz"], modes["flag"])]


def compare(name, modes, reference):
    """Nearest identified mode to each reference frequency."""
    rows = []
    for i, f_ref in enumerate(reference, 1):
        nearest = modes.iloc[int(np.argmin(np.abs(modes["freq_hz"] - f_ref)))] if len(modes) else None
        f = np.nan if nearest is None else nearest["freq_hz"]
        rows.append({
            "record": name, "mode": i, "reference_hz": f_ref, "identified_hz": round(f, 4),
            "rel_dev_pct": round(100 * (f - f_ref) / f_ref, 3),
            "damping_pct": np.nan if nearest is None else round(100 * nearest["damping"], 3),
            "n_poles": np.nan if nearest is None else int(nearest["n_poles"]),
        })
    return pd.DataFrame(rows)


def main() -> int:
    tables, timings = [], {}

    acc = np.load(DATA / "weimar_frame" / "measurement_1" / "measurement_1.npy")[:, :5]
    start = time.perf_counter()
    result, _ = modal.identify_record(acc, 1 / 256, "ambient", max_order=80, fmax=10, refs=[3, 4])
    timings["weimar"] = time.perf_counter() - start
    tables.append(compare("Weimar frame, setup 1", result.trusted_modes, WEIMAR_REFERENCE))
    extra_weimar = len(result.trusted_modes) - len(WEIMAR_REFERENCE)
    doubtful = {"weimar": flagged(result)}

    record = modal.read_record(DATA / "palisaden" / "palisaden_accel_100Hz_float32.npy", fs=100)
    start = time.perf_counter()
    result, _ = modal.identify_record(record.acc, record.dt, "ambient", max_order=60, fmax=5, highpass_hz=0.5)
    timings["palisaden"] = time.perf_counter() - start
    tables.append(compare("Palisaden, 90 min", result.trusted_modes, PALISADEN_REFERENCE))
    palisaden = result.trusted_modes["freq_hz"].round(4).tolist()
    palisaden_second = result.trusted_modes["second_freq_hz"].dropna().round(4).tolist()
    doubtful["palisaden"] = flagged(result)
    palisaden_candidates = result.candidates["freq_hz"].round(4).tolist()

    record = modal.read_record(DATA / "usc_cantilever" / "timeseries_data.lvm")
    start = time.perf_counter()
    result, _ = modal.identify_record(record.acc, record.dt, "free_decay", max_order=60, fmax=150)
    timings["cantilever"] = time.perf_counter() - start
    peaks = spectrum_peaks(record.acc[modal.decay_start(record.acc):], record.dt, 150)
    table = compare("USC cantilever (spectrum peaks)", result.trusted_modes, peaks)
    table["reference_hz"] = table["reference_hz"].round(3)
    tables.append(table)
    extra_cantilever = len(result.trusted_modes) - len(peaks)
    doubtful["cantilever"] = flagged(result)

    frame = pd.concat(tables, ignore_index=True)
    print(frame.to_markdown(index=False))
    print(f"\ntrusted modes selected beyond the references: Weimar {extra_weimar}, cantilever {extra_cantilever}")
    print(f"Palisaden, 90 min: trusted modes {palisaden} (second estimates {palisaden_second}), "
          f"candidates {palisaden_candidates}")
    for name, rows in doubtful.items():
        print(f"doubtful ({name}): {rows or 'none'}")
    print("seconds per record (identification only): " + ", ".join(f"{k} {v:.2f}" for k, v in timings.items()))
    missed = frame[~(frame["rel_dev_pct"].abs() <= 100 * TOLERANCE)]
    if len(missed):
        print(f"\nMISSED (beyond {100 * TOLERANCE} %):\n{missed.to_markdown(index=False)}")
    return int(len(missed) > 0 or extra_cantilever != 0 or len(palisaden) != 4)


if __name__ == "__main__":
    sys.exit(main())
