"""Run the thesis's simulation studies (Ch. 6) from plain configuration
mappings: build the beam record, add noise per seed, pick the signals an
interpretation names, identify, and collect tidy tables of identified modes.

The Snakemake scripts only read files and call these functions.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from contextlib import contextmanager

import numpy as np
import pandas as pd

from ..identification import cera
from ..identification import era
from ..identification import ModalWarning
from ..structures import Record, beam_impulse_response, with_noise
from ..structures import SimplySupportedBeam
from ..identification import tcm
from .chunks import chunk_seeds, study_cases

SIGNAL_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}


def beam_record(spec: Mapping, damping: float) -> Record:
    """Noise-free impulse response of the beam described by ``spec``.

    ``spec`` keys: ``length``, ``bending_stiffness``, ``mass_per_length``,
    ``n_modes`` (participating), ``stations`` (the span is divided into that
    many equal parts), ``impact`` and ``sensors`` (station indices, so
    ``impact: 2`` with ``stations: 7`` is x = 2L/7), ``samples_per_period``
    (dt = the period of mode ``period_mode`` / this; by default of the
    shortest participating mode, ``period_mode = n_modes``) and ``n_samples``.
    Sec. 3.4's guideline ``T_s <= pi / (5 omega_n)`` is ``samples_per_period:
    10`` of mode n; Sec. 6.1's "one tenth of the shortest period" is that
    guideline with n = 6. ``damping_model`` (optional, :data:`DAMPING_MODELS`)
    says how ``damping`` spreads over the modes.
    """
    beam = SimplySupportedBeam(spec["length"], spec["bending_stiffness"], spec["mass_per_length"])
    omega = beam.natural_frequencies(spec["n_modes"])
    dt = 2 * np.pi / omega[spec.get("period_mode", spec["n_modes"]) - 1] / spec["samples_per_period"]
    station = beam.length / spec["stations"]
    sensors = station * np.asarray(spec["sensors"], dtype=float)
    ratios = modal_damping(damping, omega, spec.get("damping_model", "modal"))
    return beam_impulse_response(beam, spec["n_modes"], station * spec["impact"], sensors, dt, spec["n_samples"], ratios)


#: How a case's damping ``zeta`` spreads over the modes (the thesis, Sec. 6.1: "a damping
#: coefficient of zeta = .05", read as a modal damping ratio; the others are searched for Table 8):
#: ``modal``, every mode's ratio is zeta (decay zeta omega_r); ``uniform_decay``, every mode decays
#: as mode 1 does (zeta omega_1, ratio zeta omega_1 / omega_r, mass-proportional damping);
#: ``stiffness``, ratio zeta omega_r / omega_1 (stiffness-proportional, zeta at mode 1).
DAMPING_MODELS = ("modal", "uniform_decay", "stiffness")


def modal_damping(damping: float, omega, model: str = "modal"):
    """Modal damping ratios of the modes ``omega`` (rad/s, ascending) under a
    :data:`DAMPING_MODELS` entry; ``damping`` itself for ``modal``."""
    if model not in DAMPING_MODELS:
        raise ValueError(f"damping_model must be one of {', '.join(DAMPING_MODELS)}, got {model!r}")
    if model == "modal" or damping == 0:
        return damping
    omega = np.asarray(omega, dtype=float)
    return damping * (omega[0] / omega if model == "uniform_decay" else omega / omega[0])


def interpreted(study: Mapping, beam: Mapping, interpretation: Mapping, study_name: str) -> tuple[dict, dict]:
    """The study and beam as one interpretation reads them.

    An interpretation (config ``interpretations``) names the signals each
    method sees and, under ``studies.<study_name>``, the unstated settings it
    reads differently: ``beam`` keys replace the beam's, ``methods.<method>``
    keys the method's, any other key the study's (e.g. ``cols_sweep``).

    Returns
    -------
    study, beam : dict
        Copies; the inputs are left alone.
    """
    import copy

    study, beam = copy.deepcopy(dict(study)), copy.deepcopy(dict(beam))
    overrides = copy.deepcopy(dict((interpretation.get("studies") or {}).get(study_name) or {}))
    beam.update(overrides.pop("beam", {}))
    for method, settings in overrides.pop("methods", {}).items():
        study["methods"][method] = {**study["methods"].get(method, {}), **settings}
    study.update(overrides)
    return study, beam


@contextmanager
def flags_recorded():
    """Silence :class:`~modal.ModalWarning` inside: the thesis layer writes every
    flag to its identified-modes files instead (thousands of seeds would
    otherwise print thousands of warnings)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModalWarning)
        yield


def identify(record: Record, method: str, settings: Mapping, signals, channels=None):
    """Identify modes of ``record`` with one method.

    Parameters
    ----------
    record : Record
    method : {"tcm", "era", "cera"}
    settings : mapping
        Keyword arguments of the method (``n_modes``, ``rows``, ``cols``,
        ``lag``, ``duration``, ``start``).
    signals : str or sequence of two str
        Which outputs the method sees: for the TCM ``[A-signal, B-signal]``
        (the thesis: ``[velocity, acceleration]``, Eq. 31); for ERA and CERA
        one signal (the thesis: ``acceleration``).
    channels : sequence of int, optional
        Subset of sensors (0-based), e.g. the first n for spillover.
    """
    with flags_recorded():
        return _identify(record, method, settings, signals, channels)


