"""Test structures with known modes: the simply supported beam and plate and their
simulated responses (thesis Ch. 5-6), the finite-element model of the grid
and its virtual shaking test (Ch. 7)."""

from ._beam import SimplySupportedBeam
from ._grid import Grid
from ._plate import SimplySupportedPlate, ambient_response
from ._shake_test import ShakeTest, pick_peaks, select_sharpest, shake_test, sharpness
from ._simulate import Record, add_noise, beam_impulse_response, damping_ratios, impulse_response, with_noise

__all__ = [
    "Grid", "Record", "ShakeTest", "SimplySupportedBeam", "SimplySupportedPlate", "add_noise", "ambient_response",
    "beam_impulse_response", "damping_ratios",
    "impulse_response", "pick_peaks", "select_sharpest", "shake_test", "sharpness", "with_noise",
]
