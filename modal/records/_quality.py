"""Clipping and spikes: a record whose converter ran at full scale, or
with a few samples that no vibration could have made.

A clipped peak is a harmonic distortion at multiples of the response's
frequencies: spurious modes, and real ones lost. The record is not refused
(a user may still want the modes of the rest), but a warning names the
channel, how many samples and when, so that nobody believes the modes
without looking.

A spike (a sample, or two or three in a row, far from both of its
neighbours, after which the record is where it was before) is a broadband
impulse: its own "modes" appear in the diagram. Spikes are named the same
way (:func:`spike_warnings`) and, before the identification, replaced by
the straight line between their neighbours (:func:`despiked`). The rule
(:func:`spike_samples`) was chosen to raise no alarm on any measured record
the project has: the 15 Weimar setups (whose reference accelerometers carry
a smooth seven-sample glitch every 10 s: not sharp at its ends, so not a
spike), Palisaden at 100, 20 and 12.5 Hz, the roving-plate setups and the
USC cantilever's impact (which rings on: not a spike); the largest
statistic among them is 28.5 (Palisaden channel 1 at 5195.5 s, a dip of
8 standard deviations over two samples), against a threshold of 50. An
earlier running-median rule flagged dozens of samples in every Weimar
setup, that impact and a simulated free decay.
"""

from __future__ import annotations

import numpy as np

__all__ = ["CLIP_MIN_SAMPLES", "CLIP_PILE_UP", "SPIKE_EDGE", "SPIKE_MAX_WIDTH", "SPIKE_RETURN", "SPIKE_RING",
           "SPIKE_RING_WINDOW", "SPIKE_THRESHOLD", "SPIKE_WINDOW", "clipped_samples", "clipping_warnings", "despiked",
           "spike_samples", "spike_warnings"]

#: Clipping: at least this many samples sit exactly at the channel's extreme
#: value ...
CLIP_MIN_SAMPLES = 3
#: ... this many times more than at the next value inward: a pile-up (a
#: converter at full scale holds every larger value there), which a peak
#: that is only coarsely quantised or oversampled does not make (its top
#: level holds about as many samples as the levels just below).
CLIP_PILE_UP = 3.0


def clipped_samples(acc) -> list[np.ndarray]:
    """Per channel, the samples at its largest or smallest value where that
    value is a pile-up: at least :data:`CLIP_MIN_SAMPLES` samples hold it,
    and :data:`CLIP_PILE_UP` times more than hold the next distinct value
    inward.

    Parameters
    ----------
    acc : ndarray, shape (n_samples, n_channels)

    Returns
    -------
    list of ndarray
        One sorted array of sample indices per channel (empty: not clipped).
    """
    return _per_channel(acc, _clipped_ends)


def _per_channel(acc, find) -> list[np.ndarray]:
    """Per channel ``y`` of ``acc``, the sorted samples of the index arrays
    ``find(y)`` returns (an empty array where it returns none)."""
    acc = np.asarray(acc, dtype=float)
    found = []
    for c in range(acc.shape[1]):
        parts = find(np.ascontiguousarray(acc[:, c]))  # a column of a C-ordered record: its passes 3 x faster
        found.append(np.unique(np.concatenate(parts)) if parts else np.empty(0, dtype=int))
    return found


def _clipped_ends(y) -> list[np.ndarray]:
    """The samples of each end of ``y`` (its largest, its smallest value)
    that is a pile-up by the rule of :func:`clipped_samples`."""
    clipped = []
    for extreme, nearest in ((np.max(y), np.max), (np.min(y), np.min)):
        at = np.flatnonzero(y == extreme)
        if at.size < CLIP_MIN_SAMPLES:
            continue
        inward = y < extreme if nearest is np.max else y > extreme
        if not inward.any():
            continue
        next_value = nearest(y[inward])  # the next distinct value inward
        if at.size >= CLIP_PILE_UP * np.count_nonzero(y == next_value):
            clipped.append(at)
    return clipped


