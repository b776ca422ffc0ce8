"""The measured-record pipeline behind ``modal identify``: preprocessing,
NExT correlations or the free decay, the stabilisation diagram, and the
results of a record written to a folder."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np
import pandas as pd

from .._checks import positive_float, unit_scale
from ..identification import (BLEND, PEAK_HEIGHT_DB, ModalWarning, Stabilisation, StabilityCriteria,
                              height_above_median_db, stabilisation)
from ..records import SPIKE_MAX_WIDTH, clipping_warnings, despiked, spike_samples, spike_warnings
from ._options import IdentifyOptions, identify_options, least_rows

#: Without ``fmax`` and ``rows``, the block rows span this many periods of the
#: record's lowest spectral peak (a common guideline for SSI-cov asks at least
#: half a period of the lowest mode, ``i >= fs / (2 f_0)``: Rainieri and
#: Fabbrocino 2014), and
#: no fewer than ``2 max_order / channels`` (the Hankel matrix must hold the
#: highest order). Longer lags add the correlations' random error where a mode
#: has decayed: on 2-minute simulated records three periods (at least 60 rows)
#: found 35 of 60 modes damped 6-10 % and 23 of 60 in pairs 0.8 % apart, one
#: period 46 and 32, the other kinds as many (docs/benchmarks.md) ...
AUTO_PERIODS = 1
#: ... for ambient records; a free decay's keep three periods, and at least 60
#: rows (the rule the benchmark above did not try on decays).
DECAY_PERIODS = 3
#: ... and the record is decimated to about this many samples per period of
#: that peak (at most), so the band kept reaches some ``AUTO_SAMPLES / 2.5``
#: = 27 times it ...
AUTO_SAMPLES = 200 / 3
#: ... and never so far that the highest prominent peak, times this, leaves
#: the anti-aliasing filter's pass band: a beam's modes lie at ``n^2`` times
#: its first (its sixth at 36 times), a tall building's span 20 times and
#: more; a mode at the highest peak keeps its half-power band (``1 + zeta``)
#: and room for a weaker one above it in the band ...
AUTO_BAND = 1.25
#: ... unless that leaves more than this many samples per period of the lowest
#: peak: the rows span that period, and a Hankel matrix of 512 block rows per
#: channel is already some seconds' work; a band wider than about
#: ``AUTO_MAX_SAMPLES / (2.5 AUTO_BAND)`` = 164 times the lowest peak takes
#: ``fmax`` (the log says so).
AUTO_MAX_SAMPLES = 512
#: Ambient records are also cut into this many non-overlapping segments,
#: whose correlations give the standard deviation of each frequency and
#: damping (:func:`modal.identification.segment_std`): fewer when a segment
#: would be shorter than :data:`SEGMENT_LAGS` times the lags, but at least
#: :data:`MIN_SEGMENTS` (then shorter, down to twice the lags; none below).
SEGMENTS = 10
MIN_SEGMENTS = 4
#: A segment's correlation at lag ``tau`` averages ``length - tau`` products
#: (with the biased estimator then used, also tapered by ``1 - tau / length``):
#: segments of only 2.5 times the lags (ten of a 2-minute record) scatter in
#: another regime than the record, and their spread made the damping std of
#: the higher modes 1.3-1.9 times too small (bench_uncertainty.py); at six
#: times the lags every lag averages at least 5/6 of the segment.
SEGMENT_LAGS = 6
#: The correlations' estimator (:func:`modal.correlations`): ``biased`` divides
#: lag ``k`` by ``N`` instead of ``N - k``, a taper ``1 - k / N ~ exp(-k / N)``
#: that adds ``1 / (omega N dt)`` to every damping ratio: 0.054 points to the
#: Weimar frame's first mode (1.23 Hz, 240 s; identified 0.345 %, published
#: 0.23-0.25 %; unbiased 0.273 %), 7 % of the first mode's damping in a
#: 2-minute record of the benchmark frame. Over lags far fewer than ``N``
#: the unbiased estimator costs no variance worth the name (``N / (N - k)``).
CORRELATION_ESTIMATOR = "unbiased"


#: The lowest spectral peak lies above this many Welch bins: the Hann window's main lobe around 0 Hz (two
#: bins), where drift and trends lie, and one more. Five (before 2026-11-29) put the floor at 40-80 periods
#: per record (segments of an eighth of it, rounded down to a power of two): the 0.45 Hz fundamental pair of
#: a 2-minute record at 50 Hz (bins of 0.098 Hz) was passed over, the block rows spanned the 1.4 Hz mode's
#: period and the pair was found in 4 of 12 records (exploratory run); with three, in 12 and 11 of 12.
LOWEST_PEAK_BINS = 3


def prominent_peaks_hz(y, dt, prominence_db=6.0) -> np.ndarray:
    """The prominent peaks of a record's spectrum (Hz), ascending: the
    first of :func:`spectral_peaks`."""
    return spectral_peaks(y, dt, prominence_db)[0]


def spectral_peaks(y, dt, prominence_db=6.0) -> tuple[np.ndarray, np.ndarray]:
    """The prominent peaks of a record's spectrum (Hz), ascending, and how far
    each stands above the median level around it (dB,
    :func:`modal.identification.height_above_median_db`, the spectral
    witness's measure).

    Welch's averaged spectrum (scipy.signal.welch, segments of the largest
    power of two up to an eighth of the record), each channel normalised
    to its maximum, averaged over channels, in dB; its peaks
    (scipy.signal.find_peaks) at least ``prominence_db`` above their
    surroundings, above :data:`LOWEST_PEAK_BINS` frequency bins and ten
    periods per record (the record cannot resolve lower: drift and trends
    lie there). Empty for a record of fewer than 64 samples.

    Over a wide band of noise (a record sampled far above its modes) the
    estimate's random error alone leaves maxima 6 dB above their troughs:
    on an hour at 1 kHz of a structure with modes below 10 Hz, 22 of them
    between 160 and 500 Hz, each 2.6-4.6 dB above the median around it,
    where a mode's stands 6-26 dB above it (the Weimar frame's, Palisaden's,
    a simply supported beam's eight).
    """
    from scipy.signal import find_peaks, welch

    n = y.shape[0]
    if n < 64:
        return np.empty(0), np.empty(0)
    nperseg = 2 ** int(np.log2(n / 8)) if n >= 256 else n
    level = 0.0
    for c in range(y.shape[1]):  # channel by channel: welch's segments of one channel at a time in memory
        freqs, power = welch(y[:, c], fs=1 / dt, nperseg=nperseg)
        level = level + power / (power.max() if power.max() > 0 else 1) / y.shape[1]
    db = 10 * np.log10(level + 1e-300)
    peaks, _ = find_peaks(db, prominence=prominence_db)
    floor = max(LOWEST_PEAK_BINS * freqs[1], 10 / (n * dt))
    peaks = peaks[freqs[peaks] > floor]
    heights = np.array([height_above_median_db(db, index, freqs[index], freqs[1]) for index in peaks])
    return freqs[peaks], heights


def lowest_peak_hz(y, dt, prominence_db=6.0) -> float | None:
    """The lowest of :func:`prominent_peaks_hz` (Hz), or None without one."""
    peaks = prominent_peaks_hz(y, dt, prominence_db)
    return float(peaks[0]) if len(peaks) else None


def auto_decimation(dt, peaks_hz) -> int:
    """The decimation factor, without ``fmax``, of a record sampled every
    ``dt`` s whose spectrum peaks at ``peaks_hz`` (:func:`prominent_peaks_hz`,
    ascending): down to about :data:`AUTO_SAMPLES` samples per period of
    the lowest peak, but no further than keeps :data:`AUTO_BAND` times the
    highest inside the anti-aliasing filter's pass band (as ``fmax`` would:
    :meth:`IdentifyOptions.decimation`), and at least down to
    :data:`AUTO_MAX_SAMPLES` per period of the lowest. 1: none (also
    without a peak)."""
    if not len(peaks_hz):
        return 1
    low, high = peaks_hz[0], peaks_hz[-1]
    by_lowest = int(1 / (dt * AUTO_SAMPLES * low))
    by_highest = max(int(1 / (dt * 2.5 * AUTO_BAND * high)), int(1 / (dt * AUTO_MAX_SAMPLES * low)))
    return max(1, min(by_lowest, by_highest))

#: A channel whose linear trend leaves less than this fraction of its peak
#: magnitude (rms of the remainder against the largest raw value) holds no
#: vibration: what is left is round-off, not response. 1e-10 is 200 dB, far
#: beyond any data acquisition (a 24-bit converter spans 144 dB) and far above
#: double precision's 1e-16 (an exact ramp or a constant leaves ~1e-16).
NO_VIBRATION_RTOL = 1e-10
#: Round-off of the detrended record against its peak: a few hundred units
#: of double precision (an exact ramp of 2e6 samples leaves 640 eps).
ROUND_OFF = 1e3 * np.finfo(float).eps


def no_vibration(raw, detrended) -> np.ndarray:
    """Indices of the channels of ``raw`` (n_samples, n_channels) whose
    ``detrended`` content is at round-off level (:data:`NO_VIBRATION_RTOL`):
    constants, exact drifts (linear ramps), dead sensors."""
    # channel by channel: no temporary of the record's size, and a reduction along one column is some ten
    # times faster than numpy's along axis 0 of a C-ordered record with a few channels (the same values)
    peak = np.array([max(raw[:, c].max(), -raw[:, c].min()) for c in range(raw.shape[1])], dtype=float)
    rms = np.sqrt(np.einsum("ij,ij->j", detrended, detrended) / len(detrended))
    return np.flatnonzero(rms <= NO_VIBRATION_RTOL * peak)


def _refuse_no_vibration(raw, detrended, labels) -> None:
    dead = no_vibration(raw, detrended)
    if dead.size:
        rms = np.sqrt(np.mean(np.square(detrended[:, dead]), axis=0))
        peak = np.max(np.abs(raw[:, dead]), axis=0)
        offset = np.abs(np.mean(raw[:, dead], axis=0))
        which = ", ".join(str(labels[c]) for c in dead)
        everything = dead.size == raw.shape[1]
        channels = f"channel {which}" if dead.size == 1 else f"channels {which}"
        if np.all(rms > ROUND_OFF * peak) and np.all(offset > 0.5 * peak):
            # something varies, more than round-off, on an offset so large that it lies in the last digits
            subject = f"{channels}: vibration lost in an offset"
            why = (f"what varies (rms {rms.max():.2g}) is less than {NO_VIBRATION_RTOL:g} of the offset it rides "
                   f"on (mean {offset.min():.3g}), the round-off of most acquisitions' numbers: subtract the offset "
                   "before the record is written")
        else:
            subject = (("no channel holds vibration" + (f" ({channels})" if dead.size > 1 else ""))
                       if everything else f"{channels} {'holds' if dead.size == 1 else 'hold'} no vibration")
            why = (f"after removing the linear trend what remains (rms {rms.max():.2g}) is round-off against the "
                   f"values (peak {peak.min():.3g}), as for a constant, an exact drift (linear ramp) or a dead sensor")
        raise ValueError(f"{subject}: {why}" + ("" if everything else "; leave it out of the channels used (--channels)"))


#: Channels of one quantity whose RMS levels differ by this factor or more draw a warning (:func:`level_warning`).
LEVEL_RATIO = 100.0


#: ... and a channel weaker than this fraction of its quantity's strongest is scaled up (by a power of two) to
#: about that fraction for the identification, its shape entries scaled back after it.
LEVEL_FLOOR = 0.1


def level_scales(y, quantities=None) -> np.ndarray:
    """Per channel, the power of two that brings a channel weaker than
    :data:`LEVEL_FLOOR` of the strongest channel of its quantity to about
    that fraction (1 for the others): the correlations and their
    decomposition weigh each channel by its level, so a channel in other
    units (1000-fold weaker) would otherwise count for nothing: with one of
    four channels 1000 times larger, two pairs of modes 0.8 % apart lost three
    of their four modes, and on 180 simulated records with channel gains of
    ``10^U(-3, 3)`` 632 of 741 modes were found against 676 scaled (694
    without gains; records whose channels lie within ten-fold are
    unchanged)."""
    rms, groups = _levels(y, quantities)
    scales = np.ones(len(rms))
    for group in groups.values():
        floor = LEVEL_FLOOR * rms[group].max()
        weak = group[(rms[group] < floor) & (rms[group] > 0)]
        scales[weak] = np.exp2(np.round(np.log2(floor / rms[weak])))
    return scales


def _levels(y, quantities) -> tuple[np.ndarray, dict]:
    """Each channel's RMS, and the channels of each quantity (``"the same
    quantity"`` for all when ``quantities`` is None), in order of first use."""
    rms = np.sqrt(np.einsum("tc,tc->c", y, y) / len(y))
    kinds = ["the same quantity"] * len(rms) if quantities is None else list(quantities)
    return rms, {kind: np.array([c for c, q in enumerate(kinds) if q == kind]) for kind in dict.fromkeys(kinds)}


