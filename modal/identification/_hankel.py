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
    # A strided view (m, r, l, s) of the record, element [k, i, c, j] = y[k, start+i+j, c],
    # copied once into the (block row, sensor) x (block column, data set) layout.
    windows = np.lib.stride_tricks.sliding_window_view(y, cols, axis=1)[:, start:start + rows]
    return np.ascontiguousarray(windows.transpose(1, 2, 3, 0)).reshape(rows * l, cols * m)
