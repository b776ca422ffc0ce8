"""Input validation shared by the engine: every check raises ``ValueError``
naming the offending argument and what was expected."""

from __future__ import annotations

import numbers

import numpy as np


def positive_int(name: str, value, minimum: int = 1) -> int:
    """Return ``value`` as ``int`` if it is an integer ``>= minimum``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def positive_float(name: str, value) -> float:
    """Return ``value`` as ``float`` if it is finite and strictly positive."""
    if isinstance(value, (bool, np.bool_)):
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
    (real numbers only: booleans and complex values are refused)."""
    raw = np.asarray(value)
    if raw.dtype.kind in "bcOUS" and not (raw.dtype.kind == "O" and raw.size and
                                          all(isinstance(v, (int, float, np.number)) and not isinstance(v, bool)
                                              for v in raw.ravel())):
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


def records(name: str, y) -> np.ndarray:
    """Return measurement data as ``(n_sets, n_samples, n_channels)``.

    Accepts ``(n_samples, n_channels)`` for one data set or
    ``(n_sets, n_samples, n_channels)`` for several (Eq. 34's m).
    """
    a = finite_array(name, y, ndim=(2, 3))
    if a.ndim == 2:
        a = a[np.newaxis]
    if a.shape[1] < 2:
        raise ValueError(f"{name} needs at least 2 samples per channel, got {a.shape[1]}")
    return a