def _in_record_units(result: Stabilisation, scales) -> Stabilisation:
    """``result`` of a record whose channels were multiplied by ``scales``
    (:func:`level_scales`) with its shapes back in the record's units: each
    entry divided by its channel's scale, renormalised as before. The MAC,
    MPC and the witness's columns stay those of the scaled channels (each
    channel weighed alike, as they were judged)."""
    import dataclasses

    from ..identification import normalise_complex_shapes, normalise_shapes

    complex_shapes = normalise_complex_shapes(result.complex_shapes / scales[:, None])
    pole_shapes = normalise_complex_shapes((result.pole_shapes / scales[None, :]).T).T
    return dataclasses.replace(result, complex_shapes=complex_shapes, shapes=normalise_shapes(complex_shapes),
                               pole_shapes=pole_shapes)


def level_warning(y, labels, quantities=None) -> str | None:
    """A warning when channels measuring the same quantity differ in level
    by :data:`LEVEL_RATIO` or more, else None: the correlations and their
    decomposition weigh each channel by its level, so a channel recorded in
    other units (mm/s² among m/s²: 1000-fold) outweighs the others
    (:func:`level_scales` narrows the gap for the identification). ``y``: the
    record, detrended; ``quantities``: what each channel measures (default:
    all the same)."""
    rms, groups = _levels(y, quantities)
    worst = None
    for kind, group in groups.items():
        high, low = group[np.argmax(rms[group])], group[np.argmin(rms[group])]
        ratio = rms[high] / rms[low] if rms[low] > 0 else np.inf
        if ratio >= LEVEL_RATIO and (worst is None or ratio > worst[0]):
            worst = (ratio, high, low, kind)
    if worst is None:
        return None
    ratio, high, low, kind = worst
    return (f"channels {labels[high]} (rms {rms[high]:.3g}) and {labels[low]} (rms {rms[low]:.3g}), both {kind}, "
            f"differ {ratio:.0f}-fold in level: a channel in other units (mm/s² among m/s²)? The identification "
            "weighs each channel by its level; the weaker ones were scaled up to about a tenth of the strongest "
            "for it (the shapes are in the record's units), but close modes are resolved best with every "
            "channel in one unit (a sensor near a support is weak for a reason)")


