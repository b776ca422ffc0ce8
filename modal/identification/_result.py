"""The identification result shared by TCM, ERA and CERA."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd


class ModalWarning(UserWarning):
    """Every warning the engine issues (doubtful input or results), so users
    can filter them with ``warnings.filterwarnings(..., category=ModalWarning)``."""


#: The per-mode flags of :class:`ModalResult`, each a reason to distrust an entry.
FLAGS = ("real_pole", "unstable", "aliased", "short_window")

#: Thesis guideline (Sec. 3.3): the data window spans at least six periods of
#: the lowest mode, ``T >= 12 pi / omega_1``.
GUIDELINE_PERIODS = 6

#: ``|z|`` above ``1 + UNSTABLE_TOL`` flags an ERA pole unstable; round-off
#: puts exactly undamped poles at ``|z| = 1 +- 1e-14``.
UNSTABLE_TOL = 1e-9

#: A frequency within this fraction of the method's limit ``pi / T_o`` is
#: flagged as possibly aliased.
ALIAS_MARGIN = 0.02


def _nan(n: int) -> np.ndarray:
    return np.full(n, np.nan)


@dataclass(frozen=True, repr=False)
class ModalResult:
    """Identified modes, sorted by natural frequency.

    Attributes
    ----------
    omega : ndarray, shape (n_modes,)
        Natural frequencies in rad/s (ERA: ``|s|`` with ``s = ln z / dt``, Eq. 44).
    damping : ndarray
        Modal damping ratios ``-Re s / |s|``; NaN where the method does not
        identify damping (TCM, CERA) or for real poles.
    shapes : ndarray, shape (n_channels, n_modes)
        Real mode shapes at the sensors, each scaled to unit Euclidean norm with
        its largest-magnitude entry positive.
    real_pole : ndarray of bool
        True where the identified eigenvalue is real (ERA) or does not map to
        an oscillation (TCM/CERA eigenvalue outside the admissible range); such
        entries are kept, flagged, never silently dropped.
    unstable : ndarray of bool
        ERA: ``|z| > 1``, a growing "mode" (negative damping); a computational
        or noise pole, not a structural mode.
    aliased : ndarray of bool
        Possibly aliased: the frequency lies at or beyond the highest one the
        method can tell apart, ``pi / T_o`` (``T_o = lag dt`` for the TCM with a
        lag, Eq. 30; ``dt`` for ERA, CERA and the TCM without a lag, whose
        ``sqrt(lambda)`` is unbounded), so it may be folded back from above
        or belong to no sampled mode.
    short_window : ndarray of bool
        The data window holds fewer than six periods of this mode, the
        thesis's guideline ``T >= 12 pi / omega_1`` (Sec. 3.3): expect a bias.
    mamc, mpc : ndarray
        Modal amplitude coherence and modal phase collinearity (ERA), NaN otherwise.
    singular_values : ndarray
        Singular values of the Hankel matrix for order selection (CERA and the
        ERA's thin SVD: all of them; the ERA's Gram route: the ``2 n`` leading
        ones), or the eigenvalues of the correlation matrix ``A`` (TCM).
    eigenvalues : ndarray
        The raw eigenvalues the frequencies came from (``z`` for ERA, ``lambda``
        for TCM/CERA).
    method : str
        ``"era"``, ``"tcm"`` or ``"cera"``.
    complex_shapes : ndarray, shape (n_channels, n_modes)
        The shapes as identified, complex, unit norm with the largest entry
        real and positive (ERA: the phases of a complex mode, which
        ``shapes`` rotates onto the real axis); the real ``shapes`` where the
        method gives no phase (TCM, CERA).
    """

    omega: np.ndarray
    shapes: np.ndarray
    method: str
    damping: np.ndarray | None = None
    real_pole: np.ndarray | None = None
    unstable: np.ndarray | None = None
    aliased: np.ndarray | None = None
    short_window: np.ndarray | None = None
    mamc: np.ndarray | None = None
    mpc: np.ndarray | None = None
    singular_values: np.ndarray = field(default_factory=lambda: np.empty(0))
    eigenvalues: np.ndarray = field(default_factory=lambda: np.empty(0))
    complex_shapes: np.ndarray | None = None

    def __post_init__(self):
        n = len(self.omega)
        if self.complex_shapes is None:
            object.__setattr__(self, "complex_shapes", np.asarray(self.shapes, dtype=complex))
        for name in ("damping", "mamc", "mpc"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, _nan(n))
        for name in FLAGS:
            if getattr(self, name) is None:
                object.__setattr__(self, name, np.zeros(n, dtype=bool))

    def __repr__(self) -> str:
        """One line, whatever the size (the arrays are in the attributes and
        :meth:`to_frame`): the method, the frequencies in Hz, the channels
        and how many modes each flag marks."""
        shown = ", ".join(f"{f:.4g}" for f in self.freq_hz[:8]) + (", ..." if self.n_modes > 8 else "")
        flagged = ", ".join(f"{int(np.count_nonzero(getattr(self, name)))} {name}" for name in FLAGS
                            if np.any(getattr(self, name)))
        return (f"<ModalResult {self.method}: {self.n_modes} modes at [{shown}] Hz, "
                f"{self.shapes.shape[0]} channels{'; ' + flagged if flagged else ''}>")

    @property
    def n_modes(self) -> int:
        return len(self.omega)

    @property
    def freq_hz(self) -> np.ndarray:
        """Natural frequencies in Hz."""
        return self.omega / (2 * np.pi)

    def columns(self) -> dict:
        """:meth:`to_frame`'s columns, in its order, as a dict of arrays
        (``method`` a scalar): for callers that add columns of their own and
        build one DataFrame."""
        return {
            "mode": np.arange(1, self.n_modes + 1),
            "method": self.method,
            "omega": self.omega,
            "freq_hz": self.freq_hz,
            "damping": self.damping,
            **{name: getattr(self, name) for name in FLAGS},
            "mamc": self.mamc,
            "mpc": self.mpc,
            **{f"phi_{i + 1}": row for i, row in enumerate(self.shapes)},
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per identified mode: mode, method, omega, freq_hz, damping,
        the flags real_pole, unstable, aliased, short_window, then mamc, mpc,
        and the shape entries as ``phi_1 ... phi_l``."""
        return pd.DataFrame(self.columns())


