"""The Temporal Correlation Method (thesis Ch. 3, Eqs. 21-31)."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from .._checks import constant_channels, finite_array, positive_float, positive_int, unit_scale
from ._result import (ModalResult, ModalWarning, near_limit, normalise_shapes, short_window, sort_modes, warn_flags,
                     warn_not_free_response)
from ..signals import acceleration_offset, integrate_acceleration


def correlation(a, b) -> np.ndarray:
    """Temporal inner product ``<a, b^T>`` of Eq. (12), truncated to the record:
    the plain mean over samples of ``a(t) b(t)^T``."""
    return a.T @ b / a.shape[0]


def tcm(acc, dt, n_modes=None, vel=None, lag=0, duration=None) -> ModalResult:
    """Identify modes with the TCM.

    ``lag == 0`` (Eq. 31, k = 2, m = 1, T_o = 0):
    ``A = <v, v^T>`` from velocities, ``B = <a, a^T>`` from accelerations,
    ``lambda A x = B x`` (Eq. 26), ``omega = sqrt(lambda)``. When ``vel`` is not
    given it is integrated from ``acc`` (:func:`modal.signals.integrate_acceleration`),
    and the accelerometers' offset it estimates is removed from ``acc`` in
    ``B`` too.

    ``lag > 0`` (Eq. 30, k = m, T_o = lag dt): one signal ``y = acc``,
    ``A = <y(t), y^T(t)>`` and ``B = <y(t + T_o), y^T(t)>`` over the same
    ``n - lag`` instants ``t``, B symmetrised, ``omega = acos(lambda) / T_o``.

    Mode shapes are ``A v_r`` (Eq. 28: ``v_r = M x_r``, and ``A`` plays ``M``
    up to a diagonal modal scaling), normalised.

    Flags: ``short_window`` where the inner products span fewer than six
    periods of the mode (the thesis's guideline ``T >= 12 pi / omega_1``,
    Sec. 3.3); ``aliased`` where the mode lies at or beyond what the sampling
    can carry. Without a lag that is the Nyquist rate ``pi / dt``: Eq. (31)'s
    ``sqrt(lambda)`` has no upper bound, and a frequency beyond it belongs to
    no sampled mode (typically ``vel`` is not the velocity of ``acc``: a
    displacement given as ``vel`` yields about ``omega^2``). With a lag it is
    ``pi / T_o``, above which Eq. (30)'s ``acos`` folds frequencies back,
    judged on the mode itself and on the lag-one Rayleigh quotient of its
    eigenvector, ``omega_1 = acos(v^T B_1 v / v^T A v) / dt``, which can see up
    to the Nyquist frequency. A :class:`~modal.ModalWarning` names flagged
    modes.

    When ``vel`` is given, it is checked against ``acc`` first (the TCM's
    ``lambda = omega^2`` holds only when ``acc`` is the derivative of ``vel``
    in the same units): a :class:`~modal.ModalWarning` names ``vel`` and
    ``acc`` when ``rms(acc) / rms(vel)``, a weighted mean of the modes'
    frequencies, lies far outside what the record can carry (half a cycle
    over the window ... twice the Nyquist rate), or when, channel by channel,
    ``acc`` is not about ``d(vel)/dt``: barely correlated with it (``vel`` a
    displacement, or another quantity) or scaled by a factor outside
    ``0.5 ... 2`` (a unit mix-up: every ``omega`` is scaled by that factor,
    e.g. ``vel`` in mm/s with ``acc`` in m/s^2 divides them by 1000).

    Another warning comes when ``acc`` is not a free response (its energy
    keeps rising, as an ambient record's does;
    :func:`modal.identification._result.free_response_growth`): the TCM's inner products
    (Eqs. 21-26) assume one. The signals are divided by a power of two near
    the peak of ``acc`` first, so results do not depend on units or scale.

    Parameters
    ----------
    acc : array_like, shape (n_samples, l)
        The measured signal (the thesis: accelerations).
    dt : float
        Sampling interval (s).
    n_modes : int, optional
        How many of the ``l`` identified modes to return (the lowest);
        default ``l``. The eigenproblem is always ``l x l``: to identify ``n``
        modes as the thesis does, pass ``n`` sensors.
    vel : array_like, shape (n_samples, l), optional
        Velocities for ``A`` when ``lag == 0`` (refused with a lag: Eq. 30
        uses one signal).
    lag : int
        Time offset ``T_o`` in samples.
    duration : float, optional
        Truncate the temporal inner products to ``0 <= t <= duration`` s.

    Returns
    -------
    ModalResult
        ``eigenvalues`` holds ``lambda``; ``real_pole`` flags eigenvalues that
        give no real frequency (``lambda < 0`` for lag 0, ``|lambda| > 1`` for lag > 0);
        ``singular_values`` holds the eigenvalues of ``A``.
    """
    acc = finite_array("acc", acc, ndim=(2,))
    dt = positive_float("dt", dt)
    lag = positive_int("lag", lag, minimum=0)
    n_samples, l = acc.shape
    n_modes = l if n_modes is None else positive_int("n_modes", n_modes)
    if n_modes > l:
        raise ValueError(f"n_modes = {n_modes} exceeds the {l} channels; the TCM needs one sensor per mode")
    if vel is not None:
        if lag > 0:
            raise ValueError(
                f"vel is used only with lag = 0 (Eq. 31); with lag = {lag} the TCM takes one signal "
                "(Eq. 30): pass the signal as acc and leave vel out"
            )
        vel = finite_array("vel", vel, ndim=(2,))
        if vel.shape != acc.shape:
            raise ValueError(f"vel must have the shape of acc {acc.shape}, got {vel.shape}")
        constant_channels("vel", vel)
    if n_samples < l:
        raise ValueError(
            f"acc of shape {acc.shape} has fewer samples than channels; the layout is "
            "(n_samples, n_channels): transpose it"
        )
    constant_channels("acc", acc)
    if duration is not None:
        duration = positive_float("duration", duration)
        n_samples = min(n_samples, int(round(duration / dt)) + 1)
    needed = max(lag + l + 1, 3)
    if n_samples < needed:
        raise ValueError(f"too few samples ({n_samples}) for {l} channels and lag {lag}: need at least {needed}")
    scale = unit_scale(acc)
    full = acc
    acc = acc[:n_samples] / scale

    if lag == 0:
        if vel is None:  # the offset integrates into a ramp and biases B as well
            acc = acc - acceleration_offset(acc, dt)
            vel = integrate_acceleration(acc, dt)
        else:
            vel = vel[:n_samples] / scale
            check_derivative_pair(vel, acc, dt)
        a = correlation(vel, vel)
        b = correlation(acc, acc)
        window = n_samples * dt
    else:
        early, late = acc[: n_samples - lag], acc[lag:]
        a = correlation(early, early)
        b = correlation(late, early)
        b = (b + b.T) / 2
        b_one = correlation(acc[1 : n_samples - lag + 1], early)
        b_one = (b_one + b_one.T) / 2
        window = (n_samples - lag) * dt
    a_eig = np.linalg.eigvalsh(a)
    if a_eig[0] <= a_eig[-1] * 1e-13:
        raise ValueError("the correlation matrix A is singular: the channels are linearly dependent")
    lam, v = scipy.linalg.eigh(b, a)  # Eq. (26)
    if lag == 0:
        bad = lam < 0
        omega = np.sqrt(np.abs(lam))  # Eq. (31)
        aliased = near_limit(omega, dt)  # sqrt(lambda) is unbounded: beyond pi / dt no sampled mode
    else:
        bad = np.abs(lam) > 1
        omega = np.arccos(np.clip(lam, -1, 1)) / (lag * dt)  # Eq. (30)
        # v is A-orthonormal (scipy.linalg.eigh), so v^T A v = 1
        lam_one = np.einsum("ir,ij,jr->r", v, b_one, v)
        omega_one = np.arccos(np.clip(lam_one, -1, 1)) / dt
        aliased = near_limit(omega, lag * dt) | near_limit(omega_one, lag * dt)
    shapes = normalise_shapes(a @ v)  # Eq. (28)
    omega, shapes, cols = sort_modes(omega, shapes, real_pole=bad, aliased=aliased, lam=lam)
    keep = slice(0, n_modes)
    result = ModalResult(
        omega=omega[keep],
        shapes=shapes[:, keep],
        method="tcm",
        real_pole=cols["real_pole"][keep],
        aliased=cols["aliased"][keep],
        short_window=short_window(omega[keep], window),
        singular_values=a_eig[::-1] * scale**2,
        eigenvalues=cols["lam"][keep],
    )
    warn_not_free_response(result, full[None], dt)
    return warn_flags(result, window)


#: ``acc`` is taken as ``d(vel)/dt`` in consistent units when, channel by
#: channel, their correlation is at least this ...
DERIVATIVE_MIN_CORRELATION = 0.5
#: ... and the least-squares factor ``acc ~ k d(vel)/dt`` lies within these
#: bounds (the central difference alone makes ``k`` up to ~1.5 for a mode at
#: a fifth of the Nyquist rate; unit mix-ups give 1000, 1e-3, 9.81, 0.102).
DERIVATIVE_SCALE_RANGE = (0.5, 2.0)


def check_derivative_pair(vel, acc, dt, names=("vel", "acc")) -> None:
    """Warn (:class:`~modal.ModalWarning`, naming both arguments) when ``acc``
    does not look like the time derivative of ``vel`` in the same units.

    Two checks, on the signals with their means removed:

    - ``rms(acc) / rms(vel)`` is a weighted mean of the response's angular
      frequencies; far outside the range the record can carry, from half a
      cycle over the record (``pi / T``) to twice the Nyquist rate
      (``2 pi / dt``), the two are not velocity and acceleration of one motion
      in consistent units;
    - channel by channel, ``acc`` against the central difference of ``vel``:
      a correlation below :data:`DERIVATIVE_MIN_CORRELATION` (``vel`` is a
      displacement, or ``acc`` a velocity: then they are in quadrature) or a
      least-squares factor outside :data:`DERIVATIVE_SCALE_RANGE` (units:
      the TCM's frequencies are all scaled by that factor).
    """
    import warnings

    vel_name, acc_name = names
    v = vel - vel.mean(axis=0)
    a = acc - acc.mean(axis=0)
    n_samples = len(a)
    notes = []
    v_rms, a_rms = np.sqrt(np.mean(v**2)), np.sqrt(np.mean(a**2))
    implied = a_rms / v_rms if v_rms > 0 else np.inf
    low, high = np.pi / (n_samples * dt), 2 * np.pi / dt
    if not low <= implied <= high:
        notes.append(f"rms({acc_name}) / rms({vel_name}) = {implied:.4g} rad/s, a mean frequency of the response, "
                     f"lies outside what the record can carry ({low:.3g} ... {high:.3g} rad/s)")
    if n_samples >= 3:
        dv = np.gradient(v, dt, axis=0)
        cross = np.sum(dv * a, axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            correlation = cross / np.sqrt(np.sum(dv**2, axis=0) * np.sum(a**2, axis=0))
            factor = cross / np.sum(dv**2, axis=0)
        uncorrelated = np.flatnonzero(~(np.abs(correlation) >= DERIVATIVE_MIN_CORRELATION))
        lo, hi = DERIVATIVE_SCALE_RANGE
        scaled = np.setdiff1d(np.flatnonzero(~((factor >= lo) & (factor <= hi))), uncorrelated)
        def channels(which):
            return "every channel" if which.size == a.shape[1] else f"channel(s) {', '.join(map(str, which))}"

        def spread(values):
            return f"{values.min():.3g}" + (f" ... {values.max():.3g}" if values.size > 1 else "")

        if uncorrelated.size:
            notes.append(f"{channels(uncorrelated)}: {acc_name} is barely correlated with "
                         f"d({vel_name})/dt (r = {spread(correlation[uncorrelated])}): is "
                         f"{vel_name} a displacement, or {acc_name} a velocity (one derivative apart, they are in "
                         "quadrature)?")
        if scaled.size:
            notes.append(f"{channels(scaled)}: {acc_name} = {spread(factor[scaled])} x d({vel_name})/dt, "
                         "a unit mix-up "
                         f"(e.g. {vel_name} in mm/s with {acc_name} in m/s^2 gives 0.001, {acc_name} in g with "
                         f"{vel_name} in m/s 0.102) or a sign; every omega is scaled by that factor")
    if notes:
        warnings.warn(f"tcm: {vel_name} and {acc_name} are not velocity and acceleration of one motion in the "
                      "same units: " + "; ".join(notes), ModalWarning, stacklevel=3)
