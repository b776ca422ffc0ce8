"""The virtual grid shaking test and the thesis's manual steps (Sec. 7.1-7.2).

The thesis shook the AFAL grid by hand, waited a *collection lag* of about ten
seconds for the higher modes to die out, then recorded 4096 samples at 200 Hz
(T = 20.48 s) from eleven accelerometers at strip crossings (Sec. 7.1). Six of
the eleven were kept "based on the sharpness of the peaks" of their frequency
response plots, and the four lowest frequencies were estimated "through
inspection" of those plots (Sec. 7.2). :func:`shake_test` stands in for the
measurement on the finite-element :class:`~modal.structures.Grid`;
:func:`select_sharpest` and :func:`pick_peaks` make the two manual steps
measurable and repeatable.

Time integration is exact: each retained mode
``q'' + 2 zeta omega q' + omega^2 q = f(t)`` is advanced over one sampling
interval with the exact discrete-time solution for a force that is linear
between samples (first-order hold), from the matrix exponential of the
augmented state matrix (:func:`foh_modal_response`); after the burst the free
decay is evaluated in closed form.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from .._checks import finite_array, nonnegative_float, positive_float, positive_int
from ._grid import Grid
from ..signals import amplitude_spectrum, lowpass_fft
from ._simulate import Record, add_noise, damping_ratios, free_decay



@dataclass(frozen=True)
class ShakeTest:
    """A virtual grid measurement (thesis Sec. 7.2).

    Attributes
    ----------
    t : ndarray, shape (n_samples,)
        Time from the start of data collection, ``t[k] = k dt`` (s).
    acceleration : ndarray, shape (n_samples, n_sensors)
        Measured accelerations (m/s^2), with sensor noise if requested.
    dt : float
        Sampling interval (s).
    omega : ndarray, shape (n_modes,)
        Undamped natural frequencies of the modes kept in the simulation (rad/s).
    damping : ndarray, shape (n_modes,)
        Their modal damping ratios.
    nodes : ndarray of int, shape (n_sensors,)
        Grid node ids of the accelerometers (strip crossings).
    shapes : ndarray, shape (n_sensors, n_modes)
        Mass-normalised mode shapes at the accelerometers.
    displacement, velocity : ndarray, shape (n_samples, n_sensors)
        Noise-free displacement and velocity at the accelerometers.
    clean_acceleration : ndarray, shape (n_samples, n_sensors)
        Acceleration before sensor noise.
    force : ndarray, shape (n_burst, n_force_nodes)
        Force samples of the burst (N), linear in between.
    t_start : float
        Time of the first recorded sample after the burst began (s).
    """

    t: np.ndarray
    acceleration: np.ndarray
    dt: float
    omega: np.ndarray
    damping: np.ndarray
    nodes: np.ndarray
    shapes: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    clean_acceleration: np.ndarray
    force: np.ndarray
    t_start: float

    @property
    def freq_hz(self) -> np.ndarray:
        """True natural frequencies in Hz."""
        return self.omega / (2 * np.pi)

    def record(self) -> Record:
        """As a :class:`modal.Record` (noisy acceleration, noise-free displacement and velocity)."""
        return Record(
            self.t, self.displacement, self.velocity, self.acceleration, self.dt, self.omega, self.damping, self.shapes
        )


def foh_matrices(omega, damping, dt):
    """Exact one-step matrices of ``x = (q, q')`` for a force linear over the step.

    With ``A = [[0, 1], [-omega^2, -2 zeta omega]]``, ``B = (0, 1)`` and the
    force ``f(t_k + tau) = f_k + (f_{k+1} - f_k) tau / dt``,

    ``x_{k+1} = Phi x_k + G0 f_k + G1 (f_{k+1} - f_k) / dt``

    with ``expm([[A, B, 0], [0, 0, 1], [0, 0, 0]] dt) = [[Phi, G0, G1], ...]``.

    Returns
    -------
    phi : ndarray, shape (n_modes, 2, 2)
    g0, g1 : ndarray, shape (n_modes, 2)
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    zeta = np.broadcast_to(np.asarray(damping, dtype=float), omega.shape)
    aug = np.zeros((omega.size, 4, 4))
    aug[:, 0, 1] = 1.0
    aug[:, 1, 0], aug[:, 1, 1], aug[:, 1, 2] = -(omega**2), -2 * zeta * omega, 1.0
    aug[:, 2, 3] = 1.0
    e = scipy.linalg.expm(aug * dt)  # batched over modes
    phi, g0, g1 = e[:, :2, :2], e[:, :2, 2], e[:, :2, 3]
    return phi, g0, g1


def foh_modal_response(omega, damping, modal_force, dt, x0=None):
    """Modal response to a sampled force, linear between samples (exact).

    Parameters
    ----------
    omega, damping : array_like, shape (n_modes,)
        Natural frequencies (rad/s) and damping ratios.
    modal_force : array_like, shape (n_steps, n_modes)
        ``f_r(t_k) = phi_r^T F(t_k)`` at ``t_k = k dt``.
    dt : float
        Step (s).
    x0 : array_like, shape (n_modes, 2), optional
        Initial ``(q, q')``; default rest.

    Returns
    -------
    q, v, a : ndarray, shape (n_steps, n_modes)
        Modal displacement, velocity and acceleration at ``t_k``.
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    zeta = np.broadcast_to(np.asarray(damping, dtype=float), omega.shape)
    f = np.asarray(modal_force, dtype=float).reshape(-1, omega.size)
    phi, g0, g1 = foh_matrices(omega, zeta, dt)
    x = np.zeros((omega.size, 2)) if x0 is None else np.array(x0, dtype=float)
    states = np.empty((f.shape[0], omega.size, 2))
    states[0] = x
    for k in range(f.shape[0] - 1):
        x = np.einsum("rij,rj->ri", phi, x) + g0 * f[k][:, None] + g1 * ((f[k + 1] - f[k]) / dt)[:, None]
        states[k + 1] = x
    q, v = states[..., 0], states[..., 1]
    a = f - omega**2 * q - 2 * zeta * omega * v
    return q, v, a


def force_burst(n_samples, n_nodes, dt, seed=0, rms=1.0, cutoff_hz=None) -> np.ndarray:
    """Gaussian white force samples (N), optionally low-passed with
    :func:`modal.lowpass_fft` and rescaled to ``rms``; shape ``(n_samples, n_nodes)``."""
    n_samples = positive_int("n_samples", n_samples, minimum=2)
    n_nodes = positive_int("n_nodes", n_nodes)
    rms = positive_float("force_rms", rms)
    f = np.random.default_rng(seed).standard_normal((n_samples, n_nodes))
    if cutoff_hz is not None:
        f = lowpass_fft(f, dt, cutoff_hz)
        f *= 1 / np.sqrt(np.mean(f**2, axis=0))
    return rms * f


def shake_test(
    grid: Grid,
    *,
    sensors,
    force_nodes,
    burst,
    force_rms,
    damping,
    lag,
    n_samples,
    fs,
    force_cutoff_hz=None,
    noise=0.0,
    seed=0,
    fmax_hz=None,
    n_modes=None,
) -> ShakeTest:
    """Shake the grid, wait, record (thesis Sec. 7.1-7.2).

    A random force burst acts at ``force_nodes`` for ``burst`` seconds
    (independent Gaussian white samples every ``1 / fs`` s, linear in between,
    zero afterwards); the modes of ``grid`` up to ``fmax_hz`` (or the lowest
    ``n_modes``) respond with modal damping ratios ``damping``; recording
    starts ``lag`` seconds after the burst ends and takes ``n_samples``
    samples at ``fs`` Hz from accelerometers at ``sensors``; sensor noise is
    Gaussian with standard deviation ``noise`` times each channel's RMS
    (:func:`modal.add_noise`).

    Every setting of the test itself is a required keyword: the thesis's
    test is stated once, in the workflow's config (``grid.test``), with the
    reasons for its values.

    Parameters
    ----------
    grid : Grid
    sensors : sequence of int
        Accelerometer node ids (crossings, see :meth:`Grid.crossings`).
    force_nodes : sequence of int
        Excited node ids.
    burst : float
        Duration of the force (s), rounded to whole samples.
    force_rms : float
        RMS of each force channel (N).
    force_cutoff_hz : float, optional
        Band-limit the force with the thesis's FFT filter.
    damping : float or sequence of float
        Modal damping ratio(s); modes beyond a list take its last value.
        A mode's amplitude decays by ``exp(-zeta omega t)`` over the lag
        and the record.
    lag : float
        Collection lag after the burst (s), rounded to whole samples (>= 0).
    n_samples : int
        Recorded samples (4096 in the thesis).
    fs : float
        Sampling rate (200 Hz in the thesis).
    noise : float
        Sensor noise ratio ``eta`` (0.05 = 5 %); default none.
    seed : int
        Seeds the force (first) and the noise (second) streams of
        ``numpy.random.SeedSequence(seed)``.
    fmax_hz : float, optional
        Keep the modes at or below this frequency.
    n_modes : int, optional
        Keep at most the lowest ``n_modes``. With neither, every mode of
        the model responds.

    Returns
    -------
    ShakeTest
    """
    if not isinstance(grid, Grid):
        raise ValueError(f"grid must be a modal.Grid, got {type(grid).__name__}")
    fs = positive_float("fs", fs)
    dt = 1.0 / fs
    n_samples = positive_int("n_samples", n_samples, minimum=2)
    burst = positive_float("burst", burst)
    lag = nonnegative_float("lag", lag)
    noise = nonnegative_float("noise", noise)
    sensors = np.atleast_1d(np.asarray(sensors))
    force_nodes = np.atleast_1d(np.asarray(force_nodes))
    for name, ids in (("sensors", sensors), ("force_nodes", force_nodes)):
        if ids.size == 0 or not np.issubdtype(ids.dtype, np.integer):
            raise ValueError(f"{name} must be a non-empty list of node ids")
    if np.unique(sensors).size != sensors.size:
        raise ValueError(f"sensors must be distinct, got {sensors.tolist()}")
    sensor_dofs = grid.dof(sensors)
    force_dofs = grid.dof(force_nodes)
    omega, phi = grid.modes(n_modes, fmax_hz)
    if omega.size == 0:
        raise ValueError(f"no mode at or below fmax_hz = {fmax_hz}")
    zeta = damping_ratios(damping, omega.size)
    force_ss, noise_ss = np.random.SeedSequence(positive_int("seed", seed, minimum=0)).spawn(2)

    n_burst = max(2, int(round(burst * fs)))
    force = force_burst(n_burst, force_nodes.size, dt, np.random.default_rng(force_ss), force_rms, force_cutoff_hz)
    # One extra zero sample: the force ramps to zero over the step after the burst.
    modal_force = np.vstack([force, np.zeros((1, force_nodes.size))]) @ phi[force_dofs]
    q, v, _ = foh_modal_response(omega, zeta, modal_force, dt)
    x_end = np.column_stack([q[-1], v[-1]])  # at t = n_burst dt, force zero from here on
    n_lag = int(round(lag * fs))
    tau = dt * (n_lag + np.arange(n_samples))
    qs, vs, as_ = free_decay(omega, zeta, x_end, tau)
    shapes = phi[sensor_dofs]
    acc = as_ @ shapes.T
    noisy = add_noise(acc, noise, np.random.default_rng(noise_ss)) if noise > 0 else acc.copy()
    return ShakeTest(
        t=dt * np.arange(n_samples),
        acceleration=noisy,
        dt=dt,
        omega=omega,
        damping=zeta,
        nodes=sensors.astype(int),
        shapes=shapes,
        displacement=qs @ shapes.T,
        velocity=vs @ shapes.T,
        clean_acceleration=acc,
        force=force,
        t_start=dt * (n_burst + n_lag),
    )


# ---------------------------------------------------------------- manual steps
def _band_spectrum(acc, dt, fmin, fmax):
    acc = finite_array("acc", acc, ndim=(2,))
    dt = positive_float("dt", dt)
    freqs, amp = amplitude_spectrum(acc - acc.mean(axis=0), dt)
    lo = 0.0 if fmin is None else nonnegative_float("fmin", fmin)
    hi = freqs[-1] if fmax is None else positive_float("fmax", fmax)
    if hi <= lo:
        raise ValueError(f"fmax = {fmax} must exceed fmin = {fmin}")
    band = (freqs > lo) & (freqs <= hi)
    if band.sum() < 3:
        raise ValueError(f"the band {lo}..{hi} Hz holds fewer than 3 spectral lines")
    return freqs[band], amp[band]


def sharpness(acc, dt, n_peaks=4, fmin=None, fmax=None) -> np.ndarray:
    """Sharpness of each channel's spectral peaks (thesis Sec. 7.2's criterion
    for choosing six of the eleven accelerometers, made measurable).

    For each channel, the amplitude spectrum (:func:`modal.amplitude_spectrum`
    of the mean-removed record) in ``fmin < f <= fmax`` is searched for local
    maxima (:func:`scipy.signal.find_peaks`); the score is the mean, over the
    ``n_peaks`` most prominent ones, of ``log10(prominence / median)``, the
    median amplitude of the band standing for the noise floor. A channel with
    fewer than ``n_peaks`` peaks counts the missing ones as 0.

    Returns
    -------
    ndarray, shape (n_channels,)
    """
    n_peaks = positive_int("n_peaks", n_peaks)
    freqs, amp = _band_spectrum(acc, dt, fmin, fmax)
    from scipy.signal import find_peaks  # imported where used: it is half of `import modal`'s time

    scores = np.empty(amp.shape[1])
    for c in range(amp.shape[1]):
        a = amp[:, c]
        floor = max(np.median(a), np.finfo(float).tiny)
        _, props = find_peaks(a, prominence=0)
        prom = np.sort(props["prominences"])[::-1][:n_peaks]
        logs = np.log10(np.maximum(prom / floor, 1.0))
        scores[c] = np.sum(logs) / n_peaks
    return scores


def select_sharpest(acc, dt, k=6, n_peaks=4, fmin=None, fmax=None) -> np.ndarray:
    """Indices of the ``k`` channels with the sharpest spectral peaks
    (:func:`sharpness`), best first (so that the first ``n`` serve when only
    ``n`` sensors are wanted, as in Table 14); ties go to the lower index.

    Parameters
    ----------
    acc : array_like, shape (n_samples, n_channels)
    dt : float
    k : int
        How many to keep (six in the thesis), ``k <= n_channels``.
    n_peaks, fmin, fmax
        As in :func:`sharpness`.
    """
    acc = finite_array("acc", acc, ndim=(2,))
    k = positive_int("k", k)
    if k > acc.shape[1]:
        raise ValueError(f"k = {k} exceeds the {acc.shape[1]} channels")
    scores = sharpness(acc, dt, n_peaks, fmin, fmax)
    order = np.lexsort((np.arange(scores.size), -scores))
    return order[:k]


def pick_peaks(acc, dt, n_peaks=4, fmin=None, fmax=None, min_prominence=0.01) -> np.ndarray:
    """Estimate natural frequencies from the spectra, as the thesis read them
    off the frequency response plots (Sec. 7.2, "estimated" columns of
    Tables 10-12).

    Each channel's amplitude spectrum in ``fmin < f <= fmax`` is normalised
    to its maximum, the channels are averaged, and the ``n_peaks`` most
    prominent local maxima of the average (:func:`scipy.signal.find_peaks`,
    prominence at least ``min_prominence`` times the largest value) are
    refined by a parabola through the logarithm of the three bins around
    each maximum.

    Returns
    -------
    ndarray, shape (n_peaks,)
        Frequencies in Hz, ascending.

    Raises
    ------
    ValueError
        If fewer than ``n_peaks`` peaks qualify.
    """
    n_peaks = positive_int("n_peaks", n_peaks)
    min_prominence = nonnegative_float("min_prominence", min_prominence)
    freqs, amp = _band_spectrum(acc, dt, fmin, fmax)
    peak = amp.max(axis=0)
    if np.any(peak <= 0):
        raise ValueError("acc has a channel with no spectral content in the band")
    avg = (amp / peak).mean(axis=1)
    from scipy.signal import find_peaks  # imported where used: it is half of `import modal`'s time
    idx, props = find_peaks(avg, prominence=min_prominence * avg.max())
    if idx.size < n_peaks:
        raise ValueError(f"found {idx.size} spectral peaks, fewer than n_peaks = {n_peaks}")
    best = np.sort(idx[np.argsort(-props["prominences"], kind="stable")[:n_peaks]])
    log_avg = np.log(np.maximum(avg, np.finfo(float).tiny))
    la, lb, lc = log_avg[best - 1], log_avg[best], log_avg[best + 1]
    denom = la - 2 * lb + lc
    offset = np.where(denom < 0, 0.5 * (la - lc) / np.where(denom < 0, denom, 1.0), 0.0)
    df = freqs[1] - freqs[0]
    return freqs[best] + np.clip(offset, -0.5, 0.5) * df