def normalise_shapes(shapes: np.ndarray) -> np.ndarray:
    """Scale each column to unit Euclidean norm with its largest-magnitude entry
    positive (complex columns are first rotated onto the real axis)."""
    shapes = np.atleast_2d(np.asarray(shapes))
    if np.iscomplexobj(shapes):
        k = np.argmax(np.abs(shapes), axis=0)
        pivot = shapes[k, np.arange(shapes.shape[1])]
        rotation = np.where(np.abs(pivot) > 0, np.conj(pivot) / np.where(np.abs(pivot) > 0, np.abs(pivot), 1), 1)
        shapes = (shapes * rotation).real
    norms = np.linalg.norm(shapes, axis=0)
    shapes = shapes / np.where(norms > 0, norms, 1)
    k = np.argmax(np.abs(shapes), axis=0)
    signs = np.sign(shapes[k, np.arange(shapes.shape[1])])
    return shapes * np.where(signs == 0, 1, signs)


def normalise_complex_shapes(shapes: np.ndarray) -> np.ndarray:
    """Scale each complex column to unit Euclidean norm and rotate it so its
    largest-magnitude entry is real and positive; the phases between the
    entries (the mode's complexity) are kept."""
    shapes = np.atleast_2d(np.asarray(shapes, dtype=complex))
    k = np.argmax(np.abs(shapes), axis=0)
    pivot = shapes[k, np.arange(shapes.shape[1])]
    scale = np.abs(pivot) * np.linalg.norm(shapes, axis=0)
    factor = np.divide(np.conj(pivot), scale, out=np.ones_like(pivot), where=scale > 0)
    return shapes * factor


def sort_modes(omega, shapes, **columns):
    """Return ``omega``, ``shapes`` and the named per-mode columns in order of
    increasing ``omega``."""
    order = np.argsort(omega, kind="stable")
    out = {k: (None if v is None else np.asarray(v)[order]) for k, v in columns.items()}
    return np.asarray(omega)[order], np.asarray(shapes)[:, order], out


def short_window(omega, window) -> np.ndarray:
    """True where a window of ``window`` seconds holds fewer than
    :data:`GUIDELINE_PERIODS` periods of ``omega`` (rad/s)."""
    return np.asarray(omega) * window < 2 * np.pi * GUIDELINE_PERIODS


def near_limit(omega, t_o) -> np.ndarray:
    """True where ``omega`` is at or beyond ``(1 - ALIAS_MARGIN) pi / t_o``."""
    return np.asarray(omega) * t_o >= (1 - ALIAS_MARGIN) * np.pi


def warn_flags(result: ModalResult, window: float) -> ModalResult:
    """Issue one :class:`ModalWarning` naming the flagged entries of ``result``
    (real poles are routine and only counted), and return ``result``."""
    import warnings

    notes = []
    for name, what in (
        ("unstable", "unstable (|z| > 1)"),
        ("aliased", "possibly aliased"),
        ("short_window", f"short window ({window:.4g} s holds fewer than {GUIDELINE_PERIODS} periods)"),
    ):
        flagged = np.flatnonzero(getattr(result, name))
        if flagged.size:
            freqs = ", ".join(f"{w:.4g}" for w in result.omega[flagged])
            notes.append(f"{what}: omega = {freqs} rad/s")
    if notes:
        warnings.warn(f"{result.method}: " + "; ".join(notes) + " (see the result's flags)", ModalWarning, stacklevel=3)
    return result