def clipping_warnings(acc, fs: float, labels=None) -> list[str]:
    """One message per clipped channel, with the count and the first times (s).

    Parameters
    ----------
    acc : ndarray, shape (n_samples, n_channels)
        The record as read (before any filter, which smears the flat tops).
    fs : float
        Sampling rate (Hz), for the times.
    labels : sequence, optional
        The channels' names (default: their numbers from 0).

    Returns
    -------
    list of str
    """
    acc = np.asarray(acc, dtype=float)
    labels = list(range(acc.shape[1])) if labels is None else list(labels)
    messages = []
    for channel, at, y in zip(labels, clipped_samples(acc), acc.T):
        if at.size:
            times = ", ".join(f"{i / fs:.6g}" for i in at[:3]) + (", ..." if at.size > 3 else "")
            messages.append(f"channel {channel}: clipped? {at.size} samples at its extreme values "
                            f"({np.min(y):.6g}, {np.max(y):.6g}), t = {times} s, more than at any value "
                            "just inside them (a converter at full scale): spurious modes may follow, real ones "
                            "may be lost")
    return messages


# ---------------------------------------------------------------- spikes

#: A spike is a run of at most this many consecutive samples ...
SPIKE_MAX_WIDTH = 3
#: ... each departing, on the same side, from the straight line between the
#: run's two neighbours; the smallest departure is more than this many times
#: the channel's sample-to-sample variation (and the local one, see
#: :data:`SPIKE_WINDOW`) ...
SPIKE_THRESHOLD = 50.0
#: ... after which the record is back where it was: the two neighbours
#: differ by at most this fraction of the departure (not a step) ...
SPIKE_RETURN = 0.5
#: ... sharp at both ends: each neighbour's own second difference is
#: opposite to the departure and at least this fraction of it (a smooth bump
#: curves the same way at its ends) ...
SPIKE_EDGE = 0.25
#: ... larger than the local variation too, over this many samples on each
#: side (the rough ringing of an impact raises it) ...
SPIKE_WINDOW = 32
#: ... and not the onset of an impact: the record's spread over the
#: :data:`SPIKE_RING_WINDOW` samples after the run is at most this many times
#: its spread over those before (an impact keeps ringing; a spike leaves the
#: record as it was).
SPIKE_RING = 10.0
#: Samples on each side over which the spreads of :data:`SPIKE_RING` are taken.
SPIKE_RING_WINDOW = 1000

_MAD_TO_SIGMA = 1.482602218505602  # 1 / Phi^-1(3/4): the median absolute deviation of a normal variable is 0.6745 sigma
_MEAN_AD_TO_SIGMA = 1.2533141373155001  # sqrt(pi / 2): its mean absolute deviation is 0.7979 sigma


def _spread(x) -> float:
    """1.4826 x the median absolute deviation of ``x`` (its standard
    deviation were it normal, unmoved by a few outliers); 0 if empty."""
    x = np.asarray(x, dtype=float)
    return float(_MAD_TO_SIGMA * np.median(np.abs(x - np.median(x)))) if x.size else 0.0


def _variation(d, deviation=None) -> float:
    """The channel's sample-to-sample variation: the spread of its second
    differences ``d``; where more than half of them are equal (a coarsely
    quantised record), 1.2533 x their mean absolute deviation instead.
    ``deviation``: ``|d - median(d)|``, if already computed."""
    deviation = np.abs(d - np.median(d)) if deviation is None else deviation
    spread = float(_MAD_TO_SIGMA * np.median(deviation)) if deviation.size else 0.0
    return spread if spread > 0 else float(_MEAN_AD_TO_SIGMA * np.mean(deviation))