def quadrature_warning(result: Stabilisation, labels) -> str | None:
    """A warning when the channels fall in two groups a quarter period apart
    in every well-identified mode (:func:`modal.identification.quadrature_groups`
    of the complex shapes, as identified in one quantity, of the modes of
    MAMC at least ``criteria.doubtful_mamc``), else None: one group measures
    another derivative of the motion than the identification took it for (a
    laser vibrometer's velocity beside accelerometers, all taken as one
    quantity), so the shapes read as complex and their modes are flagged
    ``low MPC`` although they are normal."""
    from ..identification import quadrature_groups

    modes = result.modes
    well_identified = modes["mamc"].to_numpy(dtype=float) >= result.criteria.doubtful_mamc
    found = quadrature_groups(_identified_shapes(result)[:, well_identified])
    if found is None:
        return None
    first, second, degrees, n_modes = found
    low = modes["mpc"].to_numpy(dtype=float)
    low = low[low < result.criteria.doubtful_mpc]
    consequence = (f"{len(low)} mode(s) read as complex and are flagged low MPC ({low.min():.2f}-{low.max():.2f})"
                   if len(low) else "the shapes read as complex")
    return (f"channels {', '.join(str(labels[c]) for c in first)} and channels "
            f"{', '.join(str(labels[c]) for c in second)} are a quarter period apart in every mode both show "
            f"({degrees:.1f} degrees, median over up to {n_modes} modes): one group measures another derivative of "
            f"the motion than the identification took it for (velocity beside acceleration, or displacement beside "
            f"velocity), so {consequence}; give each channel's quantity (quantities, --quantities, or a channel "
            "table's quantity column)")


def _identified_shapes(result: Stabilisation) -> np.ndarray:
    """The shapes as identified: complex where the result holds them, else
    the real ones."""
    return result.complex_shapes if result.complex_shapes.shape == result.shapes.shape else result.shapes


def available_memory() -> int:
    """Bytes of memory this process can still take: ``MemAvailable`` of
    ``/proc/meminfo`` (else the physical memory), and no more than what a
    cgroup (v2) memory limit leaves."""
    import os

    try:
        with open("/proc/meminfo") as fh:
            available = next(int(line.split()[1]) * 1024 for line in fh if line.startswith("MemAvailable:"))
    except (OSError, StopIteration, ValueError, IndexError):
        try:
            available = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            return 2**63 - 1  # unknown: do not refuse
    try:
        with open("/sys/fs/cgroup/memory.max") as fh:
            limit = fh.read().strip()
        if limit != "max":
            with open("/sys/fs/cgroup/memory.current") as fh:
                available = min(available, int(limit) - int(fh.read().strip()))
    except (OSError, ValueError):
        pass
    return available


def memory_needed(n_samples, n_channels, rows, cols, n_refs=None, max_order=None) -> dict:
    """Peak bytes of the identification's large arrays (float64), by stage.

    - ``correlations`` (ambient, ``n_refs`` given): ``n_refs x n_lags x
      n_channels`` lags computed through cross-spectra of ``n_refs x bins x
      n_channels`` complex values and their inverse FFT (:func:`modal.correlations`);
    - ``hankel``: ``H`` of ``(rows + 1) n_channels x cols m`` (``m = n_refs``
      data sets, or 1 for a free decay);
    - ``svd``: the thin SVD of ``H(0)`` (``l r x m s``): LAPACK's copy of it
      and both singular-vector matrices (the Gram route needs less, but may
      fall back on it);
    - ``poles`` (``max_order`` given): the modal histories of every pole of
      every order ``2, 4, ..., max_order`` over the ``m s`` columns (for the
      MAMC), real for each of the ``(max_order / 2) (max_order / 2 + 1)``
      eigenvalues and complex for one of each conjugate pair.

    ``peak`` is the larger of the correlation stage and what is held at once
    during the SVD or the poles (correlations, Hankel matrix, the larger of
    SVD and poles).
    """
    import scipy.fft

    m = 1 if n_refs is None else n_refs
    parts = {}
    corr_result = 0
    if n_refs is not None:
        n_lags = 2 * rows + 1
        n_fft = scipy.fft.next_fast_len(n_samples + n_lags, real=True)
        bins = n_fft // 2 + 1
        corr_result = 8 * n_refs * n_lags * n_channels
        parts["correlations"] = 16 * bins * n_channels * (1 + n_refs) + 8 * n_refs * n_fft * n_channels + corr_result
    h_rows, h_cols = rows * n_channels, cols * m
    parts["hankel"] = 8 * (rows + 1) * n_channels * h_cols
    k = min(h_rows, h_cols)
    parts["svd"] = 8 * (h_rows * h_cols + h_rows * k + k * h_cols)
    if max_order is not None:
        half = max_order // 2
        parts["poles"] = 16 * half * (half + 1) * h_cols
    parts["peak"] = max(parts.get("correlations", 0),
                        corr_result + parts["hankel"] + max(parts["svd"], parts.get("poles", 0)))
    return parts


def _gb(n_bytes) -> str:
    return f"{n_bytes / 1e9:.3g} GB" if n_bytes >= 1e8 else f"{n_bytes / 1e6:.3g} MB"


def _refuse_beyond_memory(n_samples, n_channels, rows, cols, n_refs, max_order) -> None:
    need = memory_needed(n_samples, n_channels, rows, cols, n_refs, max_order)
    have = available_memory()
    if need["peak"] > have:
        m = 1 if n_refs is None else n_refs
        detail = []
        if "correlations" in need:
            detail.append(f"correlations {n_refs} refs x {2 * rows + 1} lags x {n_channels} channels, "
                          f"through cross-spectra: {_gb(need['correlations'])}")
        detail.append(f"Hankel matrix {(rows + 1) * n_channels} x {cols * m}: {_gb(need['hankel'])}")
        detail.append(f"its SVD: {_gb(need['svd'])}")
        half = max_order // 2
        detail.append(f"the modal histories of {half * (half + 1)} eigenvalues (orders 2 ... {max_order}): "
                      f"{_gb(need['poles'])}")
        raise ValueError(
            f"the identification would need about {_gb(need['peak'])} of memory ({'; '.join(detail)}), "
            f"only {_gb(have)} available: use fewer channels or references (--channels, --refs), fewer rows "
            "or a lower --max-order")


