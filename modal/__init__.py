"""modal: the engine of the modal-identification workflow.

TCM (Eqs. 21-31), ERA (Eqs. 34-45) and CERA (Eqs. 46-52) of the thesis
"Experimental Verification and Development of Structural Identification
Techniques on a Grid", with beam simulation, preprocessing and indicators,
the finite-element grid and its virtual shaking test (Ch. 7), record I/O,
and operational modal analysis of measured records (NExT correlations, a
stabilisation diagram with automatic mode selection, ``modal identify``).

The names below are loaded on first use (PEP 562), so ``import modal`` and
``import modal.thesis.chunks`` import no numpy, pandas or scipy: a workflow
job that only merges files, or Snakemake reading the config, does not pay
for the engine.
"""

import importlib
import sys
import types

# Each public name and the submodule that defines it.
_SOURCES = {
    "cera": "cera",
    "correlations": "correlation",
    "era": "era",
    **dict.fromkeys(["ShakeTest", "pick_peaks", "select_sharpest", "shake_test", "sharpness"], "experiment"),
    "Grid": "grid",
    "hankel": "hankel",
    **dict.fromkeys(["MeasuredRecord", "load_record", "read_record", "save_record_npz", "write_uff58"], "io"),
    **dict.fromkeys(["align_shapes", "mac", "modal_amplitude_coherence", "modal_phase_collinearity"], "indicators"),
    **dict.fromkeys(["ModalResult", "ModalWarning"], "result"),
    **dict.fromkeys(["amplitude_spectrum", "decay_start", "decimate", "detrend", "integrate_acceleration",
                     "lowpass_fft", "split_record", "zero_phase_filter"], "signals"),
    **dict.fromkeys(["Record", "add_noise", "beam_impulse_response", "impulse_response", "with_noise"], "simulate"),
    **dict.fromkeys(["Stabilisation", "StabilityCriteria", "identify_record", "stabilisation",
                     "stabilisation_figure"], "stabilisation"),
    "SimplySupportedBeam": "structures",
    "tcm": "tcm",
}
__all__ = sorted(_SOURCES)


def __getattr__(name):
    """Import the submodule defining ``name`` on first use (``modal.era``)."""
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_SOURCES[name]}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted({*globals(), *__all__})


class _Package(types.ModuleType):
    """``modal`` itself: keeps ``modal.era``, ``modal.tcm``, ``modal.cera``,
    ``modal.hankel`` and ``modal.stabilisation`` the functions.

    Python binds a submodule to its package's attribute when it first loads
    it (``import modal.thesis.study`` loads ``modal.era``), which would
    replace the function of the same name by the module; here the function
    is bound instead. The submodule stays in ``sys.modules`` (reach it with
    ``importlib.import_module("modal.era")``).
    """

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and _SOURCES.get(name) == value.__name__.rpartition(".")[2]:
            value = getattr(value, name)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
