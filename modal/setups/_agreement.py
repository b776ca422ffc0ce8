"""Do the setups of a roving test agree? Each setup is compared with every
other before any is merged, by what must be the same in all of them: the
reference channels' levels (the same sensors at the same place, under the
same kind of excitation), the reference part of each mode (its complex
shape at the reference channels, up to one complex scale), and the
frequencies (a wrong sampling rate shows as one constant ratio). A setup
that disagrees with more than half of the others is named, with the
evidence, and kept out of the merge (:func:`modal.setups.merge_setups`).

With two setups a disagreement cannot say which one is wrong: both are
named, and nothing is merged.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..identification import mac
from ._channels import dof_keys, unit_factor

#: Matching by frequency: two modes are the same when their frequencies
#: differ by at most MATCH_Z combined relative standard deviations (each
#: mode's ``freq_std_hz``, the scatter of a cluster's members), kept within
#: RTOL_MIN ... RTOL_MAX; RTOL_UNKNOWN stands for a mode without an estimate.
MATCH_Z = 3.0
RTOL_MIN, RTOL_MAX = 0.002, 0.03
RTOL_UNKNOWN = 0.005

#: A setup's frequencies are a constant ratio of another's (a wrong rate)
#: when at least RATE_MIN_MODES modes line up at a ratio off 1 by more than
#: RATE_RTOL (within RATE_MATCH each), and more than twice as many as at 1.
RATE_RTOL, RATE_MATCH, RATE_MIN_MODES = 0.03, 0.01, 3

#: Reference levels (standard deviation of each reference channel, SI):
#: the ratio between a setup's reference channels may differ from another
#: setup's by at most LEVEL_RATIO_MAX (the excitation's direction varies,
#: a unit slip of g is 9.8), and the overall level by LEVEL_MAX (the
#: excitation's strength varies; a slip of mm/s2 is 1000).
LEVEL_RATIO_MAX, LEVEL_MAX = 3.0, 30.0

#: A setup's reference part of a mode agrees with another's when the
#: relative residual of the complex scale fit of one onto the other,
#: sqrt(1 - MAC), is at most REF_RESIDUAL_MAX (MAC >= 0.96). Good setups
#: of the simulated plate and of the Weimar frame stay below 0.11; two
#: swapped references of the plate give 0.45 in its first mode.
REF_RESIDUAL_MAX = 0.2
REF_MAC_AGREE = 1 - REF_RESIDUAL_MAX**2

DISAGREEMENT_COLUMNS = ["setup", "check", "evidence"]


def relative_uncertainty(modes: pd.DataFrame) -> np.ndarray:
    """Each mode's relative frequency uncertainty: ``freq_std_hz`` (the
    estimate's standard deviation) over ``freq_hz``, else RTOL_UNKNOWN."""
    freq = modes["freq_hz"].to_numpy(dtype=float)
    std = modes["freq_std_hz"].to_numpy(dtype=float) if "freq_std_hz" in modes else np.full(len(freq), np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        u = std / freq
    return np.where(np.isfinite(u) & (u > 0), u, RTOL_UNKNOWN)


def tolerance(u_a, u_b) -> float:
    """Relative frequency tolerance of a match between two modes (or a mode
    and a cluster) of relative uncertainties ``u_a``, ``u_b``."""
    return float(np.clip(MATCH_Z * np.hypot(u_a, u_b), RTOL_MIN, RTOL_MAX))


def reference_levels(setup, keys) -> np.ndarray:
    """Standard deviation (SI) of the setup's reference channels, in the
    order of ``keys``."""
    table = setup.channels
    rows = [dof_keys(table).index(k) for k in keys]
    factors = np.array([unit_factor(table["quantity"].iloc[r], table["unit"].iloc[r]) for r in rows])
    columns = table["channel"].to_numpy()[rows]
    return setup.record.acc[:, columns].std(axis=0) * np.abs(factors)


def rate_ratio(freq_a, freq_b) -> tuple[float, int, int]:
    """The constant ratio that lines up most of ``freq_a`` with ``freq_b``:
    ``(ratio, modes lined up at it, modes lined up at 1)`` (within
    RATE_MATCH each; ties go to the ratio nearest 1)."""
    freq_a, freq_b = np.asarray(freq_a, dtype=float), np.asarray(freq_b, dtype=float)
    if not freq_a.size or not freq_b.size:
        return 1.0, 0, 0
    log_b = np.log(freq_b)

    def lined_up(log_ratio):
        gaps = np.abs(np.log(freq_a)[:, None] - log_ratio - log_b[None, :]).min(axis=1)
        return int(np.sum(gaps <= RATE_MATCH))

    candidates = np.log(freq_a)[:, None] - log_b[None, :]
    candidates = candidates[np.abs(candidates) <= np.log(5.0)].ravel()
    best = max([0.0, *candidates], key=lambda r: (lined_up(r), -abs(r)))
    return float(np.exp(best)), lined_up(best), lined_up(0.0)


def _paired_ref_macs(result_a, rows_a, result_b, rows_b) -> np.ndarray:
    """MAC of the reference parts of the modes of two setups paired by
    frequency (each mode of ``a`` with the nearest of ``b`` within
    :func:`tolerance`)."""
    fa, fb = result_a.modes["freq_hz"].to_numpy(float), result_b.modes["freq_hz"].to_numpy(float)
    if not fa.size or not fb.size:
        return np.empty(0)
    ua, ub = relative_uncertainty(result_a.modes), relative_uncertainty(result_b.modes)
    macs = []
    for i, f in enumerate(fa):
        j = int(np.argmin(np.abs(fb - f)))
        if abs(fb[j] - f) <= tolerance(ua[i], ub[j]) * f:
            ra, rb = result_a.complex_shapes[rows_a, i], result_b.complex_shapes[rows_b, j]
            macs.append(mac(ra[:, None], rb[:, None])[0, 0])
    return np.array(macs)


def setup_disagreements(setups, results, keys, ref_rows) -> pd.DataFrame:
    """The setups that disagree with more than half of the others, one row
    per setup and check: ``setup``, ``check`` (``rate``, ``reference
    levels``, ``reference ratio``, ``reference shapes``), ``evidence``.

    Parameters
    ----------
    setups, results : sequences
        The setups and their identifications (:func:`identify_setup`).
    keys : list of tuple
        The reference DOFs (:func:`check_setups`).
    ref_rows : list of list of int
        Each setup's rows of its shapes at ``keys``.
    """
    n = len(setups)
    if n < 2 or not keys:
        return pd.DataFrame(columns=DISAGREEMENT_COLUMNS)
    log_levels = np.log([reference_levels(s, keys) for s in setups])
    freqs = [r.modes["freq_hz"].to_numpy(float) for r in results]
    verdicts = {check: np.zeros((n, n), dtype=bool) for check in
                ("rate", "reference levels", "reference ratio", "reference shapes")}
    found = {check: np.full((n, n), np.nan) for check in verdicts}
    for a in range(n):
        for b in range(n):
            if a == b:
                continue
            ratio, lined, at_one = rate_ratio(freqs[a], freqs[b])
            found["rate"][a, b] = ratio
            verdicts["rate"][a, b] = (abs(np.log(ratio)) > RATE_RTOL and lined >= RATE_MIN_MODES
                                      and lined > 2 * at_one)
            difference = log_levels[a] - log_levels[b]
            overall = np.median(difference)
            found["reference levels"][a, b] = np.exp(overall)
            verdicts["reference levels"][a, b] = abs(overall) > np.log(LEVEL_MAX)
            if len(keys) > 1:  # the largest ratio between two reference channels' level ratios
                spread = np.ptp(difference)
                found["reference ratio"][a, b] = np.exp(spread)
                verdicts["reference ratio"][a, b] = spread > np.log(LEVEL_RATIO_MAX)
            macs = _paired_ref_macs(results[a], ref_rows[a], results[b], ref_rows[b])
            if macs.size:
                found["reference shapes"][a, b] = np.median(macs)
            verdicts["reference shapes"][a, b] = macs.size >= 2 and np.sum(macs < REF_MAC_AGREE) > macs.size / 2
    rows = []
    for a, setup in enumerate(setups):
        others = [b for b in range(n) if b != a]
        for check, verdict in verdicts.items():
            against = [b for b in others if verdict[a, b]]
            if len(against) <= len(others) / 2:
                continue
            values = found[check][a, against]
            names = ", ".join(setups[b].name for b in against)
            rows.append({"setup": setup.name, "check": check,
                         "evidence": _evidence(check, values, len(against), len(others), names, setup, keys,
                                               log_levels[a], log_levels[against])})
    return pd.DataFrame(rows, columns=DISAGREEMENT_COLUMNS)


def _evidence(check, values, count, others, names, setup, keys, own_levels, their_levels) -> str:
    those = f"{count} of {others} other setup(s) ({names}" + \
        ("; with two setups, which one is wrong cannot be told)" if others == 1 else ")")
    if check == "rate":
        return (f"its frequencies are {np.median(values):.4g} x those of {those}: a wrong sampling rate "
                "(setup_info.txt, --fs, the record's time column)?")
    if check == "reference levels":
        return (f"its reference channels record {np.median(values):.3g} x the level of {those}: a unit slip "
                "(a unit or quantity declared wrongly in its channel table)?")
    if check == "reference ratio":
        own = own_levels - own_levels[0]
        theirs = np.median(their_levels - their_levels[:, :1], axis=0)
        nodes = [f"node {k[0]} ({k[1]:g}, {k[2]:g}, {k[3]:g})" for k in keys]
        listed = ", ".join(f"{nodes[j]}: {np.exp(own[j]):.3g} (others {np.exp(theirs[j]):.3g})"
                           for j in range(1, len(keys)))
        return (f"the levels of its reference channels relative to {nodes[0]} ({listed}) differ from those of "
                f"{those} by up to {np.max(values):.3g} x: a unit slip or swapped reference channels?")
    return (f"the reference part of its modes disagrees with that of {those} (median MAC {np.nanmedian(values):.2f} "
            "over the modes paired by frequency): swapped, misplaced or dead reference channels?")