def _within(d, deviation, edge) -> bool:
    """Whether every ``|d| <= edge x _variation(d)``, known without the
    median of ``deviation = |d - median(d)|`` (the spike check's costliest
    step): False when it cannot tell that way.

    With ``level`` just above ``max|d| / (1.4826 edge)``: if fewer than
    ``ceil(n / 2)`` deviations are ``<= level``, the ``ceil(n / 2)``-th
    smallest deviation is above ``level``, and so is their median (NumPy's
    median of ``n`` values is that one for odd ``n``, the mean of it and the
    next for even ``n``, no smaller). Rounding is monotone, so the spread
    ``1.4826 x median`` is then at least ``1.4826 x level`` as rounded, and
    positive (not the quantised records' fallback); and ``edge`` times it at
    least ``max|d|`` once ``edge x (1.4826 x level)``, rounded as
    :func:`_spike_runs` rounds, is checked to be."""
    if not edge > 0 or not deviation.size:
        return False
    largest = float(np.max(np.abs(d)))
    if not np.isfinite(largest):
        return False
    level = largest / (edge * _MAD_TO_SIGMA) * (1 + 2**-40)  # a little above, for the check's rounding
    if not largest <= edge * float(_MAD_TO_SIGMA * level):
        return False
    return int(np.count_nonzero(deviation <= level)) < (deviation.size + 1) // 2


def _spike_runs(y, threshold=None) -> list[tuple[int, int, float]]:
    """The runs of ``y`` that are spikes by the rule of :func:`spike_samples`
    with ``threshold`` (default :data:`SPIKE_THRESHOLD`): ``(first sample,
    last sample, statistic)``, the statistic being the smallest departure
    over the larger of the channel's and the local variation."""
    threshold = SPIKE_THRESHOLD if threshold is None else threshold
    y = np.asarray(y, dtype=float)
    n = y.size
    runs = []
    if n < SPIKE_MAX_WIDTH + 4:
        return runs
    d = np.zeros(n)
    d[1:-1] = y[1:-1] - (y[:-2] + y[2:]) / 2  # each sample less the mean of its two neighbours
    # A spike's left neighbour has |d| >= SPIKE_EDGE x its departure > SPIKE_EDGE x threshold x variation: the
    # runs to look at start just after such samples (half that bound, against round-off), rare in any record:
    # most records have none, which _within tells without the variation's second median.
    edge = 0.5 * SPIKE_EDGE * threshold
    deviation = np.abs(d[1:-1] - np.median(d[1:-1]))
    if _within(d[1:-1], deviation, edge):
        return runs
    variation = _variation(d[1:-1], deviation)
    if not variation > 0:
        return runs
    after_big = np.flatnonzero(np.abs(d) > edge * variation) + 1
    for width in range(1, SPIKE_MAX_WIDTH + 1):
        # the neighbours first - 1 and first + width have two neighbours each
        first = after_big[(after_big >= 2) & (after_big <= n - width - 2)]
        left, right = y[first - 1], y[first + width]
        departure = np.stack([y[first + j] - (left + (right - left) * (j + 1) / (width + 1)) for j in range(width)])
        up, down = np.all(departure > 0, axis=0), np.all(departure < 0, axis=0)
        size = np.where(up | down, np.min(np.abs(departure), axis=0), 0.0)
        sign = np.where(up, 1.0, -1.0)
        candidate = ((size > threshold * variation)
                     & (np.abs(right - left) <= SPIKE_RETURN * size)
                     & (-sign * d[first - 1] >= SPIKE_EDGE * size)
                     & (-sign * d[first + width] >= SPIKE_EDGE * size))
        for i in np.flatnonzero(candidate):
            start, end = int(first[i]), int(first[i]) + width - 1
            local = max(_spread(d[max(1, start - 1 - SPIKE_WINDOW):start - 1]),  # d free of the run: it moves d[start - 1 .. end + 1]
                        _spread(d[end + 2:min(n - 1, end + 2 + SPIKE_WINDOW)]))
            statistic = size[i] / max(variation, local)
            before = _spread(y[max(0, start - 1 - SPIKE_RING_WINDOW):start - 1])
            after = _spread(y[end + 2:end + 2 + SPIKE_RING_WINDOW])
            if statistic > threshold and after <= SPIKE_RING * before:
                runs.append((start, end, float(statistic)))
    return runs