#: Windows of this many periods of the lowest identified mode, for
#: :func:`free_response_growth`.
FREE_RESPONSE_PERIODS = 4
#: Without an oscillating mode, the record is cut into this many windows.
FREE_RESPONSE_MIN_WINDOWS = 8
#: :func:`warn_not_free_response` warns when the energy of the record grows,
#: summed over its rises from window to window, by more than this multiple of
#: the first window's energy.
FREE_RESPONSE_MAX_GROWTH = 1.0


def free_response_growth(y, dt, omega) -> float:
    """How much the energy of ``y`` rises over the record, relative to its
    start: NaN when the record is too short to tell.

    A free response (or impulse response) starts with all the energy it will
    ever have: without excitation the energy of every mode stays constant
    (undamped) or decays, so the energy summed over channels (and data sets),
    averaged over windows of :data:`FREE_RESPONSE_PERIODS` periods of the
    lowest mode of ``omega`` (so its oscillation averages out), never rises but for noise and the beating of
    close modes. A stationary (ambient) response keeps being excited: its
    windowed energy rises and falls at random for as long as the record lasts.
    The statistic is the sum of the rises from each window to the next,
    ``sum_i max(0, E_{i+1} - E_i) / E_0``: close to 0 for a free response,
    of order one or more per ``1 / (zeta omega)`` correlation times for an
    ambient one.

    NaN when the record holds fewer than two windows: a record shorter than
    eight periods of its lowest mode cannot be told from a stretch of ambient
    response.

    Parameters
    ----------
    y : ndarray, shape (m, n_samples, l)
        The data the method analysed (means removed here per channel).
    dt : float
        Sampling interval (s).
    omega : array_like
        Identified natural frequencies (rad/s); non-finite or non-positive
        ones are ignored.
    """
    omega = _oscillating(omega)
    n_samples = y.shape[1]
    if omega.size:
        # A sampled mode's energy oscillates at 2 omega dt, folded into [0, pi]
        # (near the Nyquist frequency it beats slowly): the windows hold
        # 2 FREE_RESPONSE_PERIODS of those oscillations of every mode.
        rate = np.abs(np.mod(2 * omega * dt + np.pi, 2 * np.pi) - np.pi)
        with np.errstate(divide="ignore"):
            window = np.max(2 * FREE_RESPONSE_PERIODS * 2 * np.pi / rate)
    else:
        window = n_samples // FREE_RESPONSE_MIN_WINDOWS
    if not window < n_samples / 2 or window < 1:
        return np.nan
    window = int(round(window))
    n_windows = n_samples // window
    y = y[:, : n_windows * window]
    power = np.sum((y - y.mean(axis=1, keepdims=True)) ** 2, axis=(0, 2))
    energy = power.reshape(n_windows, window).mean(axis=1)
    if energy[0] <= 0:
        return np.inf if np.any(energy > 0) else np.nan
    return float(np.sum(np.maximum(np.diff(energy), 0)) / energy[0])


def _oscillating(frequencies) -> np.ndarray:
    """The finite, positive entries of ``frequencies`` (real poles and
    non-finite entries dropped)."""
    frequencies = np.asarray(frequencies, dtype=float)
    return frequencies[np.isfinite(frequencies) & (frequencies > 0)]


def warn_not_free_response(result: ModalResult, y, dt) -> ModalResult:
    """Issue a :class:`ModalWarning` when ``y`` is not consistent with a free
    (or impulse) response, :func:`free_response_growth` above
    :data:`FREE_RESPONSE_MAX_GROWTH`, and return ``result``. TCM, ERA and CERA
    all model the data as the free response of the structure (thesis Eqs.
    22, 34, 46); on a stationary ambient record they return frequencies and
    damping that belong to no mode."""
    import warnings

    growth = free_response_growth(y, dt, result.omega)
    if growth > FREE_RESPONSE_MAX_GROWTH:
        found = _oscillating(result.freq_hz)
        lowest = f", {found.min():.4g} Hz" if found.size else ""
        warnings.warn(
            f"{result.method}: the data do not look like a free response: their energy keeps rising "
            f"({growth:.3g} x the initial energy over the record), as in an ambient (stationary) record. "
            f"The {result.method.upper()} assumes free (or impulse) response; for ambient data use "
            "modal.correlations and then modal.era or modal.stabilisation on the correlation functions. "
            "(On a free decay it means the model missed a mode below the lowest it found"
            f"{lowest}, whose oscillation the energy windows do not average out: raise the model order.)",
            ModalWarning, stacklevel=3)
    return result
