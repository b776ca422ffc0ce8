"""Frequency domain decomposition (FDD): the singular values of a record's
spectral density matrix, a witness of the modes that the time-domain
identification selects.

Brincker, Zhang and Andersen (2001), "Modal identification of output-only
systems using frequency domain decomposition", Smart Mater. Struct. 10:
under broadband excitation the spectral density matrix near a lightly damped
mode is about ``d(f) psi psi^H``, so the first singular value peaks at each
mode (the second at the weaker of two close modes) and its singular vector
there is the mode shape. A mode selected from the stabilisation diagram with
no such peak near it is one that no spectrum of the record confirms.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pandas as pd

from .._checks import finite_array, nonnegative_float, positive_int
from ._indicators import mac

#: Singular values kept per frequency: the first peaks at every mode, the
#: second at the weaker of two close ones; more would add noise peaks.
N_VALUES = 2
#: A peak of a singular value (10 log10) must stand this far above the
#: higher of the troughs on either side (``scipy.signal.find_peaks``
#: prominence): some 5 standard deviations of a Welch estimate averaged
#: over about 15 segments (+-1.1 dB), so noise rarely makes one.
PEAK_PROMINENCE_DB = 6.0
#: ... and its level this far above the median of that singular value within
#: :data:`PEAK_WINDOW` of its frequency (at least :data:`PEAK_WINDOW_BINS`
#: bins either side): a noise peak stands a few dB above its neighbours'
#: median, a mode's above a floor of noise around it (for a mode damped 4 %,
#: the median of +-25 % lies some 10 dB below its peak; 10 % would leave 4).
PEAK_HEIGHT_DB = 6.0
PEAK_WINDOW = 0.25
PEAK_WINDOW_BINS = 10
#: A mode is supported by a local maximum of a singular value within
#: ``max(SUPPORT_BINS * df, zeta * f)`` of its frequency: a couple of
#: frequency bins, or its half-power band ``f (1 +- zeta)`` ...
SUPPORT_BINS = 2.0
#: ... with the damping ratio taken at most this (the half-power band of a
#: heavily damped mode; a spurious mode's damping of 30 % would otherwise
#: accept any peak in a wide band) ...
SUPPORT_MAX_DAMPING = 0.10
#: ... that stands :data:`PEAK_PROMINENCE_DB` above the higher of the troughs
#: on either side within this many of those half-widths (the prominence of
#: ``scipy.signal.find_peaks`` with ``wlen``): the mode judged on its own
#: scale. A single-degree-of-freedom peak falls by ``10 log10(1 + 4**2)``
#: = 12.3 dB at 4 half-widths, so an isolated mode, however damped, passes
#: with 6 dB to spare; a fixed window (:meth:`SingularValueSpectrum.peaks`,
#: +-25 % of the frequency) sees a mode damped 8 % as the floor it stands on.
SUPPORT_BANDWIDTHS = 4.0
#: A mode without such a peak is supported by the direction of the spectrum
#: instead when a local maximum of a singular value within its half-power
#: band has a singular vector of at least this MAC with its shape (FDD's
#: estimate of the shape there): modes that overlap leave troughs shallower
#: than 6 dB between them (two equal modes ``2 zeta f`` apart dip 3 dB), a
#: storey frame's upper modes, on six floors of fifteen, stood 1.6-5.9 dB ...
SHAPE_SUPPORT_MAC = 0.9
#: ... on at least this many channels (two unit vectors of ``C^n`` drawn at
#: random reach a MAC ``t`` with probability ``(1 - t)^(n - 1)``, 1 % for 0.9
#: on three channels, 10 % on two), and only for a mode whose shape is its
#: own (:func:`own_shapes`): a second estimate of a neighbour, of the
#: neighbour's shape, matches the neighbour's singular vector as well as the
#: neighbour does.
SHAPE_SUPPORT_CHANNELS = 3
#: Two modes that one singular-value peak supports are one mode estimated
#: twice (:func:`shared_peaks`) when their shapes have at least this MAC: the
#: peak holds one shape, and the weaker estimate's scatters more than the
#: poles of one mode do from order to order (MAC 0.89-0.98 with the stronger
#: in simulated records, where the selection's 0.98 let them pass: a weaker
#: estimate of twice the damping beside a frame's 12.08 Hz mode, 0.892); two
#: modes of one peak with shapes of their own (close modes) lie far below
#: (0.01-0.34 in the close pairs of ``bench_selection``). 0.8: the MAC at
#: which a campaign's tracking (``mac_min``) and EFDD's bell (:data:`EFDD_MAC`)
#: take two shapes for one.
SHARED_PEAK_MAC = 0.8
#: How :func:`shared_peaks`' reason starts (``same spectral peak as 9.72 Hz (MAC 0.990)``).
SHARED_PEAK = "same spectral peak as"
#: Columns of :func:`spectral_support`.
SUPPORT_COLUMNS = ["sv_peak_hz", "sv_number", "sv_mac", "sv_prominence_db", "spectral_support", "efdd_freq_hz",
                   "efdd_damping"]
#: EFDD: the single-degree-of-freedom bell of a peak is the band around it
#: where a kept singular vector has at least this MAC with the peak's ...
EFDD_MAC = 0.8
#: ... and stays within this many dB of the peak (the whole spectrum would be
#: one bell where every vector is alike: a single channel) ...
EFDD_RANGE_DB = 20.0
#: ... and its correlation function's decay is fitted between these levels
#: of its envelope (Brincker, Ventura and Andersen 2001 fit a similar range).
EFDD_LEVELS = (0.9, 0.1)


def height_above_median_db(db, index: int, freq_hz: float, df: float) -> float:
    """How far ``db[index]``, a level in dB at ``freq_hz`` on bins ``df`` Hz
    apart, stands above the median of ``db`` within :data:`PEAK_WINDOW` of its
    frequency (at least :data:`PEAK_WINDOW_BINS` bins either side): a mode's
    peak stands above the floor of noise around it, a maximum of the
    spectral estimate's random error a few dB above its neighbours'
    median."""
    half = max(PEAK_WINDOW_BINS, int(PEAK_WINDOW * freq_hz / df))
    return float(db[index] - np.median(db[max(0, index - half):index + half + 1]))


@dataclass(frozen=True)
class SingularValueSpectrum:
    """The singular values of a record's spectral density matrix.

    Attributes
    ----------
    freq_hz : ndarray, shape (n_freq,)
    values : ndarray, shape (n_freq, n_values)
        The largest singular values at each frequency, in decreasing order
        (units of the record squared per Hz).
    vectors : ndarray, shape (n_freq, n_channels, n_values)
        Their left singular vectors (complex, unit norm, largest entry real
        and positive): near a mode, the first is its shape.
    nperseg : int
        Samples per Welch segment; the frequency resolution is
        ``freq_hz[1]``.
    """

    freq_hz: np.ndarray
    values: np.ndarray
    vectors: np.ndarray
    nperseg: int

    @property
    def df(self) -> float:
        """Frequency resolution (Hz)."""
        return float(self.freq_hz[1] - self.freq_hz[0]) if len(self.freq_hz) > 1 else float("nan")

    def decibels(self) -> np.ndarray:
        """``10 log10`` of :attr:`values`, relative to the largest first
        singular value (0 dB); a zero value is -300 dB."""
        return self._decibels.copy()

    @cached_property
    def _decibels(self) -> np.ndarray:
        """:meth:`decibels`, computed once for the methods below (read-only):
        :func:`spectral_support` asks for them some twenty times per record."""
        reference = float(np.max(self.values[:, 0])) if self.values.size else 0.0
        with np.errstate(divide="ignore"):
            db = np.maximum(10 * np.log10(self.values / (reference if reference > 0 else 1.0)), -300.0)
        db.flags.writeable = False
        return db

    @cached_property
    def _maxima(self) -> list[np.ndarray]:
        """The local maxima (``scipy.signal.find_peaks``) of each singular value in dB, computed once."""
        from scipy.signal import find_peaks

        return [find_peaks(self._decibels[:, k])[0] for k in range(self._decibels.shape[1])]

    def peaks(self, prominence_db=PEAK_PROMINENCE_DB, height_db=PEAK_HEIGHT_DB, fmax=None) -> pd.DataFrame:
        """The peaks of each singular value, by frequency.

        A peak is a local maximum of ``10 log10`` of the singular value with
        a prominence of at least ``prominence_db`` (``scipy.signal.find_peaks``)
        and at least ``height_db`` above the median of the same curve within
        :data:`PEAK_WINDOW` of its frequency (at least
        :data:`PEAK_WINDOW_BINS` bins either side), above the first two bins
        (the mean removed from each segment leaves nothing there) and up to
        ``fmax``. Its frequency is refined by the parabola through the three
        bins around it (in dB), which is exact for a Gaussian peak and better
        than a bin for any smooth one.

        Returns
        -------
        pandas.DataFrame
            ``freq_hz``, ``sv_number`` (1 for the first singular value),
            ``bin`` (index into :attr:`freq_hz`), ``db``, ``prominence_db``
            and ``height_db`` (above the median around it).
        """
        from scipy.signal import find_peaks

        prominence_db = nonnegative_float("prominence_db", prominence_db)
        height_db = nonnegative_float("height_db", height_db)
        db = self._decibels
        rows = []
        for k in range(db.shape[1]):
            found, properties = find_peaks(db[:, k], prominence=prominence_db)
            for index, prominence in zip(found, properties["prominences"]):
                if index < 2 or (fmax is not None and self.freq_hz[index] > fmax):
                    continue
                height = height_above_median_db(db[:, k], index, self.freq_hz[index], self.df)
                if height < height_db:
                    continue
                rows.append({"freq_hz": self.refined_hz(index, k + 1), "sv_number": k + 1, "bin": int(index),
                             "db": float(db[index, k]), "prominence_db": float(prominence),
                             "height_db": float(height)})
        rows.sort(key=lambda row: (row["freq_hz"], row["sv_number"]))
        return pd.DataFrame(rows, columns=["freq_hz", "sv_number", "bin", "db", "prominence_db", "height_db"])

    def refined_hz(self, index: int, sv_number: int = 1) -> float:
        """Frequency (Hz) of the local maximum at bin ``index`` of singular
        value ``sv_number``, refined by the parabola through the three bins
        around it (in dB): exact for a Gaussian peak, better than a bin for
        any smooth one."""
        db = self._decibels[:, sv_number - 1]
        if not 0 < index < len(db) - 1:
            return float(self.freq_hz[index])
        left, centre, right = db[index - 1:index + 2]
        curvature = left - 2 * centre + right
        shift = 0.5 * (left - right) / curvature if curvature < 0 else 0.0
        return float(self.freq_hz[index] + shift * self.df)

    def maxima_near(self, freq_hz: float, tolerance_hz: float) -> list[tuple[int, int, float]]:
        """The local maxima of each singular value (in dB, above the first two
        bins) within ``tolerance_hz`` of ``freq_hz`` (a mode's half-power
        half-width, :func:`support_tolerance_hz`), each with its prominence
        within :data:`SUPPORT_BANDWIDTHS` times ``tolerance_hz`` on either side
        (``scipy.signal.peak_prominences`` with that ``wlen``): the mode's
        neighbourhood judged on its own scale.

        Returns
        -------
        list of (int, int, float)
            ``(bin, sv_number, prominence_db)``, by singular value, then bin.
        """
        from scipy.signal import peak_prominences

        db = self._decibels
        half = int(np.ceil(SUPPORT_BANDWIDTHS * tolerance_hz / self.df))
        found = []
        for k in range(db.shape[1]):
            maxima = self._maxima[k]
            maxima = maxima[(maxima >= 2) & (np.abs(self.freq_hz[maxima] - freq_hz) <= tolerance_hz)]
            if maxima.size:
                prominences = peak_prominences(db[:, k], maxima, wlen=2 * half + 1)[0]
                found += [(int(index), k + 1, float(p)) for index, p in zip(maxima, prominences)]
        return found

    def supporting_peak(self, freq_hz: float, tolerance_hz: float, prominence_db=PEAK_PROMINENCE_DB):
        """The local maximum of a singular value that supports a mode at
        ``freq_hz`` whose half-power half-width is ``tolerance_hz``: of
        :meth:`maxima_near`, those whose prominence reaches
        ``prominence_db``, the nearest to ``freq_hz``.

        Returns
        -------
        tuple of (int, int, float) or None
            ``(bin, sv_number, prominence_db)`` of that maximum, or None.
        """
        best = None
        for index, sv_number, prominence in self.maxima_near(freq_hz, tolerance_hz):
            distance = abs(self.freq_hz[index] - freq_hz)
            if prominence >= prominence_db and (best is None or distance < best[0]):
                best = (distance, index, sv_number, prominence)
        return None if best is None else best[1:]

    def matching_maximum(self, freq_hz: float, tolerance_hz: float, shape, mac_min=SHAPE_SUPPORT_MAC):
        """The local maximum of :meth:`maxima_near` whose singular vector has
        the highest MAC with ``shape`` (at the spectrum's channels), if that
        MAC reaches ``mac_min``: the spectrum's direction there is the mode's.

        Returns
        -------
        tuple of (int, int, float) or None
            ``(bin, sv_number, prominence_db)`` of that maximum, or None.
        """
        shape = np.asarray(shape)[:, None]
        best, best_mac = None, mac_min
        for index, sv_number, prominence in self.maxima_near(freq_hz, tolerance_hz):
            alike = float(mac(shape, self.vectors[index, :, sv_number - 1][:, None])[0, 0])
            if alike >= best_mac:
                best, best_mac = (index, sv_number, prominence), alike
        return best


def fdd(y, dt, nperseg=None, n_values=N_VALUES) -> SingularValueSpectrum:
    """Frequency domain decomposition: the singular values of the spectral
    density matrix (:func:`modal.signals.spectral_density`, Welch) at every
    frequency.

    ``G(f)`` is Hermitian and positive semi-definite, so its singular value
    decomposition is its eigendecomposition: the singular values are the
    eigenvalues (``numpy.linalg.eigh``, negative round-off clipped to 0),
    the singular vectors the eigenvectors, largest first.

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
        The record (as identified: after detrending, decimation and filters).
    dt : float
        Sampling interval (s).
    nperseg : int, optional
        Samples per Welch segment (:func:`modal.signals.welch_segment` by default).
    n_values : int
        Singular values kept (at most the channels).

    Returns
    -------
    SingularValueSpectrum
    """
    from ..signals import spectral_density, welch_segment

    n_values = positive_int("n_values", n_values)
    if nperseg is None:
        nperseg = welch_segment(np.shape(y)[0]) if np.ndim(y) in (1, 2) and np.shape(y)[0] >= 2 else None
    freq_hz, G = spectral_density(y, dt, nperseg=nperseg)
    n_values = min(n_values, G.shape[1])
    eigenvalues, eigenvectors = np.linalg.eigh(G)  # ascending, per frequency
    values = np.clip(eigenvalues[:, ::-1][:, :n_values], 0.0, None)
    vectors = eigenvectors[:, :, ::-1][:, :, :n_values]
    largest = np.take_along_axis(vectors, np.argmax(np.abs(vectors), axis=1)[:, None, :], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        phase = np.where(np.abs(largest) > 0, np.conj(largest) / np.abs(largest), 1.0)
    return SingularValueSpectrum(freq_hz=freq_hz, values=values, vectors=vectors * phase, nperseg=int(nperseg))


def efdd(spectrum: SingularValueSpectrum, peak_bin: int, sv_number: int = 1, limits=None) -> tuple[float, float]:
    """Enhanced FDD: frequency and damping ratio of the mode whose peak is at
    ``peak_bin`` of singular value ``sv_number``.

    Brincker, Ventura and Andersen (2001): the single-degree-of-freedom bell
    is the band of bins around the peak where one of the kept singular
    vectors has a MAC of at least :data:`EFDD_MAC` with the peak's vector
    and its singular value is within :data:`EFDD_RANGE_DB` of the peak's,
    within ``limits`` (first and last bin; :func:`spectral_support` gives
    half-way to the neighbouring peaks) (that singular value taken at each
    bin, zero elsewhere); its
    inverse FFT is the mode's correlation function, divided here by the
    correlation of the Hann window (the window's own decay would add
    damping). The logarithm of its extrema between the envelope levels
    :data:`EFDD_LEVELS` is fitted by a line (slope ``-zeta omega_n``), its
    zero crossings by another (half the damped period), and
    ``omega_n = sqrt((zeta omega_n)^2 + omega_d^2)``.

    Returns
    -------
    freq_hz : float
        Undamped natural frequency (Hz); NaN when the bell's correlation
        function has fewer than three extrema in the fitted range.
    damping : float
        Damping ratio; NaN then too.
    """
    k = positive_int("sv_number", sv_number) - 1
    return _efdd(spectrum, peak_bin, k, limits, _window_correlation(spectrum.nperseg))


def _window_correlation(n: int) -> np.ndarray:
    """The autocorrelation of the periodic Hann window of ``n`` samples (the
    window of :func:`modal.signals.spectral_density`) at lags ``0 ... n - 1``,
    1 at lag 0: what the window's own decay adds to a correlation function
    taken back from Welch spectra (:func:`efdd` divides it out)."""
    from scipy.signal.windows import hann

    window = hann(n, sym=False)
    return np.correlate(window, window, "full")[n - 1:] / window.dot(window)


def _efdd(spectrum, peak_bin, k, limits, window_correlation):
    """:func:`efdd` of singular value ``k + 1`` (0-based ``k``), with the
    window's autocorrelation (``_window_correlation``) computed once by the
    caller (:func:`spectral_support` checks several modes on one
    spectrum)."""
    from scipy.signal import find_peaks

    reference = spectrum.vectors[peak_bin, :, k]
    macs = np.abs(np.einsum("fck,c->fk", spectrum.vectors.conj(), reference)) ** 2  # unit vectors
    best = np.argmax(macs, axis=1)
    value = spectrum.values[np.arange(len(best)), best]
    inside = (np.max(macs, axis=1) >= EFDD_MAC) & (value >= spectrum.values[peak_bin, k] * 10 ** (-EFDD_RANGE_DB / 10))
    first, last = (1, len(inside) - 1) if limits is None else (max(1, limits[0]), min(len(inside) - 1, limits[1]))
    low = high = peak_bin
    while low > first and inside[low - 1]:
        low -= 1
    while high < last and inside[high + 1]:
        high += 1
    bell = np.zeros(len(spectrum.freq_hz))
    band = np.arange(low, high + 1)
    bell[band] = value[band]
    n = spectrum.nperseg
    half = n // 2
    r = np.fft.irfft(bell, n=n)[:half] / window_correlation[:half]
    if not r[0] > 0:
        return float("nan"), float("nan")
    r = r / r[0]
    lag_s = 1 / (2 * spectrum.freq_hz[-1]) if n % 2 == 0 else 1 / (spectrum.freq_hz[1] * n)
    extrema, _ = find_peaks(np.abs(r))
    extrema = np.concatenate([[0], extrema])
    envelope = np.abs(r[extrema])
    below = np.flatnonzero(envelope < EFDD_LEVELS[1])
    extrema = extrema[:below[0]] if below.size else extrema
    fitted = extrema[np.abs(r[extrema]) <= EFDD_LEVELS[0]]
    if len(fitted) < 3:
        return float("nan"), float("nan")
    decay = -np.polyfit(fitted * lag_s, np.log(np.abs(r[fitted])), 1)[0]
    end = fitted[-1]
    signs = np.signbit(r[:end + 1])
    crossings = np.flatnonzero(signs[1:] != signs[:-1])
    times = (crossings + r[crossings] / (r[crossings] - r[crossings + 1])) * lag_s  # linear interpolation
    if len(times) < 2 or not decay > 0:
        return float("nan"), float("nan")
    half_period = np.polyfit(np.arange(len(times)), times, 1)[0]
    omega_d = np.pi / half_period
    omega_n = np.hypot(decay, omega_d)
    return float(omega_n / (2 * np.pi)), float(decay / omega_n)


def support_tolerance_hz(freq_hz, damping, df) -> np.ndarray:
    """How far (Hz) from a mode a singular-value peak supports it:
    ``max(SUPPORT_BINS df, zeta f)`` (the half-power band), ``zeta`` clipped
    to ``0 ... SUPPORT_MAX_DAMPING`` (NaN damping: bins only)."""
    freq_hz = np.asarray(freq_hz, dtype=float)
    zeta = np.clip(np.nan_to_num(np.asarray(damping, dtype=float), nan=0.0), 0.0, SUPPORT_MAX_DAMPING)
    return np.maximum(SUPPORT_BINS * df, zeta * freq_hz)


def spectral_support(spectrum: SingularValueSpectrum, freq_hz, shapes, damping=None,
                     prominence_db=PEAK_PROMINENCE_DB, own_shape=None) -> pd.DataFrame:
    """Each mode checked against the peaks of the first singular values.

    A mode is supported when a local maximum of one of the singular values
    lies within its half-power half-width (:func:`support_tolerance_hz`) and
    stands ``prominence_db`` above the troughs on either side within
    :data:`SUPPORT_BANDWIDTHS` half-widths
    (:meth:`SingularValueSpectrum.supporting_peak`): its peak judged on the
    mode's own scale, so that a heavily damped mode's broad peak counts as
    a lightly damped mode's sharp one does; of several, the nearest one
    counts. Without such a peak, a mode marked in ``own_shape``, on
    :data:`SHAPE_SUPPORT_CHANNELS` channels or more, is supported by the
    maximum within its half-width whose singular vector has a MAC of at
    least :data:`SHAPE_SUPPORT_MAC` with its shape
    (:meth:`SingularValueSpectrum.matching_maximum`): overlapping modes
    leave no 6 dB troughs between them, but each turns the spectrum's
    direction to its shape. The damping is a ratio (0.05 for 5 %).

    Parameters
    ----------
    spectrum : SingularValueSpectrum
        As :func:`fdd` returns it.
    freq_hz : array_like, shape (n_modes,)
        The modes' frequencies (Hz).
    shapes : array_like, shape (n_channels, n_modes)
        Their shapes (complex as identified, or real), at the channels of
        the spectrum.
    damping : array_like, shape (n_modes,), optional
        Their damping ratios, fractions of critical (widen the tolerance and
        the prominence window to the half-power bandwidth); NaN or absent:
        two bins.
    prominence_db : float
        Prominence a supporting maximum needs (dB).
    own_shape : array_like of bool, shape (n_modes,), optional
        The modes whose shape no other trusted mode shares (:func:`own_shapes`),
        which their singular vector may support; none by default.

    Returns
    -------
    pandas.DataFrame
        One row per mode: ``sv_peak_hz`` (the supporting maximum's frequency,
        NaN without one), ``sv_number`` (which singular value peaks there:
        1 the first, 0 none), ``sv_mac`` (MAC between the mode's shape and
        that singular value's vector at the peak bin; NaN without a peak),
        ``sv_prominence_db`` (that maximum's prominence: below
        ``prominence_db`` where the shape alone supports the mode),
        ``spectral_support`` (a maximum was found), and the cross-check
        ``efdd_freq_hz`` and ``efdd_damping`` of that maximum (:func:`efdd`;
        NaN without one or when its bell decays too fast to fit).
    """
    freq_hz = finite_array("freq_hz", np.atleast_1d(freq_hz), ndim=(1,)) if np.size(freq_hz) else np.empty(0)
    shapes = np.asarray(shapes)
    if shapes.ndim != 2 or shapes.shape[1] != freq_hz.size or shapes.shape[0] != spectrum.vectors.shape[1]:
        raise ValueError(f"shapes must be (n_channels, n_modes) = ({spectrum.vectors.shape[1]}, {freq_hz.size}), "
                         f"got {shapes.shape}")
    damping = np.full(freq_hz.size, np.nan) if damping is None else np.asarray(damping, dtype=float)
    own_shape = np.zeros(freq_hz.size, dtype=bool) if own_shape is None else np.asarray(own_shape, dtype=bool)
    if own_shape.shape != freq_hz.shape:
        raise ValueError(f"own_shape must have one entry per mode ({freq_hz.size}), got shape {own_shape.shape}")
    by_shape = shapes.shape[0] >= SHAPE_SUPPORT_CHANNELS
    tolerance = support_tolerance_hz(freq_hz, damping, spectrum.df)
    bins = spectrum.peaks(prominence_db)["bin"].to_numpy()  # the neighbours that bound an EFDD bell
    window = _window_correlation(spectrum.nperseg) if freq_hz.size else None  # once for every mode's EFDD
    rows = []
    for m, f in enumerate(freq_hz):
        peak = spectrum.supporting_peak(f, tolerance[m], prominence_db)
        if peak is None and by_shape and own_shape[m]:
            peak = spectrum.matching_maximum(f, tolerance[m], shapes[:, m])
        if peak is None:
            rows.append({"sv_peak_hz": np.nan, "sv_number": 0, "sv_mac": np.nan, "sv_prominence_db": np.nan,
                         "spectral_support": False, "efdd_freq_hz": np.nan, "efdd_damping": np.nan})
            continue
        here, sv_number, prominence = peak
        vector = spectrum.vectors[here, :, sv_number - 1]
        below, above = bins[bins < here], bins[bins > here]
        limits = ((here + below.max()) // 2 + 1 if below.size else 1,
                  (here + above.min()) // 2 if above.size else len(spectrum.freq_hz) - 1)
        efdd_freq_hz, efdd_damping = _efdd(spectrum, here, sv_number - 1, limits, window)
        rows.append({"sv_peak_hz": spectrum.refined_hz(here, sv_number), "sv_number": sv_number,
                     "sv_mac": float(mac(shapes[:, m:m + 1], vector[:, None])[0, 0]), "sv_prominence_db": prominence,
                     "spectral_support": True, "efdd_freq_hz": efdd_freq_hz, "efdd_damping": efdd_damping})
    return pd.DataFrame(rows, columns=SUPPORT_COLUMNS)


def own_shapes(shapes, trusted, mac_max=SHARED_PEAK_MAC) -> np.ndarray:
    """Which modes have a shape of their own: a MAC below ``mac_max`` with
    every other mode marked ``trusted`` (a mode's second estimate shares
    the first's shape; two modes of their own, even of one peak, do not).

    Parameters
    ----------
    shapes : array_like, shape (n_channels, n_modes)
    trusted : array_like of bool, shape (n_modes,)
    mac_max : float

    Returns
    -------
    ndarray of bool, shape (n_modes,)
    """
    alike = auto_mac(shapes)
    trusted = np.asarray(trusted, dtype=bool)
    if trusted.shape != (alike.shape[0],):
        raise ValueError(f"trusted must have one entry per mode ({alike.shape[0]}), got shape {trusted.shape}")
    others = (alike >= mac_max) & trusted[None, :]
    np.fill_diagonal(others, False)
    return ~others.any(axis=1)


def shared_peaks(freq_hz, support: pd.DataFrame, shapes, n_poles, mac_min, shadows=None, doubtful=None) -> list[str]:
    """Which modes are a second estimate of one resonance: ``"same spectral
    peak as 2.47 Hz (MAC 0.999)"``, or empty.

    Two modes supported by the same singular-value peak
    (:func:`spectral_support`: the same ``sv_number`` and ``sv_peak_hz``)
    whose shapes have a MAC of at least ``mac_min`` are one peak of one
    shape in the spectrum: the channels and the spectrum see one mode, so
    the one farther from the peak (as far: the one with fewer poles, then
    the higher frequency) is the other's second estimate, unless that one
    is doubtful already and it is not: a trusted estimate keeps the peak
    over one flagged for another reason (its implausible damping, say),
    whatever their distances (which, within the spectrum's resolution, say
    little), so that the resonance keeps a trusted row. Two modes of one
    peak with shapes of their own (close modes, the first and second
    singular values' peaks at one frequency) stay two.

    Parameters
    ----------
    freq_hz : array_like, shape (n_modes,)
        The modes' frequencies (Hz), for the reason's text.
    support : pandas.DataFrame
        :func:`spectral_support` of the modes.
    shapes : array_like, shape (n_channels, n_modes)
        The modes' shapes, for their MAC with each other.
    n_poles : array_like, shape (n_modes,)
        The poles of each mode (its weight in the diagram: the tie-break).
    mac_min : float
        The MAC above which two shapes are one.
    shadows : array_like of bool, shape (n_modes,), optional
        Modes already judged another's shadow (the selection's ``same shape
        as ...``): that pair is decided, so they take no part here.
    doubtful : array_like of bool, shape (n_modes,), optional
        Modes flagged for another reason (the selection's other flags): of
        two on one peak, the one that is not keeps it.

    Returns
    -------
    list of str
        One reason per mode, empty where none (always for a shadow).
    """
    freq_hz, n_poles = np.asarray(freq_hz, dtype=float), np.asarray(n_poles)
    peak = support["sv_peak_hz"].to_numpy(dtype=float)
    number = support["sv_number"].to_numpy()
    alike = auto_mac(shapes)
    taking_part = np.ones(len(support), dtype=bool) if shadows is None else ~np.asarray(shadows, dtype=bool)
    trusted = np.ones(len(support), dtype=bool) if doubtful is None else ~np.asarray(doubtful, dtype=bool)

    def rank(j):  # trusted first, then nearer the peak, then more poles, then the lower frequency
        return bool(trusted[j]), -abs(freq_hz[j] - peak[j]), n_poles[j], -j

    reasons = []
    for k in range(len(support)):
        stronger = [j for j in range(len(support)) if j != k and taking_part[j] and taking_part[k]
                    and number[j] == number[k] and peak[j] == peak[k] and alike[j, k] >= mac_min and rank(j) > rank(k)]
        j = max(stronger, key=rank, default=None)
        reasons.append("" if j is None else f"{SHARED_PEAK} {freq_hz[j]:.4g} Hz (MAC {alike[j, k]:.3f})")
    return reasons


def auto_mac(shapes) -> np.ndarray:
    """The MAC of every pair of ``shapes`` (n_channels, n_modes): symmetric,
    1 on the diagonal (:func:`modal.mac` of the shapes with themselves)."""
    shapes = np.asarray(shapes)
    if shapes.ndim != 2:
        raise ValueError(f"shapes must be (n_channels, n_modes), got shape {shapes.shape}")
    if shapes.shape[1] == 0:
        return np.empty((0, 0))
    return mac(shapes, shapes)