def identify_record(
    acc,
    dt,
    options: IdentifyOptions | str | None = None,
    *,
    criteria: StabilityCriteria | None = None,
    log: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
    channel_labels=None,
    details: dict | None = None,
    **keywords,
) -> tuple[Stabilisation, float]:
    """Modes of a measured record, as ``modal identify`` finds them.

    Steps: keep the channels used (``options.channels``); remove a linear
    trend (:func:`detrend`); with ``fmax``, decimate (:func:`decimate`) by
    ``q = floor(fs / (2.5 fmax))`` so that the anti-aliasing filter passes
    ``fmax``; optionally high-pass (:func:`zero_phase_filter`). Then

    - ``"ambient"``: NExT correlation functions (:func:`modal.correlations`,
      biased) with ``2 rows + 1`` lags, one data set per reference, are the
      ERA data;
    - ``"free_decay"``: the record from its impact on
      (:func:`modal.decay_start`) is.

    Without ``fmax`` and ``rows`` the settings come from the record: the
    lowest prominent peak of its spectrum (:func:`lowest_peak_hz`) sets the
    block rows so they span :data:`AUTO_PERIODS` of its periods (at least
    ``2 max_order / channels``; a free decay :data:`DECAY_PERIODS`, at least
    60), the record decimated to about
    :data:`AUTO_SAMPLES` samples per period; ``log`` says what was chosen.

    :func:`stabilisation` with ``rows`` block rows and as many columns as the
    data allow (free decay: at most ``10 rows``, the decay is then long gone
    into noise for lightly damped structures sampled at ``2.5 fmax``).

    The spectral witness: the singular values of the spectral density matrix
    of the record as identified (after decimation and filters; :func:`modal.fdd`),
    and each selected mode checked against their peaks
    (:func:`modal.spectral_support`): ``modes`` gains the columns
    ``sv_peak_hz``, ``sv_number``, ``sv_mac`` and ``spectral_support``, and a
    mode without a peak near it has ``no spectral peak`` among its ``flag``
    reasons (where the selection writes a ``flag`` column). Of an ambient
    record, each mode's amplitude steadiness (:func:`with_harmonic_check`):
    ``envelope_cv`` and ``envelope_values``, and ``harmonic (envelope CV
    0.06)`` among the reasons of a mode whose amplitude stays steady.

    Refused with ``ValueError`` before the work: options the record cannot
    take (:meth:`IdentifyOptions.record_problems`: fmax above its Nyquist
    frequency, a channel it lacks), a channel with no vibration
    (:func:`no_vibration`: a constant, an exact linear drift, a dead sensor:
    otherwise round-off would yield stable-looking "modes"), and settings
    whose arrays would not fit in the available memory
    (:func:`memory_needed` against :func:`available_memory`; the message
    states the sizes).

    Parameters
    ----------
    acc : array_like, shape (n_samples, n_channels)
        The record, every channel (``options.channels`` picks those used).
    dt : float
        Sampling interval (s).
    options : IdentifyOptions or str
        Every option of the identification (:class:`IdentifyOptions`); or
        the excitation (``"ambient"``, ``"free_decay"``) with the other
        options as ``keywords``.
    criteria : StabilityCriteria, optional
    log : callable, optional
        Receives one line per step (for progress messages).
    progress : callable, optional
        Passed to :func:`stabilisation`.
    channel_labels : sequence, optional
        How messages name the channels used; default the record's channel
        numbers.
    details : dict, optional
        Filled with what the identification chose and computed besides the
        result: ``"settings"`` (a dict of plain values: the sampling rates,
        decimation factor, block rows and columns, lags, references, segments,
        the lowest spectral peak, the decay's start, the orders, the Welch
        segment; what ``settings.json`` records) and ``"spectrum"`` (the
        :class:`modal.SingularValueSpectrum`).
    **keywords
        Options (fields of :class:`IdentifyOptions`: ``max_order``, ``fmax``,
        ``rows``, ``refs``, ``highpass_hz``, ``quantities``, ...) given one by
        one, or replacing those of ``options``.

    Returns
    -------
    result : Stabilisation
    dt : float
        The sampling interval after decimation.
    """
    from ..identification import fdd
    from ..signals import correlations
    from ..signals import decay_start, decimate, detrend, zero_phase_filter

    log = log or (lambda message: None)
    options = identify_options(options, **keywords)
    excitation, max_order, fmax, rows = options.excitation, options.max_order, options.fmax, options.rows
    dt = positive_float("dt", dt)
    chosen = {"fs_record_hz": 1 / dt, "decimation": 1, "lowest_peak_hz": None}
    acc = np.asarray(acc)
    if acc.ndim != 2:
        raise ValueError(f"acc must be a record of shape (n_samples, n_channels), got shape {acc.shape}")
    if acc.shape[0] < acc.shape[1]:
        raise ValueError(f"acc of shape {acc.shape} reads as {acc.shape[0]} samples of {acc.shape[1]} channels; the "
                         "layout is (n_samples, n_channels): transpose it (acc.T)")
    if options.fs is not None and abs(options.fs * dt - 1) > 1e-9:
        raise ValueError(f"options.fs = {options.fs:g} Hz contradicts dt = {dt:g} s ({1 / dt:g} Hz): "
                         "identify_record takes the sampling interval dt; give one rate")
    options.check_record(acc.shape[1], 1 / dt)
    channels, refs = options.channel_choice(acc.shape[1])
    if options.channels is not None:
        acc = acc[:, channels]
    labels = channels if channel_labels is None else list(channel_labels)
    if len(labels) != acc.shape[1]:
        raise ValueError(f"channel_labels: {len(labels)} labels for {acc.shape[1]} channels used")
    raw = acc
    spikes = spike_samples(raw)
    if excitation == "free_decay" and any(at.size for at in spikes):
        # the impact: an accelerometer's direct response to a hammer's blow is one sharp sample, not a spike
        impact = decay_start(detrend(raw))
        spikes = [at[np.abs(at - impact) > SPIKE_MAX_WIDTH] for at in spikes]
    if any(at.size for at in spikes):
        acc = despiked(raw, spikes)  # the straight line between each spike's neighbours (modal.despiked)
    y = detrend(acc)  # a copy of the record, the only one of its size
    _refuse_no_vibration(np.asarray(acc, dtype=float), y, labels)
    levels = level_warning(y, labels, options.quantities)
    for message in clipping_warnings(raw, 1 / dt, labels) + spike_warnings(raw, 1 / dt, labels, spikes=spikes) + (
            [levels] if levels else []):
        warnings.warn(message, ModalWarning, stacklevel=2)
    y /= unit_scale(y)  # a power of two: exact, and the products below neither underflow nor overflow
    scales = level_scales(y, options.quantities)
    if np.any(scales != 1):
        y *= scales  # powers of two: exact; the shapes are scaled back at the end
        log("scaled up for the identification (weaker than a tenth of the strongest of their quantity): "
            + ", ".join(f"channel {labels[c]} x {scales[c]:g}" for c in np.flatnonzero(scales != 1)))
        chosen["channel_scales"] = {str(labels[c]): float(scales[c]) for c in np.flatnonzero(scales != 1)}
    n_channels = y.shape[1]
    min_rows = least_rows(max_order, n_channels)
    problems = options.length_problems(y.shape[0], dt, n_channels)
    if problems:
        raise ValueError(problems[0])
    if fmax is not None:
        factor = options.decimation(dt)
        if factor >= 2:
            log(f"decimating by {factor}: {1 / dt:g} Hz -> {1 / (dt * factor):g} Hz")
            y, dt = decimate(y, dt, factor)
            chosen["decimation"] = factor
        else:
            log(f"fmax = {fmax:g} Hz: no decimation ({1 / dt:g} Hz is below 2 x 2.5 fmax); "
                f"modes are selected below {fmax:g} Hz")
        rows = options.fixed_rows(n_channels)
    elif rows is None:
        peaks, heights = spectral_peaks(y, dt)
        low = float(peaks[0]) if len(peaks) else None
        # the band reaches the highest peak that stands above the noise around it, not a maximum of the noise
        peaks = np.concatenate([peaks[:1], peaks[1:][heights[1:] >= PEAK_HEIGHT_DB]])
        chosen["lowest_peak_hz"] = low
        chosen["highest_peak_hz"] = float(peaks[-1]) if len(peaks) else None
        if low is None:
            log(f"no spectral peak found: {min_rows} block rows, no decimation")
            rows = min_rows
        else:
            factor, alone = auto_decimation(dt, peaks), auto_decimation(dt, peaks[:1])
            if factor >= 2:
                y, dt = decimate(y, dt, factor)
                chosen["decimation"] = factor
            if excitation == "ambient":
                rows = max(math.ceil(2 * max_order / n_channels), math.ceil(AUTO_PERIODS / (low * dt)))
            else:
                rows = max(min_rows, math.ceil(DECAY_PERIODS / (low * dt)))
            span = f"{rows * dt * low:.2g}"
            log(f"lowest spectral peak {low:.4g} Hz: {rows} block rows span {rows * dt:.3g} s "
                f"({span} period{'' if span == '1' else 's'} of it)"
                + (f", decimated by {factor} to {1 / dt:g} Hz" if factor >= 2 else "")
                + (f", the highest spectral peak {peaks[-1]:.4g} Hz kept in the band (the lowest alone would decimate "
                   f"by {alone})" if factor < alone else "") + " (set --fmax and --rows to choose)")
            lost = peaks[peaks * 2.5 * AUTO_BAND > 1 / dt] if factor >= 2 else peaks[:0]
            if len(lost):
                log(f"spectral peaks above the band kept ({', '.join(f'{f:.4g}' for f in lost)} Hz): more than "
                    f"{AUTO_MAX_SAMPLES} samples per period of the lowest peak would be needed; set --fmax to identify them")
    if options.highpass_hz is not None:
        log(f"high-pass at {options.highpass_hz:g} Hz")
        y = zero_phase_filter(y, dt, highpass_hz=options.highpass_hz)
    if excitation == "ambient":
        n_lags = 2 * rows + 1
        if n_lags > y.shape[0] // 2:
            raise ValueError(f"rows = {rows} needs {n_lags} lags, more than half the {y.shape[0]}-sample record: "
                             "reduce rows or give a longer record")
        n_refs = n_channels if refs is None else len(refs)
        _refuse_beyond_memory(y.shape[0], n_channels, rows, n_lags - rows, n_refs, max_order)
        chosen_refs = list(range(n_channels)) if refs is None else list(refs)
        log(f"correlations: {n_lags} lags ({CORRELATION_ESTIMATOR} estimator), references {chosen_refs}")
        data, start, cols = correlations(y, n_lags, refs=refs, estimator=CORRELATION_ESTIMATOR), 0, None
        n_segments = min(SEGMENTS, max(MIN_SEGMENTS, y.shape[0] // (SEGMENT_LAGS * n_lags)), y.shape[0] // (2 * n_lags))
        chosen.update(n_lags=n_lags, correlation_estimator=CORRELATION_ESTIMATOR,
                      references=[labels[r] for r in chosen_refs])
        if n_segments >= MIN_SEGMENTS:
            length = y.shape[0] // n_segments
            segments = [correlations(y[k * length:(k + 1) * length], n_lags, refs=refs, estimator=CORRELATION_ESTIMATOR)
                        for k in range(n_segments)]
            log(f"uncertainty: {n_segments} segments of {length} samples")
            chosen.update(uncertainty_segments=n_segments, segment_samples=length)
        else:
            segments = None
            log(f"no uncertainty: the record holds fewer than {MIN_SEGMENTS} segments of twice {n_lags} lags")
            chosen.update(uncertainty_segments=0, segment_samples=None)
    else:
        segments = None  # a free decay is one event: no segments to compare
        start = decay_start(y)
        log(f"free decay from sample {start} (t = {start * dt:.4g} s)")
        data = y
        cols = min(y.shape[0] - start - rows, 10 * rows)
        if cols < 1:
            raise ValueError(f"rows = {rows}: the decay after sample {start} is too short; reduce rows")
        _refuse_beyond_memory(y.shape[0], n_channels, rows, cols, None, max_order)
        chosen.update(decay_start_sample=int(start), decay_start_s=start * dt)
    log(f"stabilisation: orders 2 ... {max_order}, {rows} block rows")
    result = stabilisation(data, dt, max_order, rows, cols=cols, start=start, fmax=fmax, criteria=criteria,
                           progress=progress, quantities=options.quantities, segments=segments)
    spectrum = fdd(y if excitation == "ambient" else y[start:], dt)
    log(f"spectral witness: singular values of the spectral density matrix (Welch, {spectrum.nperseg}-sample "
        f"segments, {spectrum.df:.3g} Hz resolution)")
    onset = None if excitation == "ambient" else onset_spectrum(y[start:], dt, spectrum.nperseg)
    result = with_spectral_witness(result, spectrum, quantities=options.quantities, onset=onset)
    for note in result.notes:  # the selection's decisions (doubtful modes, second estimates, what it left out)
        log(note)  # after the witness, which may vouch for a damping the selection doubted
    mixed = quadrature_warning(result, labels)
    if mixed:
        warnings.warn(mixed, ModalWarning, stacklevel=2)
    if chosen["decimation"] >= 2:
        result = with_filter_check(result, chosen["decimation"], dt)
    if excitation == "ambient":  # a decay's amplitude decays, a harmonic's and a random mode's do not
        result = with_harmonic_check(result, y, dt)
    if np.any(scales != 1):
        result = _in_record_units(result, scales)
    freq_hz = result.modes["freq_hz"].to_numpy()  # arrays, not pandas' masks: a tenth of the time
    unsupported = freq_hz[~result.modes["spectral_support"].to_numpy(bool)]
    if len(unsupported):
        log("no singular-value peak near " + ", ".join(f"{f:.4g}" for f in unsupported) + " Hz")
    flags = _flag_texts(result.modes["flag"])
    blended = freq_hz[[BLEND in flag for flag in flags]]
    if len(blended):
        log("a broad fit across two close modes (a blend of both, not a mode) at "
            + ", ".join(f"{f:.4g}" for f in blended) + " Hz")
    harmonics = freq_hz[[HARMONIC in flag for flag in flags]]
    if len(harmonics):
        log("steady amplitude (a harmonic, not a mode) at " + ", ".join(f"{f:.4g}" for f in harmonics) + " Hz")
    if details is not None:
        chosen.update(fs_identified_hz=1 / dt, channels=list(labels), n_samples=int(y.shape[0]), rows=int(rows),
                      cols=int(cols) if cols is not None else int(data.shape[-2] - rows),
                      orders={"first": 2, "last": int(max_order), "step": 2}, welch_nperseg=spectrum.nperseg,
                      welch_df_hz=spectrum.df)
        details.update(settings=chosen, spectrum=spectrum)
    return result, dt


#: The reason a mode without a singular-value peak near it carries in ``flag``.
NO_SPECTRAL_PEAK = "no spectral peak"
#: The reason a mode of steady amplitude carries in ``flag`` (with its envelope's variation).
HARMONIC = "harmonic"
#: The reason a mode at the decimation filter's own pole carries in ``flag`` (with the pole).
FILTER_POLE = "anti-aliasing filter's pole"


def with_filter_check(result: Stabilisation, factor, dt) -> Stabilisation:
    """``result`` with ``anti-aliasing filter's pole (33.52 Hz, 6.6 %)``
    among the reasons of each mode (where ``modes`` has a ``flag`` column)
    within the pole's half-power half-width ``zeta_p f_p`` of
    :func:`modal.signals.antialiasing_pole` and damped within a factor two of
    it: a record decimated by ``factor`` to ``dt`` rings at that pole where
    it had noise or modes in the filter's transition band; a structural
    mode there is told apart by its lighter damping (a mode damped 5-7 % at
    that very frequency is flagged too)."""
    import dataclasses

    from ..signals import antialiasing_pole

    modes = result.modes
    if "flag" not in modes or not len(modes):
        return result
    pole_hz, pole_zeta = antialiasing_pole(factor, dt)
    freq, damping = modes["freq_hz"].to_numpy(), modes["damping"].to_numpy()
    at_pole = (np.abs(freq / pole_hz - 1) < pole_zeta) & (damping >= pole_zeta / 2) & (damping <= 2 * pole_zeta)
    reason = f"{FILTER_POLE} ({pole_hz:.4g} Hz, {100 * pole_zeta:.2g} %)"
    modes = modes.copy()
    modes["flag"] = _with_reasons(_without_reasons(modes["flag"], FILTER_POLE),
                                  [reason if hit else "" for hit in at_pole])
    return dataclasses.replace(result, modes=modes)


def with_harmonic_check(result: Stabilisation, y, dt) -> Stabilisation:
    """``result`` with each mode's amplitude steadiness in ``modes``
    (:func:`modal.identification.envelope_variation` of the ambient record
    ``y`` as identified, on the modes' real shapes: ``envelope_cv``,
    ``envelope_values``; any already there replaced) and, where ``modes``
    has a ``flag`` column, ``harmonic (envelope CV 0.06)`` added to the
    reasons of a mode whose amplitude stays steady
    (:func:`modal.identification.steady`): a sinusoidal force or a
    machine's rotation, not a mode of the structure."""
    import dataclasses

    from ..identification import envelope_variation, steady

    modes = result.modes
    variation = envelope_variation(y, dt, modes["freq_hz"].to_numpy(dtype=float),
                                   modes["damping"].to_numpy(dtype=float), result.shapes)
    modes = _with_columns(modes, variation)
    if "flag" in modes:
        modes["flag"] = _with_reasons(_without_reasons(modes["flag"], HARMONIC),
                                      [f"{HARMONIC} (envelope CV {cv:.2f})" if h else ""
                                       for h, cv in zip(steady(variation), variation["envelope_cv"])])
    return dataclasses.replace(result, modes=modes)


def _with_columns(modes: pd.DataFrame, table: pd.DataFrame) -> pd.DataFrame:
    """``modes`` with ``table``'s columns (one row per mode) last, any already
    there replaced: in one step (a third of the time of one at a time), and
    ``drop`` only when a column is replaced (it costs as much as the join)."""
    replaced = [column for column in table.columns if column in modes.columns]
    return pd.concat([modes.drop(columns=replaced) if replaced else modes, table.set_axis(modes.index)], axis=1)


def _flag_texts(flags: pd.Series) -> list[str]:
    """Each mode's ``flag`` as text, ``""`` where missing."""
    return [flag if isinstance(flag, str) else "" for flag in flags.tolist()]


def _with_reasons(flags: pd.Series, *reasons) -> pd.Series:
    """Each mode's ``flag`` with its ``reasons`` (lists of one reason per mode,
    empty for none) joined after it by ``"; "``."""
    return pd.Series(["; ".join(filter(None, parts)) for parts in zip(_flag_texts(flags), *reasons)],
                     index=flags.index, dtype=flags.dtype)


def _without_reasons(flags: pd.Series, marker: str, where=None) -> pd.Series:
    """Each mode's ``flag`` without the reasons that contain ``marker``
    where ``where`` (one bool per mode; None: every mode) holds. A check
    takes its own reasons away before it adds them, so that applied twice
    it flags as once."""
    where = [True] * len(flags) if where is None else where
    kept = [flag if not drop else "; ".join(r for r in flag.split("; ") if marker not in r)
            for flag, drop in zip(_flag_texts(flags), where)]
    return pd.Series(kept, index=flags.index, dtype=flags.dtype)


def _vouched_notes(notes, modes: pd.DataFrame, before: pd.Series) -> tuple:
    """The selection's ``notes`` with the sentence of each mode whose flag
    changed from ``before`` to ``modes["flag"]`` (a damping the spectral
    witness vouched for) rewritten: doubtful for the reasons left, or
    trusted and why."""
    from ..identification import doubtful_note

    notes = list(notes)
    for number, freq_hz, damping, peak_hz, old, new in zip(
            modes["mode"], modes["freq_hz"], modes["damping"], modes["sv_peak_hz"], _flag_texts(before),
            _flag_texts(modes["flag"])):
        if old == new:
            continue
        said = doubtful_note(number, freq_hz, old)
        now = doubtful_note(number, freq_hz, new) if new else (
            f"mode {number} ({freq_hz:.4g} Hz): its damping {100 * damping:.2g} % lies above the record's other "
            f"modes', but its own singular-value peak at {peak_hz:.4g} Hz vouches for it (a heavily damped mode: "
            "trusted)")
        notes = [now if note == said else note for note in notes]
    return tuple(notes)


def onset_spectrum(decay, dt, nperseg):
    """The singular-value spectrum of a free decay with its first Welch
    segment centred on the impact: ``decay`` (from its start) after
    ``nperseg // 2`` zeros, in segments of ``nperseg`` (the frequencies of
    :func:`modal.fdd` of ``decay`` with the same ``nperseg``).

    Welch's first Hann segment of the decay itself starts at the impact,
    where the window is zero: a mode that has decayed within a fraction of a
    segment (a high mode of a lightly damped structure: 2270 Hz damped 0.6 %
    lasts 150 samples at 12.8 kHz, a segment holds 2048) is tapered away and
    has no peak. Here the whole decay lies inside the first segment's
    window; the step at the impact spreads the strong modes' leakage, so this
    spectrum only witnesses modes the record's own spectrum has no peak for
    (:func:`with_spectral_witness`)."""
    from ..identification import fdd

    decay = np.asarray(decay, dtype=float)
    padded = np.vstack([np.zeros((int(nperseg) // 2, decay.shape[1])), decay])
    return fdd(padded, dt, nperseg=int(nperseg))


def with_spectral_witness(result: Stabilisation, spectrum, quantities=None, onset=None) -> Stabilisation:
    """``result`` with its modes checked against the singular-value spectrum
    (:func:`modal.spectral_support`, on the complex shapes as identified):
    the columns ``sv_peak_hz``, ``sv_number``, ``sv_mac``, ``spectral_support``
    added to ``modes`` (last; any already there replaced) and, where
    ``modes`` has a ``flag`` column, the reason :data:`NO_SPECTRAL_PEAK` added
    to an unsupported mode's reasons, a supported mode's ``damping ...
    implausibly high`` taken back (a heavily damped mode with a peak of its
    own is real: a damper, a joint, the soil; noise modes, damped as much,
    have none, while a harmonic's or a noise line's implausibly low damping
    comes with a sharp peak and stays flagged), and ``same spectral peak as ...`` to a
    mode that shares its peak and shape with a stronger one
    (:func:`modal.identification.shared_peaks`; a pair of which the
    selection named one ``same shape as ...`` is left as it decided, and a
    mode the selection flagged otherwise yields the peak to a trusted one),
    and then ``blend of ...`` to a broad mode between two sharper trusted
    ones, each with its own peak, whose shapes span its own
    (:func:`modal.identification.blends`: one resonance fitted across two
    close modes, as a decay whose damping falls with its amplitude gives).

    ``quantities`` (what each channel measures, as :func:`modal.stabilisation`
    took them): the shapes are in the first channel's quantity, the spectrum
    in each channel's own, so each entry is multiplied back by
    ``s^(k - k_0)`` (``s`` the mode's pole, ``k`` the channel's derivative,
    ``k_0`` the first's) before its MAC with a singular vector; without it
    every channel measures the same quantity.

    ``onset`` (a free decay, :func:`onset_spectrum`): a mode without a peak in
    ``spectrum`` is checked against it instead, so a mode that decays within
    a fraction of a Welch segment is judged on the decay's first samples."""
    import dataclasses

    from ..identification import (DAMPED_ABOVE, PEAK_PROMINENCE_DB, QUANTITIES, SAME_SHAPE, SHARED_PEAK,
                                  SHARED_PEAK_MAC, blends, own_shapes, shared_peaks, spectral_support)

    modes = result.modes
    identified = _identified_shapes(result)
    shapes = identified
    freq_hz, damping = modes["freq_hz"].to_numpy(dtype=float), modes["damping"].to_numpy(dtype=float)
    if quantities is not None and len(modes):
        relative = np.array([QUANTITIES[q] for q in quantities]) - QUANTITIES[quantities[0]]
        zeta = np.clip(np.nan_to_num(damping), 0.0, 1.0)
        pole = 2 * np.pi * freq_hz * (-zeta + 1j * np.sqrt(1 - zeta**2))
        shapes = np.asarray(shapes, dtype=complex) * pole[None, :] ** relative[:, None]
    own = None
    if "flag" in modes:
        # the reasons a witness applied before gave, taken away: applied twice, it flags as once
        before = modes["flag"]
        for marker in (NO_SPECTRAL_PEAK, SHARED_PEAK, BLEND):
            before = _without_reasons(before, marker)
        own = own_shapes(identified, [flag == "" for flag in _flag_texts(before)])  # the selection's trusted modes
    support = spectral_support(spectrum, freq_hz, shapes, damping=damping, own_shape=own)
    lacking = ~support["spectral_support"].to_numpy(bool)
    if onset is not None and lacking.any():
        second = spectral_support(onset, freq_hz[lacking], np.asarray(shapes)[:, lacking], damping=damping[lacking],
                                  own_shape=None if own is None else own[lacking])
        for column in support.columns:
            values = support[column].to_numpy(copy=True)
            values[lacking] = second[column].to_numpy()
            support[column] = values
    modes = _with_columns(modes, support)
    if "flag" in modes:
        supported = support["spectral_support"].to_numpy(bool)
        peaked = supported & (support["sv_prominence_db"].to_numpy(dtype=float) >= PEAK_PROMINENCE_DB)
        modes["flag"] = _without_reasons(before, DAMPED_ABOVE, peaked)  # a peak of its own, not only a direction
        notes = _vouched_notes(result.notes, modes, before)
        flags = _flag_texts(modes["flag"])
        shadows = np.array([flag.startswith(SAME_SHAPE) for flag in flags], dtype=bool)
        shared = shared_peaks(freq_hz, support, identified, modes["n_poles"], SHARED_PEAK_MAC, shadows,
                              doubtful=np.array([flag != "" for flag in flags], dtype=bool) & ~shadows)
        lacking = [NO_SPECTRAL_PEAK if not found else "" for found in supported]
        modes["flag"] = _with_reasons(modes["flag"], lacking, shared)
        # two sharp modes, each with its own peak, that a broad one between them blends
        blended = blends(freq_hz, damping, identified, [flag == "" for flag in _flag_texts(modes["flag"])],
                         result.criteria.mac_min)
        modes["flag"] = _with_reasons(modes["flag"], blended)
        return dataclasses.replace(result, modes=modes, notes=notes)
    return dataclasses.replace(result, modes=modes)


def write_identification(record, out, options: IdentifyOptions | str | None = None, *, title=None, log=None,
                         progress=None, command=None, **keywords) -> tuple[Stabilisation, float]:
    """Identify a record's modes and write them to the folder ``out``.

    What ``modal identify`` and the workflow's measured records both do:
    :func:`identify_record` on the chosen channels, then

    - ``out/modes.csv``: one row per selected mode (``mode``, ``freq_hz``,
      ``freq_std_hz`` (standard deviation of the estimate), ``freq_spread_hz``
      (spread over the model orders), ``damping``, ``damping_std`` and
      ``damping_spread`` as ratios to critical
      (fractions, not %), ``n_poles``, ``mpc``, ``mamc``, the selection's
      ``flag`` where it gives one, and the spectral witness: ``sv_peak_hz``,
      ``sv_number``, ``sv_mac``, ``spectral_support``, :func:`modal.spectral_support`)
      and its shape, one
      column per channel: ``phi_<name>`` when the record names its channels
      (a CSV header, ``.lvm`` or UFF names: ``record.channels["name"]``),
      else ``phi_<number>`` (the record's 0-based channel numbers; so too when
      names repeat or are the reader's placeholders ``ch1``, ``ch2``, ...):
      the real normalised view, beside ``mpc`` and ``mpd`` (its complexity),
      ``close`` and ``close_mac``;
    - ``out/complex_shapes.csv``: the shapes as identified, one row per mode
      and channel (``mode``, ``channel``, ``re``, ``im``, ``magnitude``,
      ``phase_deg``);
    - ``out/mac.csv`` and ``out/mac.png``: the MAC of every pair of the
      selected modes' shapes (:func:`modal.auto_mac`);
    - ``out/singular_values.csv``: the singular-value spectrum (``freq_hz``,
      ``sv1``, ``sv2``: the record's units squared per Hz);
    - ``out/candidates.csv``: clusters that recur too rarely to be modes;
    - ``out/poles.csv``: every pole of the diagram;
    - ``out/stabilisation.png``: the diagram over the singular values
      (:func:`stabilisation_figure`);
    - ``out/settings.json``: every setting used (:func:`write_settings`),
      those chosen from the record included, and the provenance;
    - ``out/report.html``: one self-contained page of all this
      (:func:`modal.measured.identification_report`).

    The folder is complete or untouched: ``out`` is checked first
    (:func:`check_output`: not the record itself, not a file or device, on a
    writable file system), the files are written into a hidden folder beside
    it, and moved into place only when all are written. A failure part-way
    (a full disk, an error) leaves a previous ``out`` as it was and no
    partial file; other files in an existing ``out`` are left alone.

    Parameters
    ----------
    record : MeasuredRecord
        As :func:`modal.read_record` returns it.
    out : str or Path
        Output folder (created).
    options : IdentifyOptions or str
        Every option (:class:`IdentifyOptions`; ``channels`` and ``refs`` in
        the record's channel numbering, ``fs`` already applied when the
        record was read); or the excitation with the options as ``keywords``,
        as :func:`identify_record` takes them.
    log, progress
        As :func:`identify_record`.
    title : str, optional
        Title of the diagram.
    command : str, optional
        The command that asked for the results (``settings.json`` and the
        report name it); default this process's command line.

    Returns
    -------
    result : Stabilisation
    dt : float
        The sampling interval after decimation.

    Raises
    ------
    OutputError
        (a ``ValueError``) ``out`` cannot hold the results; raised before
        any computation.
    ValueError
        Bad arguments, or identification impossible (:func:`identify_record`).
    OSError
        Writing failed part-way (e.g. no space left); ``out`` is untouched.
    """
    from ._output import check_output, staged_folder
    from ._report import identification_report

    options = identify_options(options, **keywords)
    path = getattr(record, "path", None)
    out = check_output(out, inputs=[path] if path else [])
    options.check_record(record.acc.shape[1], record.fs)
    channels, _ = options.channel_choice(record.acc.shape[1])
    columns = shape_columns(record, channels)
    steps, details = [], {}

    def noted(message):
        steps.append(message)
        if log is not None:
            log(message)

    with staged_folder(out) as staging, kept_warnings() as caught:
        result, dt = identify_record(record.acc, record.dt, options, log=noted, progress=progress, details=details)
        write_results(staging, result, dt, columns, fmax=options.fmax, title=title, spectrum=details["spectrum"])
        settings = write_settings(staging, options, record.dt, dt, chosen=details["settings"],
                                  inputs=[path] if path else [], command=command, criteria=result.criteria)
        identification_report(staging, result, settings, title=title or (path.name if path else "record"),
                              steps=steps, warnings=[str(w.message) for w in caught])
    return result, dt


class kept_warnings:
    """Record the warnings of a block (for the report) and issue them again
    when it ends, so that callers see them as before."""

    def __enter__(self):
        self._context = warnings.catch_warnings(record=True)
        self.caught = self._context.__enter__()
        warnings.simplefilter("always")
        return self.caught

    def __exit__(self, *exc):
        self._context.__exit__(*exc)
        for w in self.caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return False


def provenance(inputs=(), command=None) -> dict:
    """Where results came from: the package's version and those of its
    numerical dependencies, the Python version, the command (default this
    process's command line), the date (UTC) and each input file's path, size
    and sha256."""
    import datetime
    import platform
    import shlex
    import sys
    from importlib.metadata import PackageNotFoundError, version
    from pathlib import Path

    from .._hashes import file_hash

    versions = {}
    for name in ("modal-identification", "numpy", "scipy", "pandas", "matplotlib"):
        try:
            versions[name] = version(name)
        except PackageNotFoundError:  # run from a source tree that was not installed
            versions[name] = None
    files = []
    for source in inputs:
        source = Path(source)
        files.append({"path": str(source.resolve()), "bytes": source.stat().st_size, "sha256": file_hash(source)})
    return {"version": versions["modal-identification"], "packages": versions,
            "python": platform.python_version(),
            "command": command if command is not None else shlex.join([Path(sys.argv[0]).name, *sys.argv[1:]]),
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC"),
            "inputs": files}


def write_settings(folder, options: IdentifyOptions, dt_record, dt, *, chosen=None, inputs=(), command=None,
                   criteria=None) -> dict:
    """``folder/settings.json``: what reproduces the results beside it.

    Keys: ``options`` (:meth:`IdentifyOptions.to_dict`: every option,
    ``null`` for one left to the record), ``fs_record_hz``,
    ``fs_identified_hz`` and ``decimation``, ``chosen`` (what the
    identification chose from the record: the ``details["settings"]`` of
    :func:`identify_record`: block rows and columns, lags, references,
    segments, orders, the lowest spectral peak, the Welch segment), ``criteria``
    (the :class:`modal.StabilityCriteria` of the selection), ``version`` (the
    package's) and ``provenance`` (:func:`provenance`: versions, command,
    date, the sha256 of every input file). ``options`` rebuilds the options
    (``IdentifyOptions.from_mapping(settings["options"])``).

    Returns
    -------
    dict
        What was written.
    """
    import dataclasses
    import json
    from pathlib import Path

    origin = provenance(inputs, command)
    top = {"fs_record_hz": 1 / dt_record, "fs_identified_hz": 1 / dt, "decimation": round(dt / dt_record)}
    chosen = {k: v for k, v in (chosen or {}).items() if k not in top}
    settings = {"options": options.to_dict(), **top, "chosen": _plain(chosen),
                "criteria": dataclasses.asdict(criteria) if criteria is not None else None,
                "version": origin["version"], "provenance": origin}
    (Path(folder) / "settings.json").write_text(json.dumps(settings, indent=2) + "\n")
    return settings


def _plain(value):
    """``value`` with numpy scalars and tuples as JSON's plain values."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def write_results(folder, result: Stabilisation, dt, columns, fmax=None, title=None, spectrum=None) -> None:
    """Write a record's identification into ``folder`` (which exists):
    ``modes.csv`` with a shape column per channel (``columns``, e.g. from
    :func:`shape_columns`), ``complex_shapes.csv``, ``mac.csv`` and
    ``mac.png``, ``candidates.csv``, ``poles.csv`` and ``stabilisation.png``
    (drawn up to ``fmax``, default the Nyquist frequency of ``dt``, over the
    singular values of ``spectrum`` when given, which also gives
    ``singular_values.csv``), as :func:`write_identification` describes them."""
    from pathlib import Path

    from ..identification import auto_mac, stabilisation_figure

    folder = Path(folder)
    modes = result.modes.copy()
    for c, column in enumerate(columns):
        modes[column] = result.shapes[c] if len(modes) else []
    modes.to_csv(folder / "modes.csv", index=False, float_format="%.6g")
    shapes = result.complex_shapes
    pd.DataFrame({
        "mode": np.repeat(modes["mode"].to_numpy(dtype=int), len(columns)),
        "channel": np.tile([c.removeprefix("phi_") for c in columns], len(modes)),
        "re": shapes.T.real.ravel(), "im": shapes.T.imag.ravel(), "magnitude": np.abs(shapes.T).ravel(),
        "phase_deg": np.degrees(np.angle(shapes.T)).ravel(),
    }).to_csv(folder / "complex_shapes.csv", index=False, float_format="%.6g")
    numbers = modes["mode"].to_numpy(dtype=int)
    matrix = auto_mac(shapes if shapes.shape == result.shapes.shape else result.shapes)
    pd.DataFrame(matrix, index=pd.Index(numbers, name="mode"), columns=[str(n) for n in numbers]) \
        .to_csv(folder / "mac.csv", float_format="%.4f")
    mac_figure(matrix, numbers, modes["freq_hz"].to_numpy(dtype=float)).savefig(folder / "mac.png", dpi=100)
    result.candidates.to_csv(folder / "candidates.csv", index=False, float_format="%.6g")
    result.poles.to_csv(folder / "poles.csv", index=False, float_format="%.6g")
    if spectrum is not None:
        pd.DataFrame({"freq_hz": spectrum.freq_hz,
                      **{f"sv{k + 1}": spectrum.values[:, k] for k in range(spectrum.values.shape[1])}}) \
            .to_csv(folder / "singular_values.csv", index=False, float_format="%.6g")
    figure = stabilisation_figure(result, fmax=fmax or 0.5 / dt, title=title, spectrum=spectrum)
    figure.savefig(folder / "stabilisation.png", dpi=120)


def mac_figure(matrix, numbers, freq_hz=None):
    """The MAC matrix of the selected modes as a picture: a grey scale from 0
    (white) to 1 (black), each value printed. Returns a matplotlib ``Figure``."""
    from matplotlib.figure import Figure

    n = len(numbers)
    size = min(9.0, 2.2 + 0.45 * n)
    figure = Figure(figsize=(size, size * 0.85), layout="constrained")
    ax = figure.subplots()
    image = ax.imshow(matrix if n else np.zeros((1, 1)), cmap="Greys", vmin=0, vmax=1)
    labels = [f"{m}" if freq_hz is None else f"{m}: {f:.3g} Hz" for m, f in
              zip(numbers, freq_hz if freq_hz is not None else numbers)]
    ax.set_xticks(range(n), labels, rotation=90, fontsize="small")
    ax.set_yticks(range(n), labels, fontsize="small")
    if n <= 20:
        for i in range(n):
            for j in range(n):
                ax.text(j, i, f"{matrix[i, j]:.2f}", ha="center", va="center", fontsize=7,
                        color="white" if matrix[i, j] > 0.5 else "black")
    ax.set_title("MAC of the selected modes" if n else "MAC: no mode selected", fontsize="medium")
    figure.colorbar(image, ax=ax, shrink=0.8, label="MAC")
    return figure


def shape_columns(record, channels) -> list[str]:
    """The shape columns of ``modes.csv`` for the record's ``channels``:
    ``phi_<name>`` when every channel used has a name of its own (non-empty,
    unique, not all the reader's placeholders ``ch<k>``), else ``phi_<number>``."""
    frame = getattr(record, "channels", None)
    numbers = [f"phi_{channel}" for channel in channels]
    if frame is None or "name" not in frame or len(frame) != record.acc.shape[1]:
        return numbers
    names = [frame["name"].iloc[c] for c in channels]
    if any(not isinstance(n, str) or not n.strip() for n in names):
        return numbers
    names = [n.strip() for n in names]
    placeholders = all(n == f"ch{c + 1}" for n, c in zip(names, channels))
    if placeholders or len(set(names)) != len(names):
        return numbers
    return [f"phi_{name}" for name in names]
