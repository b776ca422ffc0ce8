"""Records with known modes shared by the engine tests: beams at the thesis's
and at irregular sensor layouts, closed-form sinusoids and exponentials, an
ambient (white-noise driven) beam, the Palisaden record, and the Hypothesis
strategy that draws beams, layouts, damping and data sets.

Exactness conditions used throughout: a simply supported beam's frequencies
are ``i^2 omega_1``, so a record of whole fundamental periods spans whole
periods of every mode; with ``dt = T_1 / 360`` the sixth mode has ten samples
per period (the thesis's choice) and ``360 k`` samples are ``k`` periods.
"""

import warnings
from pathlib import Path

import numpy as np
import scipy.linalg
import scipy.signal
from hypothesis import HealthCheck, assume, settings
from hypothesis import strategies as st

import modal

THESIS_SAMPLES = 3594  # t = 0 ... 29.001 s: "truncated after 29 sec., or ten times the fundamental period"


EXACT_MAC = 1 - 1e-10


PER_PERIOD = 360  # samples per fundamental period (dt = T_1 / 360 = T_6 / 10)


THESIS_BEAM = (5.0, 30.0, 1.0)


IRREGULAR = np.array([0.3, 0.9, 1.7, 2.2, 3.1, 4.4])  # the layout on the 5 m beam


OTHER_BEAM = (3.2, 71.0, 2.3)


OTHER_LAYOUT = np.array([0.21, 0.55, 1.02, 1.66, 2.31, 2.93])


LAYOUTS = {
    "thesis": (THESIS_BEAM, 5.0 * np.arange(1, 7) / 7, 10 / 7),
    "irregular": (THESIS_BEAM, IRREGULAR, 10 / 7),
    "other_beam": (OTHER_BEAM, OTHER_LAYOUT, 0.77),
}


def beam_record(layout, n_samples, damping=0.0, n_modes=6, impact=None):
    """Impulse response of ``n_modes`` beam modes at a layout, ``dt = T_1 / 360``."""
    (length, stiffness, mass), sensors, default_impact = LAYOUTS[layout]
    beam = modal.SimplySupportedBeam(length, stiffness, mass)
    omega = beam.natural_frequencies(n_modes)
    dt = 2 * np.pi / omega[0] / PER_PERIOD
    x = default_impact if impact is None else impact
    rec = modal.beam_impulse_response(beam, n_modes, x, sensors, dt, n_samples, damping)
    return rec, omega, dt


def acos_tolerance(omega, t_o, dlam=1e-12):
    """Round-off bound of ``omega = acos(lambda) / T_o`` for an error ``dlam`` in lambda."""
    return dlam / (omega * t_o * np.abs(np.sin(omega * t_o)))


def diag_mac(a, b):
    return np.diag(modal.mac(a, b))


# Thesis Tables 1 and 2, printed digits (TCM with exact velocities, ERA r=24, l=6, s=100, m=1)
TABLE_1 = {"tcm": [2.1659, 8.6617, 19.474], "era": [2.1623, 8.6493, 19.461]}
TABLE_2 = {"tcm": [2.1711, 8.6614, 19.407], "era": [2.1623, 8.6493, 19.461]}


def printed(values, published):
    """Round each value to the number of significant digits printed in the thesis."""
    out = []
    for v, p in zip(values, published):
        decimals = len(str(p).split(".")[1])
        out.append(round(float(v), decimals))
    return out


def two_sinusoids(omega=(0.5, 2.0), periods=3, per_period=400, mixing=((1.0, 0.4), (-0.7, 1.3)), amplitude=1.0):
    """Displacement, velocity and acceleration of two modes seen through a
    non-orthogonal ``mixing`` matrix, over whole periods of both modes."""
    omega = np.asarray(omega)
    t_end = periods * 2 * np.pi / omega.min()
    n = periods * per_period
    dt = t_end / n
    t = dt * np.arange(n)
    q = np.sin(omega[None, :] * t[:, None])
    mix = amplitude * np.asarray(mixing)
    return dt, q @ mix.T, (omega * np.cos(omega[None, :] * t[:, None])) @ mix.T, (-(omega**2) * q) @ mix.T


def growing(rate, dt, n, alternate=False):
    """One channel ``e^{rate t}`` (or ``(-1)^k e^{rate t}``): its lag-``k``
    ratio ``sum y(t + k dt) y(t) / sum y(t)^2`` is exactly ``(+-e^{rate dt})^k``."""
    y = np.exp(rate * dt * np.arange(n))
    return (y * (-1.0) ** np.arange(n) if alternate else y)[:, None]


PALISADEN = Path(__file__).resolve().parents[1] / "data" / "palisaden_20hz_30min.npy"


PALISADEN_MODES_HZ = [1.88, 2.42, 2.68]  # pyOMA2 documentation (see tests/data/PALISADEN.md)


BEAM = modal.SimplySupportedBeam(length=10.0, bending_stiffness=2.0e6, mass_per_length=100.0)


