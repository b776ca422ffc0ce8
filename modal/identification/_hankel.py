"""The generalized Hankel matrix of Eq. (34)."""

from __future__ import annotations

import numpy as np

from .._checks import positive_int, records


def hankel(y: np.ndarray, rows: int, cols: int, start: int = 0) -> np.ndarray:
    """Generalized Hankel matrix ``H(start)`` of Eq. (34).

    Block ``(i, j)`` is ``Y(start + i + j)``, the ``l x m`` matrix whose column
    ``k`` is the output of data set ``k`` at that sample, so ``H`` has shape
    ``(l rows, m cols)``; its rows are ordered (block row, sensor) and its
    columns (block column, data set).

    Parameters
    ----------
    y : array_like, shape (n_samples, l) or (m, n_samples, l)
        One or ``m`` data sets.
    rows, cols : int
        Block rows ``r`` and block columns ``s``.
    start : int
        First sample ``k``.
    """
    y = records("y", y)
    rows = positive_int("rows", rows)
    cols = positive_int("cols", cols)
    start = positive_int("start", start, minimum=0)
    m, n_samples, l = y.shape
    needed = start + rows + cols - 1
    if needed > n_samples:
        raise ValueError(
            f"rows + cols - 1 = {rows + cols - 1} samples from start = {start} need "
            f"{needed} samples, but the record has {n_samples}: reduce rows or cols"
        )
    # The samples used, each sensor's with the data sets side by side, (l, (r + s - 1) m): row c holds
    # y[k, start + t, c] at t m + k, so row (i, c) of H is the run of s m values from i m on. A strided view
    # (r, l, s m) of those runs is copied once: contiguous runs, four times faster than gathering y's
    # elements one by one (the same values).
    by_sensor = np.ascontiguousarray(y[:, start:needed].transpose(2, 1, 0)).reshape(l, -1)
    runs = np.lib.stride_tricks.sliding_window_view(by_sensor, cols * m, axis=1)[:, :rows * m:m]
    return np.ascontiguousarray(runs.transpose(1, 0, 2)).reshape(rows * l, cols * m)