def _identify(record, method, settings, signals, channels):
    pick = slice(None) if channels is None else list(channels)
    for name in [signals] if isinstance(signals, str) else signals:
        if name not in SIGNAL_ORDER:
            raise ValueError(f"signals: {name!r} is not one of {list(SIGNAL_ORDER)}")
    if method == "tcm":
        low, high = (record.signal(SIGNAL_ORDER[s])[:, pick] for s in signals)
        if settings.get("lag", 0):
            return tcm(high, record.dt, **settings)
        return tcm(high, record.dt, vel=low, **settings)
    y = record.signal(SIGNAL_ORDER[signals])[:, pick]
    if method == "era":
        return era(y, record.dt, **settings)
    if method == "cera":
        return cera(y, record.dt, **settings)
    raise ValueError(f"method must be one of tcm, era, cera, got {method!r}")


def _frame(result, **labels) -> pd.DataFrame:
    """``labels`` then :meth:`ModalResult.columns` without ``method`` and with
    ``damping`` named ``damping_id``, in one DataFrame constructor call (renaming
    and inserting into ``to_frame()`` took more time than the identification
    itself; tests/thesis/test_study.py checks they agree)."""
    columns = result.columns()
    del columns["method"]
    return pd.DataFrame({**labels, **{("damping_id" if k == "damping" else k): v for k, v in columns.items()}})


def run_study(study: Mapping, beam_spec: Mapping, interpretation: Mapping, seeds: Mapping,
              chunk: int | None = None) -> pd.DataFrame:
    """Every identification of one study under one interpretation, or of one
    chunk of its seeds.

    For each case, the noise-free record is simulated once; a noise-free case
    is identified once (``seed = -1``), a noisy one once per seed
    ``seeds["first"] ... seeds["first"] + seeds["count"] - 1``. With
    ``chunk`` (0-based, see :func:`modal.thesis.chunks.seed_chunks`) only that
    chunk's seeds are run, and the noise-free cases only in chunk 0;
    :func:`modal.thesis.chunks.merge_chunks` with ``group_by="case"`` gives
    back the unsplit result. ``n_identified``
    (spillover, Sec. 6.3) repeats each method with n = 3, 4, ...: the TCM on
    the first n sensors, ERA and CERA with ``n_modes = n``. ``cols_sweep``
    repeats the CERA over Hankel widths s. ``noise_model`` (optional:
    ``scale`` and ``velocity`` of :func:`modal.structures.with_noise`) says
    how the noise is defined; by default noise of each channel's RMS on
    every signal. With ``velocity: integrated`` the noise-free cases, too,
    see velocities integrated from their accelerations.

    Returns
    -------
    DataFrame
        One row per identified mode with labels ``case, damping, noise,
        method, n, cols, seed`` and the :meth:`ModalResult.to_frame` columns
        (``damping_id`` is the identified damping ratio), plus ``actual``, the
        exact frequency of that mode number, and ``participating``, the
        number of modes in the response.
    """
    frames = []
    noise_model = dict(study.get("noise_model", {}))
    integrated = noise_model.get("velocity") == "integrated"  # noise-free cases integrate too
    noisy_seeds = chunk_seeds(seeds, chunk)
    if chunk not in (None, 0) and all(c["noise"] == 0 for c in study_cases(study).values()):
        raise ValueError(f"chunk: a study without noise has only chunk 0, got {chunk}")
    for case, params in study_cases(study).items():
        if params["noise"] == 0 and chunk not in (None, 0):
            continue
        record = beam_record(beam_spec, params["damping"])
        seed_list = [-1] if params["noise"] == 0 else noisy_seeds
        for seed in seed_list:
            noisy = (with_noise(record, params["noise"], max(seed, 0), **noise_model)
                     if seed >= 0 or integrated else record)
            for method, settings in study["methods"].items():
                for n, cols, kwargs, channels in _variants(study, method, settings, record.acceleration.shape[1]):
                    result = identify(noisy, method, kwargs, interpretation[method], channels)
                    frames.append(_frame(result, case=case, damping=params["damping"], noise=params["noise"],
                                         method=method, n=n, cols=cols, seed=seed))
    out = pd.concat(frames, ignore_index=True)
    exact = record.omega  # undamped frequencies: the same for every case
    out["actual"] = [exact[m - 1] if m <= exact.size else np.nan for m in out["mode"]]
    out["participating"] = exact.size
    return out


def _variants(study, method, settings, n_channels):
    """(n, cols, keyword arguments, channels) for each run of one method."""
    ns = study.get("n_identified") or [settings.get("n_modes", n_channels)]
    base = settings.get("cols")
    widths = [base] + ([c for c in study.get("cols_sweep", []) if c != base] if method == "cera" else [])
    for n in ns:
        kwargs, channels = dict(settings), None
        if study.get("n_identified"):
            if method == "tcm":
                channels = list(range(n))
            else:
                kwargs["n_modes"] = n
        for cols in widths:
            yield n, (-1 if cols is None else cols), (kwargs if cols is None else {**kwargs, "cols": cols}), channels
