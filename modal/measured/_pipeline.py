"""The measured-record pipeline behind ``modal identify``: preprocessing,
NExT correlations or the free decay, the stabilisation diagram, and the
results of a record written to a folder."""

from __future__ import annotations

import math
from collections.abc import Callable

from .._checks import positive_float, positive_int
from ..identification import Stabilisation, StabilityCriteria, stabilisation


EXCITATIONS = ("ambient", "free_decay")


def identify_record(
    acc,
    dt,
    excitation,
    max_order=60,
    fmax=None,
    rows=None,
    refs=None,
    highpass_hz=None,
    criteria: StabilityCriteria | None = None,
    log: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Stabilisation, float]:
    """Modes of a measured record, as ``modal identify`` finds them.

    Steps: remove a linear trend (:func:`detrend`); with ``fmax``, decimate
    (:func:`decimate`) by ``q = floor(fs / (2.5 fmax))`` so that the
    anti-aliasing filter passes ``fmax``; optionally high-pass
    (:func:`zero_phase_filter`). Then

    - ``"ambient"``: NExT correlation functions (:func:`modal.correlations`,
      biased) with ``2 rows + 1`` lags, one data set per reference, are the
      ERA data;
    - ``"free_decay"``: the record from its impact on
      (:func:`modal.decay_start`) is.

    :func:`stabilisation` with ``rows`` block rows and as many columns as the
    data allow (free decay: at most ``10 rows``, the decay is then long gone
    into noise for lightly damped structures sampled at ``2.5 fmax``).

    Parameters
    ----------
    acc : array_like, shape (n_samples, n_channels)
    dt : float
        Sampling interval (s).
    excitation : {"ambient", "free_decay"}
    max_order : int
        Largest model order (even).
    fmax : float, optional
        Highest frequency of interest (Hz).
    rows : int, optional
        Block rows; default ``max(60, ceil(2 max_order / n_channels))`` so
        ``H(0)`` has at least twice ``max_order`` rows.
    refs : sequence of int, optional
        Reference channels of the correlations (ambient); default all.
    highpass_hz : float, optional
    criteria : StabilityCriteria, optional
    log : callable, optional
        Receives one line per step (for progress messages).
    progress : callable, optional
        Passed to :func:`stabilisation`.

    Returns
    -------
    result : Stabilisation
    dt : float
        The sampling interval after decimation.
    """
    from ..signals import correlations
    from ..signals import decay_start, decimate, detrend, zero_phase_filter

    log = log or (lambda message: None)
    if excitation not in EXCITATIONS:
        raise ValueError(f"excitation must be one of {EXCITATIONS}, got {excitation!r}")
    y = detrend(acc)
    dt = positive_float("dt", dt)
    max_order = positive_int("max_order", max_order, minimum=2)
    n_channels = y.shape[1]
    rows = max(60, math.ceil(2 * max_order / n_channels)) if rows is None else positive_int("rows", rows)
    if fmax is not None:
        fmax = positive_float("fmax", fmax)
        if fmax >= 0.5 / dt:
            raise ValueError(f"fmax = {fmax} Hz must be below the Nyquist frequency {0.5 / dt:g} Hz")
        factor = int(1 / (dt * 2.5 * fmax))
        if factor >= 2:
            log(f"decimating by {factor}: {1 / dt:g} Hz -> {1 / (dt * factor):g} Hz")
            y, dt = decimate(y, dt, factor)
    if highpass_hz is not None:
        log(f"high-pass at {highpass_hz:g} Hz")
        y = zero_phase_filter(y, dt, highpass_hz=highpass_hz)
    if excitation == "ambient":
        n_lags = 2 * rows + 1
        if n_lags > y.shape[0] // 2:
            raise ValueError(f"rows = {rows} needs {n_lags} lags, more than half the {y.shape[0]}-sample record: "
                             "reduce rows or give a longer record")
        log(f"correlations: {n_lags} lags, references {list(range(n_channels)) if refs is None else list(refs)}")
        data, start, cols = correlations(y, n_lags, refs=refs), 0, None
    else:
        start = decay_start(y)
        log(f"free decay from sample {start} (t = {start * dt:.4g} s)")
        data = y
        cols = min(y.shape[0] - start - rows, 10 * rows)
        if cols < 1:
            raise ValueError(f"rows = {rows}: the decay after sample {start} is too short; reduce rows")
    log(f"stabilisation: orders 2 ... {max_order}, {rows} block rows")
    result = stabilisation(data, dt, max_order, rows, cols=cols, start=start, fmax=fmax, criteria=criteria,
                           progress=progress)
    return result, dt


def write_identification(record, out, excitation, channels=None, refs=None, max_order=60, fmax=None, rows=None,
                         highpass_hz=None, title=None, log=None, progress=None) -> tuple[Stabilisation, float]:
    """Identify a record's modes and write them to the folder ``out``.

    What ``modal identify`` and the workflow's measured records both do:
    :func:`identify_record` on the chosen channels, then

    - ``out/modes.csv``: one row per selected mode (``mode``, ``freq_hz``,
      ``freq_std_hz``, ``damping`` as a ratio, ``damping_std``, ``n_poles``,
      ``mpc``, ``mamc``) and its shape, one column ``phi_<channel>`` per
      channel (the record's channel numbers);
    - ``out/poles.csv``: every pole of the diagram;
    - ``out/stabilisation.png``: the diagram (:func:`stabilisation_figure`).

    Parameters
    ----------
    record : MeasuredRecord
        As :func:`modal.read_record` returns it.
    out : str or Path
        Output folder (created).
    excitation : {"ambient", "free_decay"}
    channels : sequence of int, optional
        The record's channels to use (0-based); default all.
    refs : sequence of int, optional
        Reference channels for the correlations, in the record's channel
        numbering, among ``channels``; default all.
    max_order, fmax, rows, highpass_hz, log, progress
        As :func:`identify_record`; ``max_order`` must be even.
    title : str, optional
        Title of the diagram.

    Returns
    -------
    result : Stabilisation
    dt : float
        The sampling interval after decimation.
    """
    from pathlib import Path

    n_channels = record.acc.shape[1]
    channels = list(range(n_channels)) if channels is None else [int(c) for c in channels]
    if not channels or min(channels) < 0 or max(channels) >= n_channels:
        raise ValueError(f"channels {channels}: the record has channels 0 ... {n_channels - 1}")
    if refs is not None:
        missing = [r for r in refs if r not in channels]
        if missing:
            raise ValueError(f"refs {missing} are not among the channels used {channels}")
        refs = [channels.index(r) for r in refs]
    if max_order % 2:
        raise ValueError(f"max_order must be even, got {max_order}")
    result, dt = identify_record(record.acc[:, channels], record.dt, excitation, max_order=max_order, fmax=fmax,
                                 rows=rows, refs=refs, highpass_hz=highpass_hz, log=log, progress=progress)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    modes = result.modes.copy()
    for c, channel in enumerate(channels):
        modes[f"phi_{channel}"] = result.shapes[c] if len(modes) else []
    modes.to_csv(out / "modes.csv", index=False, float_format="%.6g")
    result.poles.to_csv(out / "poles.csv", index=False, float_format="%.6g")
    from ._figures import stabilisation_figure

    figure = stabilisation_figure(result, fmax=fmax or 0.5 / dt, title=title)
    figure.savefig(out / "stabilisation.png", dpi=120)
    return result, dt
