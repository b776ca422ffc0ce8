"""Stabilisation diagram and automatic mode selection for ERA (thesis Ch. 4)
on measured data: impulse or free-decay responses, or the NExT correlation
functions of an ambient record (:func:`modal.correlations`).

Every model order comes from one decomposition of ``H(0)`` (Eq. 35): the
realisation of order ``k`` keeps the ``k`` largest singular triplets (Sec.
4.4), i.e. the first ``k`` columns of ``P``, entries of ``D`` and rows of
``Q^T``, so order ``k`` is a truncation of order ``max_order``
(:func:`modal.identification.decompose`, :func:`modal.identification._era.realise`).
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
from ._result import ModalWarning, normalise_shapes

POLE_COLUMNS = ["order", "freq_hz", "damping", "mpc", "mamc", "real_pole",
                "stable_freq", "stable_damping", "stable_shape", "stable"]
MODE_COLUMNS = ["mode", "freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std", "damping_spread",
                "n_poles", "mpc", "mamc", "mpd", "close", "close_mac", "second_freq_hz", "second_damping", "flag"]
CANDIDATE_COLUMNS = ["freq_hz", "damping", "n_poles", "min_poles", "mpc", "mamc", "mpd"]
ABOVE_COLUMNS = ["freq_hz", "n_poles"]
#: The median absolute deviation times this is a standard deviation for normal scatter.
MAD_SCALE = 1.4826
#: Two shapes whose ``1 - MAC`` is below this are one shape, whatever their scatter (one channel: MAC 1).
SAME_SHAPE_ATOL = 1e-9
#: A mode is doubted for living in one channel only when there are at least this many: of two sensors, one
#: near a node of a real mode is common (simulated chains with two sensors flagged real modes).
MIN_CHANNELS_ALIKE = 3
QUANTITIES = {"displacement": 0, "velocity": 1, "acceleration": 2}
#: A side band lies within its half-power half-width ``zeta f`` of ``f_p +- f_m``, the damping ratio taken within
#: these bounds (a side band's own damping is no physical quantity: 0.01 % would ask for an exact coincidence).
SIDE_BAND_ZETA = (0.001, 0.1)
#: How the flag of the weaker of two modes of one shape and one resonance begins (:func:`_flags`); the
#: spectral witness leaves a pair so decided alone (:func:`modal.measured.with_spectral_witness`).
SAME_SHAPE = "same shape as"
#: How a damping flagged above the record's median reads (:func:`_flags`); a mode with a spectral peak of its
#: own keeps no such reason (:func:`modal.measured.with_spectral_witness`): a heavily damped real mode.
DAMPED_ABOVE = "implausibly high"
#: How the flag of a broad mode that two sharper ones within its half-power band explain begins (:func:`blends`).
BLEND = "blend of"
#: The default block columns keep ``H(0)`` within this many bytes (512 MB), so a
#: long free decay or impulse response is not copied whole into a Hankel matrix.
HANKEL_MAX_BYTES = 512 * 2**20


@dataclass(frozen=True)
class StabilityCriteria:
    """Thresholds of the stabilisation diagram and of the mode selection.

    Attributes
    ----------
    freq_rtol : float
        A pole is stable in frequency when it is within this relative
        distance of the nearest pole of the next lower order. Poles stable in
        frequency (and physical) are the ones clustered into modes.
    damping_rtol : float
        In the diagram, a pole is stable in damping when its damping ratio is
        within this relative distance of that pole's (the selection judges
        damping against the mode's own scatter instead: ``scatter_k``).
    mac_min : float
        In the diagram, a pole is stable in shape when the MAC with that pole
        is at least this. In the selection, a mode's pole keeps its place when
        ``1 - MAC`` with the mode's shape is within ``scatter_k`` robust
        standard deviations above the mode's median, or at most ``1 - mac_min``.
    scatter_k : float
        How many robust standard deviations (1.4826 times the median absolute
        deviation) of a mode's own damping and shape scatter a pole may lie
        from its median: damping and shape are judged against the mode's own
        scatter, not a fixed tolerance between consecutive orders. Damping
        within ``cluster_distance`` (absolute, the resolution of the
        clustering) of the median always passes.
    max_damping : float
        Physical poles have ``0 < damping < max_damping`` (a growing
        component, ``damping <= 0``, is never a mode).
    mpc_min, mamc_min : float
        Minimum modal phase collinearity and modal amplitude coherence. The
        default ``mpc_min = 0`` lets complex modes (non-proportional damping,
        MPC well below 1) through: their complexity is measured (``mpc``,
        ``mpd``) and reported, not held against them.
    cluster_distance : float
        Poles join one mode when the distance ``|lambda_i - lambda_j| /
        max(|lambda_i|, |lambda_j|) + 1 - MAC_ij`` between the groups (average
        linkage) is below this, ``lambda`` the continuous-time poles
        (Reynders, Houbrechts and De Roeck 2012): the first term is about
        ``sqrt((df / f)^2 + (d zeta)^2)``, so poles of one frequency but
        damping ratios 2 % apart are 0.02 apart. Two poles of the same order
        never join one mode.
    merge_distance : float
        Clusters that never share an order (one mode split in two) join when
        their average distance is below this.
    min_poles : int, optional
        A cluster with fewer poles is not a mode but a candidate; default
        40 % of the orders computed, at least 3 (a single channel makes every
        MAC 1, so spurious poles near a mode are told apart only by how
        rarely they recur).
    close_rtol : float
        Two modes within this relative frequency distance are flagged
        ``close`` (with the MAC between their shapes).
    doubtful_mpc : float
        A mode whose MPC is below this is flagged ``low MPC`` (Pappa, Elliott
        and Schenk 1993: the phases of a lightly damped structural mode are
        nearly collinear; noise and harmonics are not).
    doubtful_mamc : float
        A mode whose MAMC is below this is flagged ``low MAMC``: its modal
        history does not follow one decaying exponential (Pappa, Elliott and
        Schenk 1993's EMAC; side bands and noise fall short).
    damping_factor : float
        A mode whose damping ratio is more than this factor below or above
        the median of the record's modes is flagged ``damping ... implausibly low``
        (or ``high``).
    single_channel_share : float
        A mode of a record of three channels or more whose largest channel
        holds at least this share of the shape's energy (``|phi_c|^2 / sum |phi|^2``,
        each channel's entry over that channel's RMS, both in one quantity
        (:func:`channel_levels`), so that units, levels and quantities do not
        count) is flagged ``single channel``.
    """

    freq_rtol: float = 0.01
    damping_rtol: float = 0.05
    mac_min: float = 0.98
    max_damping: float = 0.3
    mpc_min: float = 0.0
    mamc_min: float = 0.5
    cluster_distance: float = 0.02
    merge_distance: float = 0.04
    min_poles: int | None = None
    close_rtol: float = 0.02
    scatter_k: float = 3.0
    doubtful_mpc: float = 0.7
    doubtful_mamc: float = 0.95
    damping_factor: float = 5.0
    single_channel_share: float = 0.95

    def __post_init__(self):
        for name in ("freq_rtol", "damping_rtol", "max_damping", "cluster_distance", "merge_distance", "close_rtol",
                     "scatter_k"):
            positive_float(name, getattr(self, name))
        if positive_float("damping_factor", self.damping_factor) <= 1:
            raise ValueError(f"damping_factor must be above 1, got {self.damping_factor}")
        for name in ("mac_min", "mpc_min", "mamc_min", "doubtful_mpc", "doubtful_mamc", "single_channel_share"):
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
        ``damping`` (ratio; means over the mode's poles), ``freq_std_hz`` and
        ``damping_std`` (the standard deviation of the estimate, from the
        ``segments`` of :func:`stabilisation`; NaN without them),
        ``freq_spread_hz`` and ``damping_spread`` (the spread of the mode's
        poles over the model orders: not an uncertainty), ``n_poles`` (poles
        clustered into it, at most one per order), mean ``mpc``, ``mamc`` and
        ``mpd`` (mean phase deviation, degrees), ``close`` (another mode lies
        within ``criteria.close_rtol`` in frequency) and ``close_mac`` (MAC
        with the nearest mode in frequency; NaN for a single mode),
        ``second_freq_hz`` and ``second_damping`` (a second estimate of the
        same mode: a cluster of the same shape, at the same orders, within
        ``criteria.merge_distance``; NaN when none), ``flag`` (why the mode is
        doubtful, reasons separated by ``"; "``: ``low MPC 0.41``, ``damping
        0.05 % implausibly low (median 1.5 %)``, ``single channel``; empty when the
        mode is trusted; see :attr:`trusted_modes`).
    shapes : ndarray, shape (n_channels, n_modes)
        Representative shape of each mode, real and normalised: that of its
        medoid pole rotated onto the real axis.
    complex_shapes : ndarray, shape (n_channels, n_modes)
        The same shapes as identified, complex (unit norm, largest entry real
        and positive): the phases of a complex mode are kept.
    candidates : pandas.DataFrame
        Clusters of stable physical poles that recur too rarely to be modes
        (fewer than ``min_poles`` poles, at least half of them): ``freq_hz``,
        ``damping``, ``n_poles``, ``min_poles``, ``mpc``, ``mamc``, ``mpd``.
    poles : pandas.DataFrame
        One row per pole of every order: ``order``, ``freq_hz``, ``damping``,
        ``mpc``, ``mamc``, ``real_pole``, the stability flags ``stable_freq``,
        ``stable_damping``, ``stable_shape``, ``stable`` (all three),
        ``physical`` (the quality criteria) and ``mode`` (0 when unselected).
    pole_shapes : ndarray, shape (n_poles, n_channels)
        Complex normalised shape of every pole.
    singular_values : ndarray
        Singular values of ``H(0)``.
    spectrum_hz, spectrum : ndarray
        Mean amplitude spectrum of the data, drawn behind the diagram.
    criteria : StabilityCriteria
    notes : tuple of str
        What the selection decided beyond the modes table, one sentence each,
        for a log: doubtful modes and why, second estimates, candidates (how
        many poles they have, how many a mode needs) and clusters above
        ``fmax`` left out.
    """

    modes: pd.DataFrame
    shapes: np.ndarray
    poles: pd.DataFrame
    pole_shapes: np.ndarray
    singular_values: np.ndarray
    spectrum_hz: np.ndarray
    spectrum: np.ndarray
    criteria: StabilityCriteria = field(default_factory=StabilityCriteria)
    complex_shapes: np.ndarray = field(default_factory=lambda: np.empty((0, 0), dtype=complex))
    candidates: pd.DataFrame = field(default_factory=lambda: _empty(CANDIDATE_COLUMNS))
    notes: tuple = ()

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
        stable = poles["stable_freq"].to_numpy()
        candidates = stable & poles["physical"].to_numpy()
        found = f"{len(poles)} poles over {n_orders} orders, {int(stable.sum())} stable in frequency"
        if n_orders < 2:
            return (f"{len(poles)} poles at one model order ({int(poles['order'].iloc[0])}): stability is judged "
                    "between consecutive orders, so a mode needs poles at two or more: raise --max-order "
                    "(max_order); a structure with n modes in the band needs orders well above 2 n")
        if not stable.any():
            return (f"{found}: no pole recurs from one order to the next (within {criteria.freq_rtol:.0%} in "
                    "frequency), as for a record of noise alone. What could help: check that the record holds the "
                    "response of the structure; with a known band, --fmax (and --highpass against a drift); more "
                    "samples")
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
        if len(self.candidates):  # the clusters themselves, by size
            largest = self.candidates.loc[self.candidates["n_poles"].idxmax()]
            near, size = largest["freq_hz"], int(largest["n_poles"])
        else:
            f = np.sort(poles["freq_hz"].to_numpy()[candidates])
            group = max(np.split(f, np.flatnonzero(np.diff(f) > criteria.cluster_distance * f[1:]) + 1), key=len)
            near, size = group.mean(), len(group)
        return (f"{found}, {int(candidates.sum())} of them physical, but no cluster of them recurs at enough "
                f"orders: the largest group (near {near:.4g} Hz) has {size} poles, a mode needs "
                f"{min_poles} ({'set' if criteria.min_poles else '40 % of the orders'}). Noise alone gives such "
                "scattered poles; if the record holds the structure's response, what could help: a longer "
                "record (ambient: more averaging steadies the poles); --rows so that the Hankel matrix spans a few "
                "periods of the lowest mode. (A higher --max-order computes more orders but also needs more.)")

    @property
    def trusted_modes(self) -> pd.DataFrame:
        """The modes without a ``flag``: those to print and to believe
        without a second look (the others stay in :attr:`modes`)."""
        return self.modes[self.modes["flag"] == ""]

    def plot(self, fmax=None, title=None, ax=None):
        """The stabilisation diagram; see :func:`modal.stabilisation_figure`."""
        from ._figures import stabilisation_figure  # matplotlib only when drawn

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
    quantities=None,
    segments=None,
) -> Stabilisation:
    """ERA at every even model order ``2 ... max_order`` from one SVD,
    stability between orders, and modes selected by clustering.

    With ``segments`` (the same data computed from ``K`` non-overlapping
    parts of the record, e.g. their correlation functions), each mode's
    frequency and damping get the standard deviation of their estimate
    (:func:`segment_std`).

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
        Block columns ``s``; by default every sample the data allow, at most
        as many as keep ``H(0)`` within :data:`HANKEL_MAX_BYTES`.
    start : int
        First sample (Eq. 34's ``k - 1``), e.g. :func:`modal.decay_start`.
    fmax : float, optional
        Modes are selected below this frequency (Hz) only; poles above it
        stay in ``poles``.
    criteria : StabilityCriteria, optional
    progress : callable, optional
        Called as ``progress(done, total)`` after each order.
    quantities : sequence of str, optional
        What each channel measures: ``"displacement"``, ``"velocity"`` or
        ``"acceleration"``; the shapes are then in the first channel's
        quantity (:func:`modal.identification._era.pole_indicators`). Default: all the same.
    segments : sequence of array_like, optional
        ``K >= 2`` data sets shaped like ``y``, from non-overlapping parts of
        the record: ``freq_std_hz`` and ``damping_std`` of each mode.

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
    derivatives = _derivatives(quantities, l)
    if cols is None:
        cols = n_samples - start - rows
        if cols < 1:
            raise ValueError(f"rows = {rows} from start = {start} leaves no column of the {n_samples}-sample data")
        cols = min(cols, max(1, HANKEL_MAX_BYTES // (8 * (rows + 1) * l * m)))
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
    table, pole_shapes = _poles(p, d, qt, h1, orders, l, m, dt, progress, derivatives)
    table.update(_stability(table, pole_shapes, criteria))
    limit = 0.5 / dt if fmax is None else fmax
    with np.errstate(invalid="ignore"):
        quality = (
            ~table["real_pole"]
            & (table["damping"] > 0)
            & (table["damping"] < criteria.max_damping)
            & (table["mpc"] >= criteria.mpc_min)
            & (table["mamc"] >= criteria.mamc_min)
        )
    table["physical"] = quality & (table["freq_hz"] < limit)
    min_poles = criteria.min_poles or max(3, math.ceil(0.4 * len(orders)))
    table["mode"], modes, complex_shapes, candidates, above = _select_modes(
        table, pole_shapes, criteria, min_poles, quality=quality, limit=limit,
        channel_levels=channel_levels(y[:, start:], dt, derivatives))
    if segments is not None and len(modes):
        modes["freq_std_hz"], modes["damping_std"] = segment_std(
            segments, p, table, modes, rows, cols, start, l, dt)
    poles = pd.DataFrame({name: table[name] for name in POLE_COLUMNS + ["physical", "mode"]})
    spectrum_hz, spectrum = _mean_spectrum(y[:, start:], dt)
    notes = _notes(modes, candidates, above, fmax)
    result = Stabilisation(modes, normalise_shapes(complex_shapes), poles, pole_shapes, sv, spectrum_hz, spectrum,
                           criteria, complex_shapes, candidates, notes)
    if modes.empty:
        warnings.warn(f"no mode selected: {result.no_mode_reason()}", ModalWarning, stacklevel=2)
    return result


def _poles(p, d, qt, h1, orders, l, m, dt, progress=None, derivatives=None):
    """Poles of every order in ``orders``, each realised from the leading
    ``order`` triplets of ``P D Q^T`` (Sec. 4.4), as :func:`modal.identification._era.realise`
    would give them order by order.

    The realisation of order ``k`` is the leading ``k x k`` block of the
    largest order's ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` (Eq. 41) and the
    leading ``k`` columns of ``E_p^T P D^{1/2}`` (Eq. 43), so both are formed
    once. Each order then costs its real eigenproblem (Eq. 42,
    :func:`modal.identification._era_kernels.real_eigensystem`) and the
    inverse of its eigenvector matrix; complex shapes and modal histories
    (:func:`modal.identification._era_kernels.complex_poles`), frequencies,
    damping, MPC and MAMC (:func:`modal.identification._era.pole_indicators`)
    follow for all poles of all orders at once, as
    :func:`modal.identification._era.realise` gives them order by order.

    Returns
    -------
    table : dict of ndarray
        ``order``, ``freq_hz``, ``damping``, ``mpc``, ``mamc``, ``real_pole``,
        one entry per pole, by order and then by frequency.
    pole_shapes : ndarray, shape (n_poles, l)
        Complex, normalised.
    """
    if not orders:
        empty = np.empty(0)
        return ({"order": np.empty(0, dtype=int), "freq_hz": empty, "damping": empty, "mpc": empty, "mamc": empty,
                 "mpd": empty, "real_pole": np.empty(0, dtype=bool)}, np.empty((0, l), dtype=complex))
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
    poles = pole_indicators(z, real, complex_shapes, histories, dt, m, derivatives)
    by = np.lexsort((poles["omega"], order))  # stable: ties keep realise()'s order
    table = {
        "order": order[by],
        "freq_hz": poles["omega"][by] / (2 * np.pi),
        "damping": poles["damping"][by],
        "mpc": poles["mpc"][by],
        "mamc": poles["mamc"][by],
        "mpd": poles["mpd"][by],
        "real_pole": poles["real_pole"][by],
    }
    return table, poles["complex_shapes"][:, by].T


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


def segment_std(segments, p, poles: dict, modes: pd.DataFrame, rows, cols, start, l, dt):
    """Standard deviation of each mode's frequency and damping estimates from
    ``K`` segments of the record.

    The full record's observability subspace is kept: ``U`` the leading
    left singular vectors of its ``H(0)`` (Eq. 35) at the highest order
    among the mode's poles (the fullest model that holds it; a low order's
    basis leaves other modes out, and the segments' eigenvalues then scatter
    with that bias), from its pole there nearest the mode's mean frequency.
    With ``H_k(0)``, ``H_k(1)`` built from segment ``k`` as in Eq. (34),
    ``A_k = (U^T H_k(1)) (U^T H_k(0))^+`` is segment ``k``'s state matrix in
    that basis (``U^T H(0) = T C`` and ``U^T H(1) = T A C`` for an exact
    model, so ``A_k = T A T^-1``); its eigenvalues (Eq. 44, in ``s = ln z /
    dt``), matched one to one to the poles of the modes of that order
    (:func:`matched_eigenvalues`), give the segment's frequencies and
    dampings. The segments' estimates scatter with the record's noise; the
    standard deviation of their mean, ``std_k / sqrt(K)``, is that of the
    estimate from the whole record, widened by Student's ``t_{K-1}(0.975) /
    1.96``. A record of length ``T`` also carries a bias, which grows as it
    shortens (the correlations' random error at the late lags reads as too
    little decay): segments of ``T / K`` carry about ``K`` times the
    record's, so ``b = (mean_k theta_k - theta) / (K - 1)``, ``theta`` the
    record's own estimate at that order (the seed pole), estimates it
    (Quenouille's split-sample reasoning), and the standard deviation
    returned is the root-mean-square error ``sqrt(s^2 + b^2)``, ``s`` the
    widened standard deviation of the mean. ``K`` counts, per mode, the
    segments that gave an estimate (a
    segment whose state matrix has no finite ``ln z``, e.g. a lone pulse, or
    whose ``U^T H_k(0)`` is exactly singular, gives none); NaN where fewer
    than two did.

    Modes whose fullest model has the same order share that order's state
    matrix: each segment solves and decomposes ``A_k`` once per distinct
    order (usually one, ``max_order``), not once per mode.

    Returns
    -------
    freq_std_hz, damping_std : ndarray, shape (n_modes,)
    """
    from scipy.linalg import solve_triangular

    segments = [records("segments", s) for s in segments]
    k_seg = len(segments)
    n_modes = len(modes)
    if k_seg < 2:
        return np.full(n_modes, np.nan), np.full(n_modes, np.nan)
    labels, f_pole, order = poles["mode"], poles["freq_hz"], poles["order"]
    seeds = []
    for number, f in zip(modes["mode"], modes["freq_hz"]):
        members = np.flatnonzero(labels == number)
        members = members[order[members] == order[members].max()]  # the fullest model that holds the mode
        r = members[np.argmin(np.abs(f_pole[members] - f))]
        omega, zeta = 2 * np.pi * f_pole[r], poles["damping"][r]
        seeds.append((int(order[r]), omega * complex(-zeta, np.sqrt(max(1 - zeta**2, 0.0)))))
    n_max = max(n for n, _ in seeds)
    seed_s = np.array([s0 for _, s0 in seeds])
    u = p[:, :n_max]
    by_order = {}  # the modes of each fullest order: one state matrix per segment and order
    for j, (n, _) in enumerate(seeds):
        by_order.setdefault(n, []).append(j)
    freq, damping = np.full((k_seg, n_modes), np.nan), np.full((k_seg, n_modes), np.nan)
    for k, segment in enumerate(segments):
        # g0 = U^T H_k(0) and g1 = U^T H_k(1) from one product: H_k(1) is H_k(0) one block column on
        g = u.T @ hankel(segment, rows, cols + 1, start)
        m = segment.shape[0]
        g0, g1 = g[:, :-m], g[:, m:]
        # g0^T = Q R, so g0[:n]^+ = Q[:, :n] R[:n, :n]^-T for every n, and A_k^T = R[:n, :n]^-1 (g1 Q)[:n, :n]^T
        q, r = np.linalg.qr(g0.T)
        w = g1 @ q
        for n, modes_n in by_order.items():
            try:
                a_t = solve_triangular(r[:n, :n], w[:n, :n].T)
            except np.linalg.LinAlgError:  # the segment's H_k(0) has lost rank in that basis: no eigenvalue
                continue
            z = np.linalg.eigvals(a_t)
            with np.errstate(divide="ignore", invalid="ignore"):
                s = np.log(z.astype(complex)) / dt
            near = matched_eigenvalues(s, seed_s[modes_n])
            freq[k, modes_n] = np.abs(near) / (2 * np.pi)
            damping[k, modes_n] = -near.real / np.abs(near)
    from scipy.special import ndtri, stdtrit  # the quantiles of scipy.stats' norm and t, without their overhead

    # K per mode: the segments that gave an estimate
    k_est = np.sum(np.isfinite(freq), axis=0)
    known = k_est >= 2
    k = k_est[known]
    scale = stdtrit(k - 1, 0.975) / ndtri(0.975) / np.sqrt(k)
    record = seed_s[known]  # the record's own estimate at the same order
    freq_std, damping_std = np.full(n_modes, np.nan), np.full(n_modes, np.nan)
    for out, estimates, own in ((freq_std, freq, np.abs(record) / (2 * np.pi)),
                                (damping_std, damping, -record.real / np.abs(record))):
        bias = (np.nanmean(estimates[:, known], axis=0) - own) / (k - 1)
        out[known] = np.hypot(np.nanstd(estimates[:, known], axis=0, ddof=1) * scale, bias)
    return freq_std, damping_std


def matched_eigenvalues(eigenvalues, seeds) -> np.ndarray:
    """The eigenvalue of a segment's state matrix that estimates each of the
    record's poles ``seeds``: one to one, nearest in all (the assignment of
    least summed distance ``|s - s_0|``, :func:`scipy.optimize.linear_sum_assignment`),
    NaN for a seed left without one (fewer finite eigenvalues than seeds).

    Each eigenvalue is one mode's: two close modes (resonances that overlap)
    never take the same one. Each seed's nearest eigenvalue alone gave both
    modes of a pair 0.8 % apart the one between them in some segments, so
    their segments scattered too little: the damping's ``±1.96 std`` covered
    the true damping of 76 % of such modes in 2-minute records
    (``bench_selection.py``, seed 1; 97 % one to one).

    Parameters
    ----------
    eigenvalues : array_like of complex
        ``s = ln z / dt`` of the segment's state matrix (non-finite ones are
        left out).
    seeds : array_like of complex, shape (n_seeds,)
        The record's own poles (``s``) of the modes.

    Returns
    -------
    ndarray of complex, shape (n_seeds,)
    """
    from scipy.optimize import linear_sum_assignment

    eigenvalues, seeds = np.asarray(eigenvalues, dtype=complex), np.asarray(seeds, dtype=complex)
    eigenvalues = eigenvalues[np.isfinite(eigenvalues)]
    matched = np.full(seeds.shape, np.nan, dtype=complex)
    which, taken = linear_sum_assignment(np.abs(seeds[:, None] - eigenvalues[None, :]))  # none if either is empty
    matched[which] = eigenvalues[taken]
    return matched


def _select_modes(poles: dict, pole_shapes: np.ndarray, criteria: StabilityCriteria, min_poles: int, quality=None,
                  limit=np.inf, channel_levels=None):
    """Cluster the physical poles stable in frequency into modes, judge each
    pole's damping and shape against its mode's own scatter, state a second
    estimate of one mode once, and flag doubtful modes.

    1. The poles clustered are those stable in frequency between consecutive
       orders (``poles["stable_freq"]``) that pass the quality criteria
       (``quality``, default ``poles["physical"]``): damping and shape may
       scatter from order to order, as they do in ambient records, without
       keeping a real mode out (Peeters and De Roeck 2001 use frequency
       stability alone to build the diagram; Magalhães, Cunha and Caetano 2009
       cluster all poles).
    2. Average linkage (scipy.cluster) on ``|lambda_i - lambda_j| /
       max(|lambda_i|, |lambda_j|) + 1 - MAC_ij`` (``lambda`` the
       continuous-time poles, ``|lambda| = 2 pi f``: frequency and damping
       together; Reynders, Houbrechts and De Roeck 2012), cut at
       ``criteria.cluster_distance``, with two poles of the same order kept
       apart (their distance is raised above what any average can absorb):
       two close modes present at the same orders stay two. Clusters that
       never share an order and lie within ``criteria.merge_distance`` of
       each other are one mode split in two, and join.
    3. In each cluster, a pole whose damping lies more than
       ``criteria.scatter_k`` robust standard deviations (1.4826 x the median
       absolute deviation) from the cluster's median damping (and beyond
       ``criteria.cluster_distance`` of it), or whose ``1 - MAC`` with the
       cluster's medoid lies more than that above their median (and beyond
       ``1 - criteria.mac_min``), leaves it (label 0).
    4. Clusters of at least ``min_poles`` poles below ``limit`` (Hz) are
       modes; those above are reported apart; smaller ones of at least half
       as many (and two) are candidates.
    5. A mode with fewer poles than another whose shape it shares (the
       median ``1 - MAC`` between their poles within the larger of the two
       clusters' own scatter, :func:`_shape_scatter`) and whose frequency
       lies within the half-power half-width (``zeta f``) of either is the
       same physical mode estimated twice at the same orders: it becomes that mode's ``second_freq_hz`` and
       ``second_damping``, its poles carry that mode's number. Modes of
       different shapes, however close, stay apart.
    6. Modes are numbered by frequency and flagged (:func:`_flags`;
       ``channel_levels``: each channel's RMS in one quantity,
       :func:`channel_levels`, default ones).

    Returns the pole labels (mode number, 0 for none), the modes table, the
    modes' complex shapes (medoids), the candidates table and the clusters
    above ``limit`` that would have been modes (``freq_hz``, ``n_poles``).
    """
    from scipy.cluster.hierarchy import fcluster, linkage
    from scipy.spatial.distance import squareform

    l = pole_shapes.shape[1]
    labels = np.zeros(len(poles["order"]), dtype=int)
    quality = poles["physical"] if quality is None else quality
    chosen = np.flatnonzero(poles["stable_freq"] & quality)
    if len(chosen) < 2:
        return (labels, _empty(MODE_COLUMNS), np.empty((l, 0), dtype=complex), _empty(CANDIDATE_COLUMNS),
                _empty(ABOVE_COLUMNS))
    f, order, zeta = poles["freq_hz"][chosen], poles["order"][chosen], poles["damping"][chosen]
    shapes = pole_shapes[chosen].T
    # the continuous-time poles over their natural frequency: unit complex numbers fixed by the damping ratio
    unit_pole = -zeta + 1j * np.sqrt(1 - zeta**2)
    pole = f * unit_pole
    macs = mac(shapes, shapes)
    distance = np.abs(pole[:, None] - pole[None, :]) / np.maximum(f[:, None], f[None, :]) + 1 - macs
    distance = np.clip((distance + distance.T) / 2, 0, None)
    np.fill_diagonal(distance, 0)
    apart = (order[:, None] == order[None, :]) & ~np.eye(len(chosen), dtype=bool)
    # one same-order pair in a merged group lifts its average above the cut
    linked = np.where(apart, 1.0 + criteria.cluster_distance * len(chosen) ** 2, distance)
    clusters = fcluster(linkage(squareform(linked, checks=False), method="average"), criteria.cluster_distance,
                        "distance")
    clusters = _join_split_clusters(clusters, order, distance, criteria.merge_distance)
    _, clusters = np.unique(clusters, return_inverse=True)
    n_clusters = clusters.max() + 1
    # each cluster's medoid: the member with the least distance summed over its cluster (the first on ties)
    spread = np.where(clusters[:, None] == clusters[None, :], distance, 0).sum(axis=1)
    first = np.lexsort((spread, clusters))
    medoids = first[np.searchsorted(clusters[first], np.arange(n_clusters))]
    misfit = 1 - macs[np.arange(len(chosen)), medoids[clusters]]
    member = _consistent(clusters, zeta, misfit, criteria)
    member[medoids] = True
    shape_scatter = _shape_scatter(clusters, member, macs, criteria.scatter_k)
    count = np.bincount(clusters[member], minlength=n_clusters)
    groups = {name: poles[name][chosen][member] for name in ("freq_hz", "damping", "mpc", "mamc", "mpd")}
    inner = clusters[member]
    mean = {name: np.bincount(inner, values, minlength=n_clusters) / count for name, values in groups.items()}
    below = mean["freq_hz"] < limit
    is_mode = (count >= min_poles) & below
    by_freq = np.argsort(mean["freq_hz"], kind="stable")  # the clusters by frequency, for the tables below
    is_above = ((count >= min_poles) & ~below)[by_freq]
    above = pd.DataFrame({"freq_hz": mean["freq_hz"][by_freq][is_above], "n_poles": count[by_freq][is_above]})
    is_candidate = (~is_mode & below & (2 * count >= min_poles) & (count >= 2))[by_freq]
    candidates = pd.DataFrame({name: values[by_freq][is_candidate] for name, values in (
        ("freq_hz", mean["freq_hz"]), ("damping", mean["damping"]), ("n_poles", count),
        ("min_poles", np.full(n_clusters, min_poles)), ("mpc", mean["mpc"]), ("mamc", mean["mamc"]),
        ("mpd", mean["mpd"]))})
    if not np.any(is_mode):
        return labels, _empty(MODE_COLUMNS), np.empty((l, 0), dtype=complex), candidates, above
    second_of = _second_estimates(np.flatnonzero(is_mode), count, mean["freq_hz"], mean["damping"], clusters, member,
                                  macs, shape_scatter)
    main = np.array([c for c in np.flatnonzero(is_mode) if c not in second_of], dtype=int)
    kept = main[np.argsort(mean["freq_hz"][main], kind="stable")]  # modes by frequency
    number = np.zeros(n_clusters, dtype=int)
    number[kept] = np.arange(1, len(kept) + 1)
    for duplicate, mode in second_of.items():
        number[duplicate] = number[mode]
    labels[chosen[member]] = number[inner]
    with np.errstate(invalid="ignore", divide="ignore"):  # a one-pole mode (min_poles = 1) has no std
        std = {name: np.sqrt(np.bincount(inner, (groups[name] - mean[name][inner]) ** 2, minlength=n_clusters)
                             / (count - 1)) for name in ("freq_hz", "damping")}
    stated = {}  # each mode's largest second estimate: second_of runs by size, largest first
    for duplicate, mode in second_of.items():
        stated.setdefault(mode, duplicate)
    second = [stated.get(c) for c in kept]
    mode_shapes = shapes[:, medoids[kept]]
    close, close_mac = _close_modes(mean["freq_hz"][kept], mode_shapes, criteria.close_rtol)
    columns = {
        "mode": np.arange(1, len(kept) + 1), "freq_hz": mean["freq_hz"][kept], "freq_std_hz": np.nan,
        "freq_spread_hz": std["freq_hz"][kept], "damping": mean["damping"][kept], "damping_std": np.nan,
        "damping_spread": std["damping"][kept], "n_poles": count[kept],
        "mpc": mean["mpc"][kept], "mamc": mean["mamc"][kept], "mpd": mean["mpd"][kept], "close": close,
        "close_mac": close_mac,
        "second_freq_hz": [np.nan if c is None else mean["freq_hz"][c] for c in second],
        "second_damping": [np.nan if c is None else mean["damping"][c] for c in second],
    }
    # each entry against its channel's level: the shapes are in one quantity (the first channel's), the levels in
    # another (the highest derivative), and converting one mode's entries between the two scales them all alike
    visible = np.abs(mode_shapes) / (np.ones(l) if channel_levels is None else channel_levels)[:, None]
    columns["flag"] = _flags(columns, visible, criteria, mac(mode_shapes, mode_shapes))
    modes = pd.DataFrame(columns)  # one frame with its flags: a column set afterwards costs half as much again
    return labels, modes, mode_shapes, candidates, above


def _consistent(clusters, zeta, misfit, criteria):
    """Which poles agree with their cluster's own scatter in damping and in
    shape (``misfit``: ``1 - MAC`` with the cluster's medoid): see
    :func:`_select_modes`, step 3. ``clusters`` numbers the clusters
    ``0 ... n - 1``, each with a pole."""
    k = criteria.scatter_k * MAD_SCALE
    n_clusters = clusters.max() + 1
    z_centre = _group_medians(clusters, zeta, n_clusters)[clusters]
    e_centre = _group_medians(clusters, misfit, n_clusters)[clusters]
    z_mad = _group_medians(clusters, np.abs(zeta - z_centre), n_clusters)[clusters]
    e_mad = _group_medians(clusters, np.abs(misfit - e_centre), n_clusters)[clusters]
    z_tol = np.maximum(k * z_mad, criteria.cluster_distance)
    e_tol = np.maximum(e_centre + k * e_mad, 1 - criteria.mac_min)
    return (np.abs(zeta - z_centre) <= z_tol) & (misfit <= e_tol)


def _shape_scatter(clusters, member, macs, scatter_k):
    """Per cluster, how far apart two of its member poles' shapes may lie:
    the median ``1 - MAC`` over its pairs of members plus ``scatter_k``
    robust standard deviations of it (0 for fewer than two members)."""
    n_clusters = clusters.max() + 1
    inside = np.flatnonzero(member)
    first, second = np.triu_indices(len(inside), 1)
    same = clusters[inside[first]] == clusters[inside[second]]  # the pairs of members of one cluster
    first, second = inside[first[same]], inside[second[same]]
    pair_cluster, pairs = clusters[first], 1 - macs[first, second]
    centre = _group_medians(pair_cluster, pairs, n_clusters)
    spread = _group_medians(pair_cluster, np.abs(pairs - centre[pair_cluster]), n_clusters)
    scatter = centre + scatter_k * MAD_SCALE * spread
    return np.where(np.bincount(pair_cluster, minlength=n_clusters) > 0, scatter, 0.0)


def _group_medians(groups, values, n_groups):
    """The median of ``values`` within each group ``0 ... n_groups - 1``
    (``groups``: each value's group), as :func:`numpy.median` gives it
    (the middle value, or the mean of the two middle ones), for all groups
    by one sort; NaN for a group without values. ``values`` are finite.

    Examples
    --------
    >>> _group_medians(np.array([0, 1, 0, 1, 1]), np.array([4.0, 1.0, 2.0, 3.0, 2.0]), 3)
    array([3., 2., nan])
    """
    counts = np.bincount(groups, minlength=n_groups)
    ranked = values[np.lexsort((values, groups))]  # by group, then by value
    starts = np.cumsum(counts) - counts
    lower, upper = starts + (counts - 1) // 2, starts + counts // 2  # one index twice for an odd count
    taken = counts > 0
    medians = np.full(n_groups, np.nan)
    medians[taken] = (ranked[lower[taken]] + ranked[upper[taken]]) / 2
    return medians


def _second_estimates(modes, count, freq, damping, clusters, member, macs, shape_scatter):
    """``{cluster: mode cluster}`` for each mode cluster that is a second
    estimate of a larger one (more poles; on ties the first), in order of
    size, largest first: the median
    ``1 - MAC`` between their poles within the larger shape scatter of the
    two (:func:`_shape_scatter`; at least :data:`SAME_SHAPE_ATOL`), and mean
    frequencies (``freq``) within the half-power half-width ``zeta f`` of
    either (``damping``: mean ratios), i.e. one resonance peak of one shape,
    not two. Each is paired with the nearest such mode in frequency; a mode
    that is itself a second estimate takes none."""
    second_of = {}
    by_size = sorted(modes, key=lambda c: -count[c])  # stable: ties keep cluster order
    for i, b in enumerate(by_size):
        in_b = member & (clusters == b)
        pair, nearest = None, np.inf
        for a in by_size[:i]:
            gap = abs(freq[a] - freq[b])
            if a in second_of or gap > max(damping[a] * freq[a], damping[b] * freq[b]) or gap >= nearest:
                continue
            between = np.median(1 - macs[np.ix_(member & (clusters == a), in_b)])
            if between <= max(shape_scatter[a], shape_scatter[b], SAME_SHAPE_ATOL):
                pair, nearest = a, gap
        if pair is not None:
            second_of[b] = pair
    return second_of


def _flags(modes, visible: np.ndarray, criteria: StabilityCriteria, mode_mac=None) -> list[str]:
    """Why each mode is doubtful (reasons joined by ``"; "``, empty when
    trusted); ``modes``: the modes table, or its columns (``freq_hz``,
    ``damping``, ``n_poles``, ``mpc``, ``mamc``) as a dict of arrays;
    ``visible`` (channels x modes): each shape entry's magnitude
    against its channel's level; ``mode_mac``: the MAC between the modes'
    shapes (default: none alike).

    - ``same shape as 4.224 Hz (MAC 0.999)``: another mode within
      ``criteria.close_rtol`` in frequency, or closer than the sum of the
      two modes' half-power half-widths ``zeta f`` (``zeta`` taken within
      :data:`SIDE_BAND_ZETA`: their resonances overlap), has more poles (or
      as many and a lower frequency) and a shape of MAC at least
      ``criteria.mac_min`` with this one's: a shadow of that mode, not a
      mode of its own (the stronger of the two keeps no flag for it);

    - ``low MPC 0.41``: MPC below ``criteria.doubtful_mpc``;
    - ``low MAMC 0.89``: MAMC below ``criteria.doubtful_mamc``;
    - ``damping 0.05 % implausibly low (median 1.5 %)`` (or ``high``): more
      than ``criteria.damping_factor`` times below or above the median
      damping of the record's modes of MPC at least ``doubtful_mpc`` (of all
      modes when fewer than two are; no check for a single mode); the
      spectral witness takes the ``high`` reason back from a mode with a
      singular-value peak of its own (:data:`DAMPED_ABOVE`);
    - ``single channel``: of :data:`MIN_CHANNELS_ALIKE` channels or more,
      one holds at least ``criteria.single_channel_share`` of the shape's
      energy;
    - ``side band of 116.9 Hz by 6.617 Hz``: see :func:`_side_bands`.

    (The spectral witness adds ``blend of 182.2 and 186.7 Hz``, :func:`blends`.)
    """
    mpc, damping = np.asarray(modes["mpc"]), np.asarray(modes["damping"])
    clean = damping[mpc >= criteria.doubtful_mpc]
    reference = np.median(clean if len(clean) >= 2 else damping)
    mamc = np.asarray(modes["mamc"])
    freq, n_poles = np.asarray(modes["freq_hz"]), np.asarray(modes["n_poles"])
    n = len(freq)
    mode_mac = np.eye(n) if mode_mac is None else mode_mac
    energy = visible**2
    share = energy.max(axis=0) / energy.sum(axis=0)
    # two resonances overlap when they lie closer than the sum of their half-power half-widths
    half_width = freq * np.clip(np.nan_to_num(damping), *SIDE_BAND_ZETA)
    flags = []
    for k in range(n):
        reasons = []
        stronger = [j for j in range(n) if j != k and mode_mac[j, k] >= criteria.mac_min
                    and abs(freq[j] - freq[k]) < max(criteria.close_rtol * max(freq[j], freq[k]),
                                                      half_width[j] + half_width[k])
                    and (n_poles[j], -j) > (n_poles[k], -k)]
        if stronger:
            j = max(stronger, key=lambda j: (n_poles[j], -j))
            reasons.append(f"{SAME_SHAPE} {freq[j]:.4g} Hz (MAC {mode_mac[j, k]:.3f})")
        if mpc[k] < criteria.doubtful_mpc:
            reasons.append(f"low MPC {mpc[k]:.2f}")
        if mamc[k] < criteria.doubtful_mamc:
            reasons.append(f"low MAMC {mamc[k]:.2f}")
        if n > 1 and not (reference / criteria.damping_factor <= damping[k] <= reference * criteria.damping_factor):
            side = DAMPED_ABOVE if damping[k] > reference else "implausibly low"
            reasons.append(f"damping {100 * damping[k]:.2g} % {side} (median {100 * reference:.2g} %)")
        if len(visible) >= MIN_CHANNELS_ALIKE and share[k] >= criteria.single_channel_share:
            reasons.append("single channel")
        flags.append(reasons)
    side_bands = _side_bands(freq, damping, n_poles, mode_mac, [not r for r in flags], criteria.mac_min)
    return ["; ".join(reasons + ([side_bands[k]] if side_bands[k] else [])) for k, reasons in enumerate(flags)]


def blends(freq, damping, shapes, trusted, mac_min) -> list[str]:
    """Which modes are a blend of two sharper ones (``"blend of 182.2 and
    186.7 Hz"``, or empty): one broad resonance fitted across two close
    modes, not a mode of its own.

    A decay whose damping changes with its amplitude (friction in a joint,
    an impact test's early, larger cycles) is no single exponential: of two
    close modes, the early fast decay of both is fitted as a third pole
    between them, broader than either, whose shape is whatever mixture of
    the two the early cycles held. Mode ``k`` is flagged when

    - two modes ``i`` and ``j`` without a reason to doubt them (``trusted``:
      the spectral witness's included, so each has a singular-value peak of
      its own) lie below and above it within its half-power half-width
      ``zeta_k f_k`` (its resonance covers both), each less damped than
      ``k`` (sharper), and neither a blend itself (the modes are judged
      sharpest first); of several such pairs, the flag names the nearest;
    - ``k``'s shape lies in the span of theirs: the share of its energy in
      that plane, ``|P phi_k|^2 / |phi_k|^2`` (``P`` the projection, the MAC
      of ``phi_k`` with its projection), is at least ``mac_min``;
    - at least :data:`MIN_CHANNELS_ALIKE` channels: two channels span every
      shape, so the span says nothing there.

    A mode of its own between two others has a shape of its own (modes are
    independent over the channels, orthogonal in the mass), out of their
    plane; a physical broad mode between two sharp ones of its plane would
    be flagged too, and the flag says to look.

    Parameters
    ----------
    freq, damping : array_like, shape (n_modes,)
        The modes' frequencies (Hz) and damping ratios (NaN: no band).
    shapes : array_like, shape (n_channels, n_modes)
        Their shapes as identified (complex).
    trusted : sequence of bool, shape (n_modes,)
        Modes without another reason (only they explain another).
    mac_min : float
        The share of the shape in the two modes' plane above which it is theirs.

    Returns
    -------
    list of str
        One reason per mode, empty where none.
    """
    freq, damping, shapes = np.asarray(freq, dtype=float), np.asarray(damping, dtype=float), np.asarray(shapes)
    n = len(freq)
    flags = [""] * n
    if shapes.shape[0] < MIN_CHANNELS_ALIKE:
        return flags
    width = freq * damping  # NaN damping: no band, compared False
    explains = list(trusted)
    for k in np.argsort(damping, kind="stable"):  # the sharpest first: a blend explains no broader mode
        sharper = [i for i in range(n) if explains[i] and damping[i] < damping[k]]
        # the nearest pair first: the flag names it
        below = sorted((i for i in sharper if freq[k] - width[k] <= freq[i] < freq[k]), key=lambda i: -freq[i])
        above = sorted((j for j in sharper if freq[k] < freq[j] <= freq[k] + width[k]), key=lambda j: freq[j])
        for i, j in ((i, j) for i in below for j in above):
            plane = shapes[:, [i, j]]
            projected = plane @ np.linalg.lstsq(plane, shapes[:, k], rcond=None)[0]
            if np.vdot(projected, projected).real >= mac_min * np.vdot(shapes[:, k], shapes[:, k]).real:
                flags[k] = f"{BLEND} {freq[i]:.4g} and {freq[j]:.4g} Hz"
                explains[k] = False
                break
    return flags


def _side_bands(freq, damping, n_poles, mode_mac, trusted, mac_min) -> list[str]:
    """Which modes are side bands of another (``"side band of 116.9 Hz by
    6.617 Hz"``, or empty): lines of an amplitude-modulated response, not
    modes of their own.

    A mode ``p`` whose motion is modulated by the slowest mode ``m`` (a
    nonlinear stiffness, a sensor's mounting, a rattling joint) has spectral
    lines at ``f_p - f_m`` and ``f_p + f_m`` with ``p``'s shape: a
    carrier ``cos(w_p t)`` times ``1 + e cos(w_m t)`` is ``cos(w_p t) +
    e/2 cos((w_p - w_m) t) + e/2 cos((w_p + w_m) t)``. Both lines are then
    flagged when

    - ``m`` is the lowest-frequency mode without another reason to doubt it
      (``trusted``);
    - each lies within its half-power half-width ``zeta f`` (``zeta``
      within :data:`SIDE_BAND_ZETA`) of ``f_p -+ f_m``;
    - each has a shape of MAC at least ``mac_min`` with ``p``'s (always so
      with one channel) and fewer poles than ``p`` (weaker);
    - ``f_p`` is no multiple of ``f_m`` within its own half-width: in a
      harmonic family (a string or a cable, ``f_n = n f_1``)
      ``f_{n-1}`` and ``f_{n+1}`` lie exactly there and are modes.

    Both lines are needed: a single mode at ``f_p + f_m`` is a coincidence
    that the modes of a structure make often (a simply supported beam's
    ``f_5 - f_3 = f_4``); a symmetric pair of weaker lines of the carrier's
    shape is not (``n^2 +- k^2`` are never both squares).
    """
    n = len(freq)
    flags = [""] * n
    m = min((k for k in range(n) if trusted[k]), key=lambda k: freq[k], default=None)
    if n < 4 or m is None:
        return flags
    width = freq * np.clip(np.nan_to_num(damping), *SIDE_BAND_ZETA)  # NaN damping: the lower bound
    for p in range(n):
        if p == m or abs(freq[p] - round(freq[p] / freq[m]) * freq[m]) <= width[p]:
            continue
        lines = [[k for k in range(n) if k not in (p, m) and abs(freq[k] - (freq[p] + sign * freq[m])) <= width[k]
                  and mode_mac[k, p] >= mac_min and n_poles[k] < n_poles[p]] for sign in (-1, 1)]
        if lines[0] and lines[1]:
            for k in lines[0] + lines[1]:
                flags[k] = flags[k] or f"side band of {freq[p]:.4g} Hz by {freq[m]:.4g} Hz"
    return flags


def doubtful_note(number, freq_hz, flag) -> str:
    """The sentence of a log that names a doubtful mode and its reasons
    (:attr:`Stabilisation.notes`)."""
    return f"mode {number} ({freq_hz:.4g} Hz) is doubtful: {flag} (kept in the modes table with its flag)"


def _notes(modes, candidates, above, fmax) -> tuple:
    """The selection's decisions as sentences for a log (:attr:`Stabilisation.notes`)."""
    notes = []
    # column by column, not iterrows (a Series per row: 3 times slower)
    for number, freq_hz, flag, second_freq_hz, second_damping in zip(
            modes["mode"], modes["freq_hz"], modes["flag"], modes["second_freq_hz"], modes["second_damping"]):
        if flag:
            notes.append(doubtful_note(number, freq_hz, flag))
        if np.isfinite(second_freq_hz):
            notes.append(f"mode {number} ({freq_hz:.4g} Hz) has a second estimate at "
                         f"{second_freq_hz:.4g} Hz, damping {100 * second_damping:.2g} %: a cluster "
                         "of the same shape at the same orders, one physical mode")
    if len(candidates):
        listed = ", ".join(f"{f:.4g} Hz ({n} poles)" for f, n in zip(candidates["freq_hz"], candidates["n_poles"]))
        notes.append(f"not selected, too few poles (a mode needs {candidates['min_poles'].iloc[0]}, the orders "
                     f"computed and fmax set how many): {listed}")
    if fmax is not None and len(above):
        listed = ", ".join(f"{f:.4g} Hz ({n} poles)" for f, n in zip(above["freq_hz"], above["n_poles"]))
        notes.append(f"not selected, above fmax = {fmax:g} Hz: {listed}")
    return tuple(notes)


def _join_split_clusters(clusters, order, distance, merge_distance):
    """Join clusters that never share an order and whose average distance is
    below ``merge_distance``, nearest pair first (the first pair by cluster
    label on ties; the lower label stays), until none is left.

    The clusters' summed distances (``E^T D E``, ``E`` the poles' cluster
    indicators), sizes and which pairs share an order are kept as matrices and
    updated at each join, so a join costs one pass over the pairs of clusters,
    not over the pairs of poles: with a few hundred clusters of a long diagram
    the pairwise loop took seconds."""
    clusters = clusters.copy()
    ids, index = np.unique(clusters, return_inverse=True)
    k = len(ids)
    member = np.zeros((len(clusters), k))
    member[np.arange(len(clusters)), index] = 1.0
    sums = member.T @ distance @ member
    size = member.sum(axis=0)
    orders, order_index = np.unique(order, return_inverse=True)
    present = np.zeros((k, len(orders)), dtype=bool)
    present[index, order_index] = True
    shared = (present.astype(int) @ present.T.astype(int)) > 0  # the pairs that share an order
    alive = np.ones(k, dtype=bool)
    upper = np.triu(np.ones((k, k), dtype=bool), 1)
    while True:
        mean = sums / np.outer(size, size)  # a joined cluster keeps its size: never 0 / 0
        open_pair = upper & ~shared & alive[:, None] & alive[None, :] & (mean < merge_distance)
        if not open_pair.any():
            return clusters
        a, b = np.unravel_index(np.argmin(np.where(open_pair, mean, np.inf)), mean.shape)
        clusters[clusters == ids[b]] = ids[a]
        sums[a] += sums[b]
        sums[:, a] += sums[:, b]
        size[a] += size[b]
        shared[a] |= shared[b]  # a cluster shares an order with b's partners now too
        shared[:, a] |= shared[:, b]
        alive[b] = False


def _close_modes(freq_hz, shapes, close_rtol):
    """Per mode: whether another lies within ``close_rtol`` in frequency, and
    the MAC with the nearest mode in frequency (NaN when alone)."""
    n = len(freq_hz)
    if n < 2:
        return np.zeros(n, dtype=bool), np.full(n, np.nan)
    gap = np.abs(freq_hz[:, None] - freq_hz[None, :]) / np.maximum(freq_hz[:, None], freq_hz[None, :])
    np.fill_diagonal(gap, np.inf)
    nearest = np.argmin(gap, axis=1)
    return gap[np.arange(n), nearest] < close_rtol, mac(shapes, shapes)[np.arange(n), nearest]


def _empty(columns) -> pd.DataFrame:
    return pd.DataFrame({c: pd.Series(dtype=object if c == "flag" else float) for c in columns})


def channel_levels(y, dt, derivatives=None) -> np.ndarray:
    """Each channel's RMS over the data sets ``y`` (n_sets, n_samples,
    n_channels), all in one quantity: the highest derivative of the
    channels' ``derivatives`` (0 displacement, 1 velocity, 2
    acceleration; None: all alike). A channel of a lower derivative is
    differentiated by differences (``numpy.diff`` over ``dt``): exact for
    slow motion, ``2 sin(omega dt / 2) / (omega dt)`` of it per derivative
    at ``omega`` (0.94 at a tenth of the sampling rate, 0.76 at 0.4 of it),
    and no wrap-around of a record that ends where it did not start (a free
    decay), which a derivative by FFT would add.

    A shape entry over its channel's level says how much of that channel's
    motion the mode is, whatever the channel's units or gain; the level in
    one quantity keeps that true across quantities: a velocity channel's own
    RMS is dominated by the lowest modes (its spectrum is the acceleration's
    over ``2 pi f``), so over it a low mode would look confined to that
    channel (the ``single channel`` flag, :func:`_flags`).
    """
    n_sets, n_samples, n_channels = y.shape
    if derivatives is None or np.all(derivatives == derivatives[0]):
        return np.sqrt(np.einsum("mtc,mtc->c", y, y) / (n_sets * n_samples))
    steps = np.max(derivatives) - np.asarray(derivatives)
    return np.array([np.sqrt(np.mean(np.square(np.diff(y[:, :, c], n=steps[c], axis=1) / dt ** steps[c])))
                     for c in range(n_channels)])


def _derivatives(quantities, n_channels):
    """Derivative order of each channel's quantity (None when not given)."""
    if quantities is None:
        return None
    quantities = list(quantities)
    if len(quantities) != n_channels or any(q not in QUANTITIES for q in quantities):
        raise ValueError(f"quantities must name one of {sorted(QUANTITIES)} for each of the {n_channels} channels, "
                         f"got {quantities!r}")
    return np.array([QUANTITIES[q] for q in quantities])


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
