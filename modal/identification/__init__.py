"""Identification: the thesis's three methods and what they share.

The generalised Hankel matrix (Eq. 34), the Eigensystem Realization
Algorithm (Eqs. 34-45), the Temporal Correlation Method (Eqs. 21-31), the
Constrained ERA (Eqs. 46-52), accuracy indicators (MAC, MPC, MAMC), the
common result (:class:`ModalResult`) and the stabilisation diagram with
automatic mode selection (drawn by :func:`stabilisation_figure`), and
its spectral witness, frequency domain decomposition (:func:`fdd`).
"""

from ._cera import cera
from ._envelope import envelope_variation, steady
from ._era import era
from ._era_kernels import decompose
from ._fdd import (PEAK_HEIGHT_DB, PEAK_PROMINENCE_DB, SHARED_PEAK, SHARED_PEAK_MAC, SingularValueSpectrum, auto_mac,
                   efdd, fdd, height_above_median_db, own_shapes, shared_peaks, spectral_support)
from ._figures import stabilisation_figure
from ._hankel import hankel
from ._indicators import align_shapes, mac, modal_amplitude_coherence, modal_phase_collinearity, quadrature_groups
from ._result import FLAGS, ModalResult, ModalWarning, normalise_complex_shapes, normalise_shapes
from ._stabilisation import (BLEND, DAMPED_ABOVE, QUANTITIES, SAME_SHAPE, Stabilisation, StabilityCriteria, blends,
                             doubtful_note, segment_std, stabilisation)
from ._tcm import tcm

# envelope_variation and steady (harmonics told by their steady amplitude), quadrature_groups (channels a
# derivative apart), QUANTITIES (what a channel may measure), SAME_SHAPE, DAMPED_ABOVE, doubtful_note,
# SHARED_PEAK(_MAC), PEAK_PROMINENCE_DB, PEAK_HEIGHT_DB, height_above_median_db, own_shapes, segment_std,
# normalise_shapes, normalise_complex_shapes, shared_peaks, BLEND and
# blends are importable from here for the other subpackages (a channel table checks its quantities
# against QUANTITIES; a campaign averages shapes by the identification's scaling; the witness of a
# record names modes on one peak, leaves the selection's same-shape pairs alone and names blends of
# two modes; a record's band keeps the peaks that stand above their floor); the names below are also
# re-exported by modal.
__all__ = [
    "FLAGS", "ModalResult", "ModalWarning", "SingularValueSpectrum", "Stabilisation", "StabilityCriteria",
    "align_shapes", "auto_mac", "cera", "decompose", "efdd", "era", "fdd", "hankel", "mac",
    "modal_amplitude_coherence", "modal_phase_collinearity", "spectral_support", "stabilisation", "stabilisation_figure", "tcm",
]