SENSORS_X = np.array([0.9, 2.3, 4.1, 6.6, 8.7])


DAMPING = np.array([0.01, 0.015, 0.02])


def ambient_beam(duration_s=400.0, dt=0.01, seed=1):
    """Acceleration of three beam modes under spatially white, Gaussian white
    noise (exact first-order-hold integration), sensors at SENSORS_X."""
    omega = BEAM.natural_frequencies(3)
    shapes = BEAM.mode_shapes(SENSORS_X, 3)
    rng = np.random.default_rng(seed)
    force = rng.standard_normal((int(duration_s / dt), 3))
    acc_modal = np.column_stack([_foh_acceleration(w, z, f, dt) for w, z, f in zip(omega, DAMPING, force.T)])
    return acc_modal @ shapes.T, dt, omega / (2 * np.pi)


def _foh_acceleration(omega, zeta, force, dt):
    """Acceleration of ``q'' + 2 zeta omega q' + omega^2 q = f`` from rest, the
    force linear between samples: the exact one-step matrices from the
    exponential of the augmented state matrix, stepped by scipy's dlsim."""
    aug = np.zeros((4, 4))
    aug[0, 1], aug[1, 0], aug[1, 1], aug[1, 2], aug[2, 3] = 1.0, -omega**2, -2 * zeta * omega, 1.0, 1.0
    e = scipy.linalg.expm(aug * dt)
    phi, g0, g1 = e[:2, :2], e[:2, 2], e[:2, 3] / dt
    system = (phi, np.column_stack([g0 - g1, g1]), np.array([[-omega**2, -2 * zeta * omega]]), np.array([[1.0, 0.0]]), dt)
    inputs = np.column_stack([force, np.append(force[1:], 0.0)])  # f_k and f_{k+1}
    _, out, _ = scipy.signal.dlsim(system, inputs)
    return out[:, 0]


@st.composite
def beam_cases(draw):
    length = draw(st.floats(1.0, 10.0))
    stiffness = draw(st.floats(1.0, 100.0))
    mass = draw(st.floats(0.5, 5.0))
    n_modes = draw(st.integers(2, 5))
    extra = draw(st.integers(0, 2))
    fractions = draw(
        st.lists(st.floats(0.03, 0.97), min_size=n_modes + extra, max_size=n_modes + extra, unique=True)
    )
    impacts = draw(st.lists(st.floats(0.05, 0.95), min_size=1, max_size=2, unique=True))
    zeta = draw(st.sampled_from([0.0, 0.001, 0.01, 0.05]))
    beam = modal.SimplySupportedBeam(length, stiffness, mass)
    sensors = np.sort(np.array(fractions)) * length
    shapes = beam.mode_shapes(sensors, n_modes)
    assume(np.min(np.diff(sensors)) > 0.01 * length)
    sv = np.linalg.svd(shapes, compute_uv=False)
    assume(sv[-1] > 0.05 * sv[0])  # every mode observed, independently
    modal_impulses = beam.mode_shapes(np.array(impacts) * length, n_modes)
    assume(np.all(np.abs(modal_impulses) > 0.1))  # every impact excites every mode
    return beam, n_modes, sensors, [x * length for x in impacts], zeta


def _records(beam, n_modes, sensors, impacts, zeta, n_samples):
    omega = beam.natural_frequencies(n_modes)
    dt = 2 * np.pi / omega[0] / (10 * n_modes**2)  # ten samples per period of the highest mode
    recs = [modal.beam_impulse_response(beam, n_modes, x, sensors, dt, n_samples, zeta) for x in impacts]
    return recs, omega, dt


PROPERTY = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# The flags a method warns about (real poles are routine: counted, not warned), as its ModalWarning names them.
WARNED_FLAGS = {"unstable": "unstable (|z| > 1)", "aliased": "possibly aliased", "short_window": "short window ("}


def flagged(method, *args, free_response=False, **kwargs):
    """``method(*args, **kwargs)`` (modal.tcm, modal.era or modal.cera), asserting
    the ModalWarnings it issues: one naming exactly the flags its result sets
    (none when it sets none), and the free-response warning when (and only
    when) ``free_response``. Returns the result."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = method(*args, **kwargs)
    messages = [str(w.message) for w in caught]
    assert all(issubclass(w.category, modal.ModalWarning) for w in caught), messages
    notes = [m for m in messages if m.endswith("(see the result's flags)")]
    free = [m for m in messages if "do not look like a free response" in m]
    assert len(notes) + len(free) == len(messages), messages
    assert len(free) == int(free_response), messages
    set_flags = [name for name in WARNED_FLAGS if getattr(result, name).any()]
    if set_flags:
        (note,) = notes
        assert note.startswith(f"{result.method}: "), note
        assert [name for name, words in WARNED_FLAGS.items() if words in note] == set_flags, note
    else:
        assert not notes, notes
    return result