def spike_samples(acc) -> list[np.ndarray]:
    """Per channel, the samples of its spikes.

    With ``d[i] = y[i] - (y[i-1] + y[i+1]) / 2`` and the channel's variation
    ``s`` (1.4826 x the median absolute deviation of ``d``), a run of ``w``
    consecutive samples (``w <= ``:data:`SPIKE_MAX_WIDTH`) is a spike when
    every sample departs on the same side from the straight line between
    the run's two neighbours by more than :data:`SPIKE_THRESHOLD` times the
    larger of ``s`` and the variation of the :data:`SPIKE_WINDOW` samples on
    either side; the neighbours differ by at most :data:`SPIKE_RETURN` of
    that departure; each neighbour's ``d`` is opposite to it and at least
    :data:`SPIKE_EDGE` of it; and the record's spread after the run is at
    most :data:`SPIKE_RING` times its spread before. A spike within two
    samples of either end is not judged (it has no neighbours' neighbours).

    Parameters
    ----------
    acc : ndarray, shape (n_samples, n_channels)

    Returns
    -------
    list of ndarray
        One sorted array of sample indices per channel (empty: no spike).
    """
    return _per_channel(acc, lambda y: [np.arange(first, last + 1) for first, last, _ in _spike_runs(y)])


def _groups(at) -> list[np.ndarray]:
    """Sorted sample indices split into runs of consecutive ones."""
    return np.split(at, np.flatnonzero(np.diff(at) > 1) + 1) if at.size else []


def spike_warnings(acc, fs: float, labels=None, spikes=None) -> list[str]:
    """One message per channel with spikes (:func:`spike_samples`): how many
    spikes and samples, and the first times (s).

    Parameters
    ----------
    acc : ndarray, shape (n_samples, n_channels)
        The record as read (before any filter, which smears a spike).
    fs : float
        Sampling rate (Hz), for the times.
    labels : sequence, optional
        The channels' names (default: their numbers from 0).
    spikes : list of ndarray, optional
        :func:`spike_samples` of ``acc``, if already found.

    Returns
    -------
    list of str
    """
    acc = np.asarray(acc, dtype=float)
    labels = list(range(acc.shape[1])) if labels is None else list(labels)
    spikes = spike_samples(acc) if spikes is None else spikes
    messages = []
    for channel, at in zip(labels, spikes):
        if at.size:
            groups = _groups(at)
            times = ", ".join(f"{g[0] / fs:.6g}" for g in groups[:3]) + (", ..." if len(groups) > 3 else "")
            messages.append(f"channel {channel}: {len(groups)} spike{'s' if len(groups) > 1 else ''} "
                            f"({at.size} sample{'s' if at.size > 1 else ''} far from both neighbours, then back), "
                            f"t = {times} s: replaced by the straight line between their neighbours "
                            "before identifying (a spike gives spurious modes)")
    return messages


def despiked(acc, spikes=None) -> np.ndarray:
    """A copy of the record with each spike's samples (:func:`spike_samples`,
    or ``spikes``, one array of sample indices per channel) replaced by the
    straight line between the samples just before and after them.

    Parameters
    ----------
    acc : ndarray, shape (n_samples, n_channels)
    spikes : list of ndarray, optional

    Returns
    -------
    ndarray, shape (n_samples, n_channels), float
    """
    out = np.array(acc, dtype=float)
    spikes = spike_samples(out) if spikes is None else spikes
    for column, at in zip(out.T, spikes):
        for group in _groups(np.asarray(at, dtype=int)):
            before, after = group[0] - 1, group[-1] + 1
            if before < 0 or after >= column.size:
                continue
            column[group] = column[before] + (column[after] - column[before]) * (group - before) / (after - before)
    return out
