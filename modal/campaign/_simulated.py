"""A simulated monitoring campaign with known modes: a four-storey shear
frame measured every few hours, its stiffness following the temperature,
each record written as ``modal identify`` reads it; or a two-storey frame
swaying in two directions whose modes cross in frequency as the temperature
drifts (``structure="crossing"``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import scipy.linalg

from .._checks import positive_float, positive_int
from ..records import save_record_npz
from ..structures import ambient_response

#: Storey masses (kg) and stiffnesses (N/m) of the frame, bottom to top:
#: modes 1.587, 4.209, 6.245, 7.843 Hz at the reference temperature.
MASSES = (2000.0, 2000.0, 2000.0, 1500.0)
STIFFNESSES = (1.6e6, 1.5e6, 1.3e6, 1.0e6)
#: Relative change of stiffness per kelvin (steel and concrete frames lose
#: some 0.1-0.5 % of frequency per 10 K) and the reference temperature.
STIFFNESS_PER_KELVIN = -2e-3
REFERENCE_CELSIUS = 10.0


def shear_frame_modes(stiffness_factor=1.0):
    """Natural frequencies (rad/s) and mass-normalised modes (floors x modes)
    of the shear frame with every storey stiffness scaled by the factor."""
    m = np.diag(MASSES)
    k_storey = np.asarray(STIFFNESSES) * stiffness_factor
    n = len(k_storey)
    k = np.zeros((n, n))
    for i, ki in enumerate(k_storey):
        k[i, i] += ki
        if i > 0:
            k[i - 1, i - 1] += ki
            k[i - 1, i] -= ki
            k[i, i - 1] -= ki
    w2, modes = scipy.linalg.eigh(k, m)
    return np.sqrt(w2), modes


#: The crossing frame: two storeys (masses, stiffnesses bottom to top) swaying
#: in x and y alike at the reference temperature (2.512 and 5.703 Hz in both
#: directions); only the x stiffness follows the temperature, strongly
#: (-2 %/K, as a frame braced in x by elastomeric or asphalt-like members),
#: so over a year's -3 to 23 C the x modes sweep -14 % to +12 % through the y
#: modes. Sensors: floors 1, 2 along x, then along y: an x mode and a y mode
#: have MAC 0.
CROSSING_MASSES = (2000.0, 1500.0)
CROSSING_STIFFNESSES = (1.2e6, 0.8e6)
CROSSING_X_PER_KELVIN = -2e-2


def crossing_frame_modes(celsius: float):
    """Natural frequencies (rad/s) and mass-normalised modes (4 sensors x 4
    modes: floors 1, 2 along x then y) of the crossing frame at the
    temperature, in a fixed order: x 1st, y 1st, x 2nd, y 2nd (not sorted
    by frequency: the x modes cross the y modes)."""
    m = np.diag(CROSSING_MASSES)
    k1, k2 = CROSSING_STIFFNESSES
    storeys = np.array([[k1 + k2, -k2], [-k2, k2]])
    w2_x, phi_x = scipy.linalg.eigh(storeys * (1 + CROSSING_X_PER_KELVIN * (celsius - REFERENCE_CELSIUS)), m)
    w2_y, phi_y = scipy.linalg.eigh(storeys, m)
    zeros = np.zeros((2, 2))
    modes = np.block([[phi_x, zeros], [zeros, phi_y]])[:, [0, 2, 1, 3]]
    return np.sqrt(np.concatenate([w2_x, w2_y])[[0, 2, 1, 3]]), modes


def temperature(hours: np.ndarray) -> np.ndarray:
    """A year's cycle (10 +- 10 C, coldest in mid-January) and a day's
    (+- 3 C, warmest at 15:00), in Celsius, ``hours`` since 1 January 00:00."""
    day = hours / 24
    return REFERENCE_CELSIUS - 10 * np.cos(2 * np.pi * (day - 15) / 365) - 3 * np.cos(2 * np.pi * (hours - 15) / 24)


def simulate_campaign(folder, n_records=200, every_hours=6.0, duration=600.0, fs=50.0, damping=(0.012, 0.015, 0.018,
                      0.02), noise=0.02, seed=0, start="2025-01-01 00:00", structure="frame") -> pd.DataFrame:
    """Write a campaign of the shear frame to ``folder``: ``records/`` with
    one ``.npz`` per record (4 floors, acceleration, ``fs`` Hz, ``duration``
    s; white forces at every floor, seed ``seed + record``; Gaussian noise of
    ``noise`` times each channel's RMS), named ``frame_YYYYmmdd_HHMM.npz``,
    every ``every_hours`` from ``start``; ``index.csv`` (``path,time`` and
    the record's ``temperature_c``), ``geometry/`` (the frame's floors as
    nodes ``0`` (ground) to ``4``, 3 m apart, ``nodes.csv``, ``lines.csv``,
    and ``channels.csv``: channel ``k`` along x at floor ``k + 1``) and
    ``campaign.yaml`` (the index, fmax 10 Hz, the geometry).

    ``structure="crossing"`` simulates the two-storey frame swaying in x and
    y (:func:`crossing_frame_modes`; 4 sensors, ``damping`` in its mode
    order) instead: its x modes cross its y modes in frequency (its geometry:
    floors ``1``, ``2`` measured along x by channels 0, 1 and along y by 2,
    3).

    Returns the truth: ``record, time, temperature_c, mode, freq_hz,
    damping`` and the mode's shape at the sensors, ``phi_0``, ``phi_1``, ....
    """
    if structure not in ("frame", "crossing"):
        raise ValueError(f"structure must be 'frame' or 'crossing', not {structure!r}")
    n_records = positive_int("n_records", n_records)
    duration, fs = positive_float("duration", duration), positive_float("fs", fs)
    folder = Path(folder)
    (folder / "records").mkdir(parents=True, exist_ok=True)
    times = pd.Timestamp(start) + pd.to_timedelta(np.arange(n_records) * every_hours, unit="h")
    hours = (times - pd.Timestamp(times[0].year, 1, 1)).total_seconds().to_numpy() / 3600
    celsius = temperature(hours)
    rng = np.random.default_rng(seed)
    truth, index = [], []
    for r, (time, c) in enumerate(zip(times, celsius)):
        if structure == "frame":
            omega, modes = shear_frame_modes(1 + STIFFNESS_PER_KELVIN * (c - REFERENCE_CELSIUS))
        else:
            omega, modes = crossing_frame_modes(c)
        acc = ambient_response(omega, damping, modes, modes, int(round(duration * fs)), 1 / fs, seed=seed + 1 + r,
                               force_rms=100.0)
        acc += noise * acc.std(axis=0) * rng.standard_normal(acc.shape)
        name = f"records/frame_{time:%Y%m%d_%H%M}.npz"
        save_record_npz(folder / name, acc.astype(np.float32), 1 / fs)
        index.append({"path": name, "time": time.isoformat(), "temperature_c": round(float(c), 2)})
        truth += [{"record": name, "time": time, "temperature_c": c, "mode": k + 1, "freq_hz": w / (2 * np.pi),
                   "damping": z, **{f"phi_{s}": v for s, v in enumerate(modes[:, k])}}
                  for k, (w, z) in enumerate(zip(omega, damping))]
    pd.DataFrame(index).to_csv(folder / "index.csv", index=False)
    _write_geometry(folder / "geometry", len(MASSES) if structure == "frame" else len(CROSSING_MASSES),
                    both_directions=structure == "crossing")
    (folder / "campaign.yaml").write_text(
        "records:\n  index: index.csv\nidentify:\n  excitation: ambient\n  fmax: 10\n  max_order: 40\nchunk: 25\n"
        "geometry:\n  folder: geometry\n  channels: geometry/channels.csv\n")
    return pd.DataFrame(truth)


#: Storey height of the simulated frames' geometry (m).
STOREY_HEIGHT = 3.0


def _write_geometry(folder: Path, floors: int, both_directions: bool) -> None:
    """A simulated frame's geometry (the project's format): nodes ``0``
    (ground) to ``floors`` up the z axis, lines between consecutive floors,
    and the channel table: one channel per floor along x (and then one per
    floor along y when ``both_directions``), in the order of the records'
    columns."""
    folder.mkdir(parents=True, exist_ok=True)
    pd.DataFrame({"node": range(floors + 1), "x": 0.0, "y": 0.0,
                  "z": STOREY_HEIGHT * np.arange(floors + 1)}).to_csv(folder / "nodes.csv", index=False)
    pd.DataFrame({"node_1": range(floors), "node_2": range(1, floors + 1)}).to_csv(folder / "lines.csv", index=False)
    directions = [(1.0, 0.0, 0.0)] + ([(0.0, 1.0, 0.0)] if both_directions else [])
    rows = [{"channel": len(directions[:d]) * floors + f, "name": f"floor{f + 1}_{'xy'[d]}", "node": f + 1,
             "x": e[0], "y": e[1], "z": e[2], "quantity": "acceleration", "unit": "m/s2", "role": "roving"}
            for d, e in enumerate(directions) for f in range(floors)]
    pd.DataFrame(rows).to_csv(folder / "channels.csv", index=False)
