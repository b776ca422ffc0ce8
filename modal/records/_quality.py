"""Clipping: a record whose converter ran at full scale.

A clipped peak is a harmonic distortion at multiples of the response's
frequencies: spurious modes, and real ones lost. The record is not refused
(a user may still want the modes of the rest), but a warning names the
channel, how many samples and when, so that nobody believes the modes
without looking.

Isolated spikes are not detected: a running-median rule flagged dozens of
samples in every Weimar setup, the USC cantilever's impact and a simulated
free decay, none of them spikes.
"""

from __future__ import annotations

import numpy as np

__all__ = ["CLIP_MIN_SAMPLES", "CLIP_PILE_UP", "clipped_samples", "clipping_warnings"]

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
    acc = np.asarray(acc, dtype=float)
    found = []
    for y in acc.T:
        clipped = []
        for extreme, inward in ((np.max(y), y < np.max(y)), (np.min(y), y > np.min(y))):
            at = np.flatnonzero(y == extreme)
            if at.size < CLIP_MIN_SAMPLES or not inward.any():
                continue
            inner = y[inward]
            next_value = np.max(inner) if extreme == np.max(y) else np.min(inner)
            if at.size >= CLIP_PILE_UP * np.count_nonzero(y == next_value):
                clipped.append(at)
        found.append(np.unique(np.concatenate(clipped)) if clipped else np.empty(0, dtype=int))
    return found


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
