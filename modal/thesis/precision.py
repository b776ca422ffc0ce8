"""The precision of every number committed under ``results/tables``: one rule.

OpenBLAS picks its kernels for the CPU it runs on (``OPENBLAS_CORETYPE``
forces one), and kernels sum in different orders, so the last digits of every
result depend on the machine. Regenerated on one machine under the Haswell and
Prescott kernels (and SkylakeX, this machine's own, at six digits), the
committed numbers differed by at most :data:`KERNEL_SPREAD` (relative; for a
deviation or a z, absolute), measured in docs/reliability.md ("Committed
tables on any CPU"):

- the beam chapter (Tables 1-9, the CERA sensitivity): ``3e-11``, the CERA on
  noise-free data at the widest Hankel matrices and the z of Table 4;
- the grid chapter (Tables 10-15): ``5e-6``. The grid's finite-element
  eigenproblem differs by 2.5e-8 between kernels, the virtual shaking test's
  records by 2.5e-7, and the identification on noisy records amplifies that
  to 4.8e-6 (a single test's frequency, ``seed0``).

The rule, applied by every writer of a committed table
(:func:`modal.thesis.tables.write_csv`) and by the text that quotes numbers
(:func:`percent`: the claims):

- a value (a frequency, a std, a fraction of seeds) keeps
  :func:`significant_digits` significant digits: those its chapter's spread,
  times :data:`MARGIN`, leaves, at most :data:`MOST_DIGITS` (one more than
  the thesis prints): beam 6, grid 3;
- a relative deviation or error, or a z (differences, so their uncertainty is
  absolute), keeps those significant digits but no decimal beyond
  :func:`deviation_decimals`: beam 8, grid 3 (0.1 %);
- a relative deviation or error below :data:`ROUND_OFF` is the round-off of a
  method that is exact in exact arithmetic (the ERA and the CERA on
  noise-free data land at 3e-15 ... 2e-11; the smallest real deviation of
  the committed tables is 5e-7): an exact match, written :data:`EXACT` in
  text and 0 in a numeric column (``cera_sensitivity.csv`` adds the flag
  column ``exact``), never ``8.88e-13 %``.

No rounding makes every number immune: a rounding boundary falls between
two kernels' values of a number with probability spread / quantum. Summed
over the committed numbers at the measured spreads, that is 0.01 for the
3085 beam numbers and 0.11 for the 638 grid numbers (mostly the z of the
"est." rows, repeated in all six grid tables), against 1.1 with one more
grid digit. The regeneration test under two kernels
(``tests/workflow/test_kernels.py``) checks the bytes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
import pandas as pd

__all__ = ["CHAPTERS", "EXACT", "KERNEL_SPREAD", "MARGIN", "MOST_DIGITS", "ROUND_OFF", "committed",
           "deviation", "deviation_decimals", "is_exact", "percent", "significant", "significant_digits"]

#: Largest relative difference of a committed value between two OpenBLAS
#: kernels, by chapter (measured: docs/reliability.md).
KERNEL_SPREAD = {"beam": 3e-11, "grid": 5e-6}
#: The chapters of :data:`KERNEL_SPREAD`.
CHAPTERS = tuple(KERNEL_SPREAD)
#: A number keeps the digits that its spread times this factor leaves.
MARGIN = 100
#: Never more significant digits than this (the thesis prints at most five).
MOST_DIGITS = 6
#: A relative deviation or error below this is round-off: an exact match.
ROUND_OFF = 1e-10
#: How text writes an exact match.
EXACT = f"exact (< {ROUND_OFF:.0e})"


def _spread(chapter: str) -> float:
    try:
        return KERNEL_SPREAD[chapter]
    except KeyError:
        raise ValueError(f"chapter must be one of {', '.join(CHAPTERS)}, got {chapter!r}") from None


def significant_digits(chapter: str) -> int:
    """Significant digits of a committed value of ``chapter`` (``"beam"`` or
    ``"grid"``): ``floor(-log10(spread * MARGIN))``, at most
    :data:`MOST_DIGITS` (beam: 6, grid: 3)."""
    return max(1, min(MOST_DIGITS, math.floor(-math.log10(_spread(chapter) * MARGIN))))


def deviation_decimals(chapter: str) -> int:
    """Decimals of a committed relative deviation of ``chapter`` (as a
    fraction): ``floor(-log10(spread * MARGIN))`` (beam: 8, grid: 3, i.e.
    0.1 %)."""
    return math.floor(-math.log10(_spread(chapter) * MARGIN))


def _round_significant(x: float, digits: int) -> float:
    # through the decimal text, so that writing the result at ``digits``
    # significant digits gives back that text
    return float(f"{x:.{digits}g}") if np.isfinite(x) and x != 0 else float(x)


def _round_deviation(x: float, digits: int, decimals: int) -> float:
    # once, to the coarser of the two quanta (rounding twice could move the last digit)
    if not np.isfinite(x) or abs(x) < ROUND_OFF:
        return 0.0 if np.isfinite(x) else float(x)
    places = min(decimals, digits - 1 - math.floor(math.log10(abs(x))))
    return float(f"{x:.{max(places, 0)}f}") + 0.0 if places >= 0 else round(x, places) + 0.0


def significant(values, chapter: str):
    """``values`` (a number or an array) rounded to
    :func:`significant_digits` of ``chapter``; NaN and infinities kept."""
    digits = significant_digits(chapter)
    if np.ndim(values) == 0:
        return _round_significant(float(values), digits)
    return np.array([_round_significant(float(x), digits) for x in np.ravel(values)]).reshape(np.shape(values))


def is_exact(values):
    """True where a relative deviation or error is below :data:`ROUND_OFF`
    (NaN is not exact)."""
    return np.abs(np.asarray(values, dtype=float)) < ROUND_OFF


def deviation(values, chapter: str):
    """A relative deviation or error as committed: 0 where it is exact
    (:func:`is_exact`), else rounded once to :func:`significant_digits` or to
    :func:`deviation_decimals` decimals of ``chapter``, whichever is coarser."""
    digits, decimals = significant_digits(chapter), deviation_decimals(chapter)
    if np.ndim(values) == 0:
        return _round_deviation(float(values), digits, decimals)
    return np.array([_round_deviation(float(x), digits, decimals) for x in np.ravel(values)]).reshape(np.shape(values))


def percent(fraction: float, chapter: str, digits: int = 3) -> str:
    """A relative deviation or error as text in %: :data:`EXACT` below
    :data:`ROUND_OFF`, else ``digits`` significant digits or
    :func:`deviation_decimals` of ``chapter``, whichever is coarser
    (``0.00166`` -> ``"0.166 %"``; a grid error ``0.04321`` -> ``"4.3 %"``)."""
    if not np.isfinite(fraction):
        return f"{100 * fraction} %"
    if is_exact(fraction):
        return EXACT
    value = _round_deviation(float(fraction), digits, deviation_decimals(chapter))
    return f"{100 * value:.{digits}g} %"


def committed(frame: pd.DataFrame, chapter, deviations: Iterable[str] = ()) -> pd.DataFrame:
    """``frame`` at the precision of a committed table: the columns named in
    ``deviations`` by :func:`deviation`, every other float column by
    :func:`significant`.

    Parameters
    ----------
    frame : DataFrame
    chapter : str or sequence of str
        ``"beam"`` or ``"grid"``, for the whole frame or row by row (a summary
        of both chapters).
    deviations : iterable of str
        Columns holding relative deviations or errors.
    """
    out = frame.copy()
    chapters = [chapter] * len(frame) if isinstance(chapter, str) else list(chapter)
    if len(chapters) != len(frame):
        raise ValueError(f"chapter: {len(chapters)} chapters for {len(frame)} rows")
    chapters = pd.Series(chapters, index=frame.index)
    deviations = set(deviations)
    for column in out.columns:
        if out[column].dtype.kind != "f":
            continue
        values = out[column].to_numpy(float)
        rounded = np.empty_like(values)
        for name in set(chapters):
            rows = (chapters == name).to_numpy()
            rounded[rows] = (deviation if column in deviations else significant)(values[rows], name)
        out[column] = rounded
    return out
