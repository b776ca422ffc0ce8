"""Stabilisation diagram and automatic mode selection for ERA (thesis Ch. 4)
on measured data: impulse or free-decay responses, or the NExT correlation
functions of an ambient record (:func:`modal.correlations`).

Every model order comes from one decomposition of ``H(0)`` (Eq. 35): the
realisation of order ``k`` keeps the ``k`` largest singular triplets (Sec.
4.4), i.e. the first ``k`` columns of ``P``, entries of ``D`` and rows of
``Q^T``, so order ``k`` is a truncation of order ``max_order``
(:func:`modal.era.decompose`, :func:`modal.era.realise`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.fft

from .._checks import nonnegative_float, positive_float, positive_int, records
from ._era import pole_indicators, realisation
from ._era_kernels import complex_poles, decompose, real_eigensystem
from ._hankel import hankel
from ._indicators import mac, paired_mac
from ._result import ModalWarning

POLE_COLUMNS = ["order", "freq_hz", "damping", "mpc", "mamc", "real_pole",
                "stable_freq", "stable_damping", "stable_shape", "stable"]
MODE_COLUMNS = ["mode", "freq_hz", "freq_std_hz", "damping", "damping_std", "n_poles", "mpc", "mamc"]


@dataclass(frozen=True)
class StabilityCriteria:
    """Thresholds of the stabilisation diagram and of the mode selection.

    Attributes
    ----------
    freq_rtol : float
        A pole is stable in frequency when it is within this relative
        distance of the nearest pole of the next lower order.
    damping_rtol : float
        ... and stable in damping when its damping ratio is within this
        relative distance of that pole's.
    mac_min : float
        ... and stable in shape when the MAC with that pole is at least this.
    max_damping : float
        Physical poles have ``0 < damping < max_damping``.
    mpc_min, mamc_min : float
        Minimum modal phase collinearity and modal amplitude coherence.
    cluster_distance : float
        Poles join one mode when the distance ``|f_i - f_j| / max(f_i, f_j) +
        1 - MAC_ij`` between the groups (average linkage) is below this.
    min_poles : int, optional
        A cluster with fewer poles is not a mode; default 40 % of the orders
        computed, at least 3 (a single channel makes every MAC 1, so spurious
        poles near a mode are told apart only by how rarely they recur).
    """

    freq_rtol: float = 0.01
    damping_rtol: float = 0.05
    mac_min: float = 0.98
    max_damping: float = 0.1
    mpc_min: float = 0.7
    mamc_min: float = 0.5
    cluster_distance: float = 0.02
    min_poles: int | None = None

    def __post_init__(self):
        for name in ("freq_rtol", "damping_rtol", "max_damping", "cluster_distance"):
            positive_float(name, getattr(self, name))
        for name in ("mac_min", "mpc_min", "mamc_min"):
            value = nonnegative_float(name, getattr(self, name))
            if value > 1:
                raise ValueError(f"{name} must be in [0, 1], got {value}")
        if self.min_poles is not None:
            positive_int("min_poles", self.min_poles)


@dataclass(frozen=True)
class Stabilisation:
    """Poles of every model order and the modes selected from them.

    Attributes
    ----------
    modes : pandas.DataFrame
        One row per selected mode, by frequency: ``mode``, ``freq_hz`` and
        ``freq_std_hz``, ``damping`` and ``damping_std`` (ratio), ``n_poles``
        (poles clustered into it), mean ``mpc`` and ``mamc``.
    shapes : ndarray, shape (n_channels, n_modes)
        Representative shape of each mode: that of its medoid pole.
    poles : pandas.DataFrame
        One row per pole of every order: ``order``, ``freq_hz``, ``damping``,
        ``mpc``, ``mamc``, ``real_pole``, the stability flags ``stable_freq``,
        ``stable_damping``, ``stable_shape``, ``stable`` (all three),
        ``physical`` (the quality criteria) and ``mode`` (0 when unselected).
    pole_shapes : ndarray, shape (n_poles, n_channels)
    singular_values : ndarray
        Singular values of ``H(0)``.
    spectrum_hz, spectrum : ndarray
        Mean amplitude spectrum of the data, drawn behind the diagram.
    criteria : StabilityCriteria
    """

    modes: pd.DataFrame
    shapes: np.ndarray
    poles: pd.DataFrame
    pole_shapes: np.ndarray
    singular_values: np.ndarray
    spectrum_hz: np.ndarray
    spectrum: np.ndarray
    criteria: StabilityCriteria = field(default_factory=StabilityCriteria)

    def no_mode_reason(self) -> str:
        """Why no mode was selected, from the counts of the diagram: how many
        poles, how many stable, how many of those physical, and the largest
        group of candidates against the poles a mode needs; then what could
        help in that case. Empty when modes were selected."""
        if len(self.modes):
            return ""
        poles, criteria = self.poles, self.criteria
        n_orders = poles["order"].nunique()
        if poles.empty:
            return ("no pole was computed (H(0) has too low a numerical rank): the data hold (almost) no "
                    "oscillation; check the record and the channels used")
        stable = poles["stable"].to_numpy()
        candidates = stable & poles["physical"].to_numpy()
        found = f"{len(poles)} poles over {n_orders} orders, {int(stable.sum())} stable"
        if not stable.any():
            return (f"{found}: no pole recurs from one order to the next (within {criteria.freq_rtol:.0%} in "
                    f"frequency, {criteria.damping_rtol:.0%} in damping, MAC >= {criteria.mac_min}), as for a "
                    "record of noise alone. What could help: check that the record holds the response of "
                    "the structure; with a known band, --fmax (and --highpass against a drift); more samples")
        if not candidates.any():
            s = poles[stable]
            with np.errstate(invalid="ignore"):
                damping_out = ~((s["damping"] > 0) & (s["damping"] < criteria.max_damping))
                reasons = {
                    f"damping outside 0 ... {criteria.max_damping:.0%}": int(damping_out.sum()),
                    f"MPC < {criteria.mpc_min}": int((s["mpc"] < criteria.mpc_min).sum()),
                    f"MAMC < {criteria.mamc_min}": int((s["mamc"] < criteria.mamc_min).sum()),
                    "real": int(s["real_pole"].sum()),
                }
            quality = ~s["real_pole"] & ~damping_out & (s["mpc"] >= criteria.mpc_min) & (s["mamc"] >= criteria.mamc_min)
            reasons["above fmax (or the Nyquist frequency)"] = int(quality.sum())
            why = ", ".join(f"{n} {what}" for what, n in reasons.items() if n)
            advice = (" What could help: --fmax above them if they are modes of interest."
                      if reasons["above fmax (or the Nyquist frequency)"] else
                      " These are not modes of a lightly damped structure (noise or drift poles); "
                      "--highpass removes a drift, a longer record reduces noise poles.")
            return f"{found}, none physical ({why}).{advice}"
        min_poles = criteria.min_poles or max(3, math.ceil(0.4 * n_orders))
        f = np.sort(poles["freq_hz"].to_numpy()[candidates])
        groups = np.split(f, np.flatnonzero(np.diff(f) > criteria.cluster_distance * f[1:]) + 1)
        largest = max(groups, key=len)
        return (f"{found}, {int(candidates.sum())} of them physical, but no cluster of them recurs at enough "
                f"orders: the largest group (near {largest.mean():.4g} Hz) has {len(largest)} poles, a mode needs "
                f"{min_poles} ({'set' if criteria.min_poles else '40 % of the orders'}). Noise alone gives such "
                "scattered poles; if the record holds the structure's response, what could help: a longer "
                "record (ambient: more averaging steadies the poles); --rows so that the Hankel matrix spans a few "
                "periods of the lowest mode. (A higher --max-order computes more orders but also needs more.)")

    def plot(self, fmax=None, title=None, ax=None):
        """The stabilisation diagram; see :func:`modal.stabilisation_figure`."""
        from ..measured import stabilisation_figure  # matplotlib only when drawn

        return stabilisation_figure(self, fmax=fmax, title=title, ax=ax)


def stabilisation(
    y,
    dt,
    max_order,
    rows,
    cols=None,
    start=0,
    fmax=None,
    criteria: StabilityCriteria | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Stabilisation:
    """ERA at every even model order ``2 ... max_order`` from one SVD,
    stability between orders, and modes selected by clustering.

    Parameters
    ----------
    y : array_like, shape (n_samples, l) or (m, n_samples, l)
        Free-decay or impulse responses, or correlation functions
        ``(n_refs, n_lags, l)`` from :func:`modal.correlations`.
    dt : float
        Sampling interval (s).
    max_order : int
        Largest model order (state dimension ``2 n``, even), at most the
        smaller dimension ``min(l rows, m cols)`` of ``H(0)``.
    rows : int
        Block rows ``r`` of ``H(0)`` (Eq. 34). ``r dt`` should span a few
        periods of the lowest mode of interest.
    cols : int, optional
        Block columns ``s``; by default every sample the data allow.
    start : int
        First sample (Eq. 34's ``k - 1``), e.g. :func:`modal.decay_start`.
    fmax : float, optional
        Modes are selected below this frequency (Hz) only; poles above it
        stay in ``poles``.
    criteria : StabilityCriteria, optional
    progress : callable, optional
        Called as ``progress(done, total)`` after each order.

    Returns
    -------
    Stabilisation
    """
    y = records("y", y)
    dt = positive_float("dt", dt)
    max_order = positive_int("max_order", max_order, minimum=2)
    rows = positive_int("rows", rows)
    start = positive_int("start", start, minimum=0)
    criteria = StabilityCriteria() if criteria is None else criteria
    if not isinstance(criteria, StabilityCriteria):
        raise ValueError(f"criteria must be a StabilityCriteria, got {type(criteria).__name__}")
    fmax = None if fmax is None else positive_float("fmax", fmax)
    m, n_samples, l = y.shape
    if cols is None:
        cols = n_samples - start - rows
        if cols < 1:
            raise ValueError(f"rows = {rows} from start = {start} leaves no column of the {n_samples}-sample data")
    cols = positive_int("cols", cols)
    if max_order % 2:
        raise ValueError(f"max_order must be even (complex-conjugate pole pairs), got {max_order}")
    if max_order > min(rows * l, cols * m):
        raise ValueError(
            f"max_order = {max_order} exceeds the smaller dimension of H(0) ({rows * l} x {cols * m}): "
            "reduce max_order or enlarge rows/cols"
        )
    h_ext = hankel(y, rows + 1, cols, start)
    h0, h1 = h_ext[:-l], h_ext[l:]
    p, d, qt, sv = decompose(h0, max_order, block=(l, m))
    rank = int(np.sum(d > sv[0] * np.finfo(float).eps * max(h0.shape)))
    if rank < max_order:
        warnings.warn(f"H(0) has numerical rank {rank}: orders above it are not computed", ModalWarning, stacklevel=2)
        max_order = rank - rank % 2
    orders = list(range(2, max_order + 1, 2))
    table, pole_shapes = _poles(p, d, qt, h1, orders, l, m, dt, progress)
    table.update(_stability(table, pole_shapes, criteria))
    with np.errstate(invalid="ignore"):
        table["physical"] = (
            ~table["real_pole"]
            & (table["damping"] > 0)
            & (table["damping"] < criteria.max_damping)
            & (table["mpc"] >= criteria.mpc_min)
            & (table["mamc"] >= criteria.mamc_min)
            & (table["freq_hz"] < (0.5 / dt if fmax is None else fmax))
        )
    min_poles = criteria.min_poles or max(3, math.ceil(0.4 * len(orders)))
    table["mode"], modes, shapes = _select_modes(table, pole_shapes, criteria.cluster_distance, min_poles)
    poles = pd.DataFrame({name: table[name] for name in POLE_COLUMNS + ["physical", "mode"]})
    if modes.empty:
        warnings.warn("no stable physical poles cluster into a mode: raise max_order or rows, or relax the criteria",
                      ModalWarning, stacklevel=2)
    spectrum_hz, spectrum = _mean_spectrum(y[:, start:], dt)
    return Stabilisation(modes, shapes, poles, pole_shapes, sv, spectrum_hz, spectrum, criteria)


def _poles(p, d, qt, h1, orders, l, m, dt, progress=None):
    """Poles of every order in ``orders``, each realised from the leading
    ``order`` triplets of ``P D Q^T`` (Sec. 4.4), as :func:`modal.era.realise`
    would give them order by order.

    The realisation of order ``k`` is the leading ``k x k`` block of the
    largest order's ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` (Eq. 41) and the
    leading ``k`` columns of ``E_p^T P D^{1/2}`` (Eq. 43), so both are formed
    once. Each order then costs its real eigenproblem (Eq. 42,
    :func:`modal.era.real_eigensystem`) and the inverse of its eigenvector
    matrix; complex shapes and modal histories (:func:`modal.era.complex_poles`),
    frequencies, damping, MPC and MAMC (:func:`modal.era.pole_indicators`)
    follow for all poles of all orders at once, as :func:`modal.era.realise`
    gives them order by order.

    Returns
    -------
    table : dict of ndarray
        ``order``, ``freq_hz``, ``damping``, ``mpc``, ``mamc``, ``real_pole``,
        one entry per pole, by order and then by frequency.
    pole_shapes : ndarray, shape (n_poles, l)
    """
    if not orders:
        empty = np.empty(0)
        return ({"order": np.empty(0, dtype=int), "freq_hz": empty, "damping": empty, "mpc": empty, "mamc": empty,
                 "real_pole": np.empty(0, dtype=bool)}, np.empty((0, l)))
    phi, output, states = realisation(p[:, :orders[-1]], d[:orders[-1]], qt[:orders[-1]], h1, l)  # Eqs. (41), (43)
    # every order's real eigensystem side by side, then one pass over all poles;
    # LAPACK reads Fortran order, so each block is then copied without a transpose
    phi, states = np.asfortranarray(phi), np.ascontiguousarray(states)
    n = sum(orders)
    wr, wi = np.empty(n), np.empty(n)
    real_shapes, real_histories = np.empty((l, n)), np.empty((n, states.shape[1]))
    end = 0
    for done, k in enumerate(orders, 1):
        block = slice(end, end + k)
        wr[block], wi[block], real_shapes[:, block], real_histories[block] = real_eigensystem(
            phi[:k, :k], output[:, :k], states[:k])  # Eq. (42)
        end += k
        if progress is not None:
            progress(done, len(orders))
    z, real, complex_shapes, histories, kept = complex_poles(wr, wi, real_shapes, real_histories)
    order = np.repeat(orders, orders)[kept]
    poles = pole_indicators(z, real, complex_shapes, histories, dt, m)
    by = np.lexsort((poles["omega"], order))  # stable: ties keep realise()'s order
    table = {
        "order": order[by],
        "freq_hz": poles["omega"][by] / (2 * np.pi),
        "damping": poles["damping"][by],
        "mpc": poles["mpc"][by],
        "mamc": poles["mamc"][by],
        "real_pole": poles["real_pole"][by],
    }
    return table, poles["shapes"][:, by].T


def _stability(table, pole_shapes, criteria) -> dict:
    """Compare each pole with the nearest-frequency pole of the next lower
    order (the first such pole on ties); poles of the lowest order, or whose
    lower order has no pole, are not stable."""
    order, f, zeta = table["order"], table["freq_hz"], table["damping"]
    n = len(order)
    nearest = np.full(n, -1)
    bounds = np.flatnonzero(np.diff(order)) + 1
    starts = np.concatenate([[0], bounds])
    ends = np.concatenate([bounds, [n]])
    for i in range(1, len(starts)):
        lo, hi, lo0, hi0 = starts[i], ends[i], starts[i - 1], ends[i - 1]
        if order[lo0] == order[lo] - 2:
            nearest[lo:hi] = lo0 + np.argmin(np.abs(f[lo:hi, None] - f[None, lo0:hi0]), axis=1)
    has = nearest >= 0
    near = np.where(has, nearest, 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        stable_freq = has & (np.abs(f - f[near]) <= criteria.freq_rtol * f)
        stable_damping = has & (np.abs(zeta - zeta[near]) <= criteria.damping_rtol * np.abs(zeta[near]))
    stable_shape = has & (paired_mac(pole_shapes.T, pole_shapes[near].T) >= criteria.mac_min)
    stable = stable_freq & stable_damping & stable_shape
    return {"stable_freq": stable_freq, "stable_damping": stable_damping, "stable_shape": stable_shape, "stable": stable}


def _select_modes(poles: dict, pole_shapes: np.ndarray, cluster_distance: float, min_poles: int):
    """Cluster the stable physical poles (average linkage, scipy.cluster) by
    frequency and shape into modes; ``poles`` maps the pole columns to arrays."""
    from scipy.cluster.hierarchy import fcluster, linkage
    from scipy.spatial.distance import squareform

    labels = np.zeros(len(poles["order"]), dtype=int)
    candidates = np.flatnonzero(poles["stable"] & poles["physical"])
    if len(candidates) < max(2, min_poles):
        return labels, _no_modes(), np.empty((pole_shapes.shape[1], 0))
    f = poles["freq_hz"][candidates]
    shapes = pole_shapes[candidates].T
    distance = np.abs(f[:, None] - f[None, :]) / np.maximum(f[:, None], f[None, :]) + 1 - mac(shapes, shapes)
    distance = np.clip((distance + distance.T) / 2, 0, None)
    np.fill_diagonal(distance, 0)
    clusters = fcluster(linkage(squareform(distance, checks=False), method="average"), cluster_distance, "distance")
    members = np.flatnonzero(np.bincount(clusters)[clusters] >= min_poles)  # of the clusters that are modes
    if not len(members):
        return labels, _no_modes(), np.empty((pole_shapes.shape[1], 0))
    _, cluster = np.unique(clusters[members], return_inverse=True)
    group = {name: poles[name][candidates[members]] for name in ("freq_hz", "damping", "mpc", "mamc")}
    # modes numbered by mean frequency
    mode = np.argsort(np.argsort(np.bincount(cluster, group["freq_hz"]) / np.bincount(cluster), kind="stable"))[cluster]
    labels[candidates[members]] = mode + 1
    count = np.bincount(mode)
    mean = {name: np.bincount(mode, values) / count for name, values in group.items()}
    with np.errstate(invalid="ignore", divide="ignore"):  # a one-pole mode (min_poles = 1) has no std
        std = {name: np.sqrt(np.bincount(mode, (group[name] - mean[name][mode]) ** 2) / (count - 1))
               for name in ("freq_hz", "damping")}
    modes = pd.DataFrame({
        "mode": np.arange(1, len(count) + 1), "freq_hz": mean["freq_hz"], "freq_std_hz": std["freq_hz"],
        "damping": mean["damping"], "damping_std": std["damping"], "n_poles": count, "mpc": mean["mpc"],
        "mamc": mean["mamc"],
    })
    # each mode's medoid: the member with the least distance summed over its mode (the first on ties)
    spread = np.where(mode[:, None] == mode[None, :], distance[np.ix_(members, members)], 0).sum(axis=1)
    medoids = members[np.lexsort((spread, mode))[np.cumsum(count) - count]]
    return labels, modes, shapes[:, medoids]


def _no_modes() -> pd.DataFrame:
    return pd.DataFrame({c: pd.Series(dtype=float) for c in MODE_COLUMNS})


def _mean_spectrum(y, dt, min_bins=4096):
    """Root-mean-square amplitude spectrum over data sets and channels.

    The data are tapered by the falling half of a Hann window (for
    correlation functions this is the Blackman-Tukey spectral estimate;
    for a free decay it hides the cut at the end) and zero-padded to at
    least ``min_bins`` frequencies, so short records give smooth curves.

    The power summed over the ``m l`` series is the DFT of their summed
    autocorrelation (Wiener-Khinchin); when the padded length is at least
    ``2 n - 1`` there is no wrap-around, so the autocorrelation comes from
    short FFTs and the fine spectrum from one long FFT instead of ``m l``.
    """
    m, n, l = y.shape
    taper = np.hanning(2 * n)[n:]
    x = (y * taper[None, :, None]).transpose(1, 0, 2).reshape(n, m * l)
    n_fft = max(n, 2 * min_bins)
    if n_fft >= 2 * n - 1:
        short = scipy.fft.next_fast_len(2 * n - 1, real=True)
        acf = scipy.fft.irfft(np.sum(np.abs(scipy.fft.rfft(x, n=short, axis=0)) ** 2, axis=1), n=short)
        circular = np.zeros(n_fft)
        circular[:n] = acf[:n]  # lags 0 ... n - 1
        circular[n_fft - n + 1:] = acf[short - n + 1:]  # lags -(n - 1) ... -1
        power = np.clip(scipy.fft.rfft(circular).real, 0, None)
    else:
        power = np.sum(np.abs(scipy.fft.rfft(x, n=n_fft, axis=0)) ** 2, axis=1)
    return scipy.fft.rfftfreq(n_fft, dt), np.sqrt(power / (m * l)) / n
