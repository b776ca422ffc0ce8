"""Input validation shared by the engine: every check raises ``ValueError``
naming the offending argument and what was expected."""

from __future__ import annotations

import numbers

import numpy as np


def printable(text: str) -> str:
    """``text`` with every byte that a file name held but UTF-8 could not
    decode (Python keeps it as a lone surrogate, ``\\udce9``) shown as the
    replacement character U+FFFD: a title, a page or a table can then be
    drawn and written (a surrogate stops matplotlib and any UTF-8 writer)."""
    return text.encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def positive_int(name: str, value, minimum: int = 1) -> int:
    """Return ``value`` as ``int`` if it is an integer ``>= minimum``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def positive_float(name: str, value) -> float:
    """Return ``value`` as ``float`` if it is finite and strictly positive."""
    if isinstance(value, (bool, np.bool_)) or np.asarray(value).dtype == bool:
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {value!r}") from None
    if not np.isfinite(x) or x <= 0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return x


def nonnegative_float(name: str, value) -> float:
    """Return ``value`` as ``float`` if it is finite and ``>= 0``."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be a number >= 0, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number >= 0, got {value!r}") from None
    if not np.isfinite(x) or x < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return x


def finite_array(name: str, value, ndim: tuple[int, ...]) -> np.ndarray:
    """Return ``value`` as a float array of one of the ranks ``ndim``, all finite
    (real numbers only: integer and float dtypes, or objects that are all
    real numbers; booleans, complex values, strings, dates and durations
    (``datetime64``, ``timedelta64``: they convert to numbers, but not to a
    measured quantity) are refused)."""
    raw = np.asarray(value)
    if raw.dtype.kind not in "iuf" and not (raw.dtype.kind == "O" and raw.size and
                                            all(isinstance(v, (int, float, np.integer, np.floating))
                                                and not isinstance(v, bool) for v in raw.ravel())):
        raise ValueError(f"{name} must hold real numbers, got dtype {raw.dtype}")
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric array") from None
    if a.ndim not in ndim:
        ranks = " or ".join(str(d) for d in ndim)
        raise ValueError(f"{name} must be a {ranks}-dimensional array, got shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"{name} is empty (shape {a.shape})")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or inf")
    return a


def square_matrix(name: str, value) -> np.ndarray:
    """Return ``value`` as a finite square float matrix (:func:`finite_array`)."""
    a = finite_array(name, value, ndim=(2,))
    if a.shape[0] != a.shape[1]:
        raise ValueError(f"{name} must be a square matrix, got shape {a.shape}")
    return a


def records(name: str, y) -> np.ndarray:
    """Return measurement data as ``(n_sets, n_samples, n_channels)``.

    Accepts ``(n_samples, n_channels)`` for one data set or
    ``(n_sets, n_samples, n_channels)`` for several (Eq. 34's m). A record
    with fewer samples than channels or than data sets is refused: it is
    almost always an array in another layout (channels first, or data sets on
    the last axis). So is a channel that is constant in a data set (a dead or
    disconnected sensor carries no response and makes the correlations
    singular).
    """
    a = finite_array(name, y, ndim=(2, 3))
    if a.ndim == 2:
        a = a[np.newaxis]
    n_sets, n_samples, n_channels = a.shape
    if n_samples < 2:
        raise ValueError(f"{name} needs at least 2 samples per channel, got {n_samples}")
    if n_samples < n_channels or n_samples < n_sets:
        raise ValueError(
            f"{name} of shape {np.shape(y)} reads as {n_sets} data set(s) of {n_samples} samples "
            f"and {n_channels} channels: fewer samples than channels or data sets. The layout is "
            "(n_samples, n_channels) or (n_sets, n_samples, n_channels); transpose the array "
            "(e.g. np.moveaxis(y, -1, 0) for data sets on the last axis)"
        )
    constant_channels(name, a)
    return a


def constant_channels(name: str, a: np.ndarray) -> None:
    """Refuse a channel that does not vary within a data set (``a`` as
    ``(n_sets, n_samples, n_channels)``, or 2-D for one set)."""
    sets = a if a.ndim == 3 else a[np.newaxis]
    # A channel whose last sample differs from its first varies; only the others are compared sample by
    # sample, each channel on its own (a reduction over the samples of all channels at once strides
    # across the channels: 8 x slower on a 4-channel record), with no copy of the record.
    flat = np.zeros(sets.shape[::2], dtype=bool)  # (n_sets, n_channels)
    for k, c in np.argwhere(sets[:, -1] == sets[:, 0]):
        flat[k, c] = not np.any(sets[k, :, c] != sets[k, 0, c])
    if flat.any():
        k, c = np.argwhere(flat)[0]
        where = f"channel {c}" + (f" of data set {k}" if sets.shape[0] > 1 else "")
        raise ValueError(
            f"{name}: {where} is constant ({float(sets[k, 0, c])!r}); a constant or all-zero channel "
            "carries no vibration: remove it (a dead sensor, or a sensor at a node of every mode)"
        )


def unit_scale(a: np.ndarray) -> float:
    """The power of two nearest the largest magnitude in ``a``.

    The engine divides data by it before forming products, so results do not
    depend on the data's units or scale (1e-160 or 1e+150 would underflow or
    overflow in correlations); dividing by a power of two is exact.
    """
    peak = max(float(np.max(a)), -float(np.min(a))) if np.size(a) else 0.0  # no |a| temporary of a's size
    return float(np.ldexp(1.0, int(np.frexp(peak)[1]))) if peak > 0 else 1.0
