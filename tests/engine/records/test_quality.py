"""Clipping: a converter at full scale is named, a quantised or oversampled
peak is not; the warning reaches the caller of ``identify_record``."""

import warnings

import numpy as np
import pytest

import modal
from modal.records import clipped_samples, clipping_warnings

from ..cases import ambient_beam

FULL_SCALE = 32767


def _int16(y, gain):
    """``y`` recorded by a 16-bit converter with ``gain`` counts per unit."""
    return np.clip(np.round(y * gain), -FULL_SCALE - 1, FULL_SCALE)


def _noisy_sine(n=100_000, seed=1):
    t = np.arange(n) / 1000
    return np.sin(2 * np.pi * t) + 0.3 * np.random.default_rng(seed).standard_normal(n)


def test_a_clipped_converter_is_found_sample_for_sample():
    y = _int16(_noisy_sine(), 20_000)  # peaks of about 1.9 x 20000 counts: clipped at both ends
    truth = np.flatnonzero((y == FULL_SCALE) | (y == -FULL_SCALE - 1))
    assert truth.size > 100
    (found,) = clipped_samples(y[:, None])
    np.testing.assert_array_equal(found, truth)


def test_one_sided_clipping_is_found():
    """Only the negative side at full scale: the minimum's pile-up alone."""
    y = _noisy_sine()
    y = _int16(np.where(y < 0, y * 2.0, y * 0.5), 20_000)
    (found,) = clipped_samples(y[:, None])
    np.testing.assert_array_equal(found, np.flatnonzero(y == -FULL_SCALE - 1))
    assert found.size > 50 and not np.any(y[found] > 0)


@pytest.mark.parametrize("record", ["quantised sine", "8-bit noisy sine", "unclipped int16", "beam"])
def test_unclipped_records_are_not_named(record):
    """A pure sine quantised to 8 bits dwells at its top code, but no more
    than at the codes just below: no pile-up."""
    t = np.arange(200_000) / 1000
    y = {"quantised sine": lambda: np.round(127 * np.sin(2 * np.pi * t)),
         "8-bit noisy sine": lambda: np.round(_noisy_sine(200_000) / 2.5 * 127),
         "unclipped int16": lambda: _int16(_noisy_sine(), 12_000),
         "beam": lambda: ambient_beam(60.0)[0]}[record]()
    y = y if y.ndim == 2 else y[:, None]
    assert all(found.size == 0 for found in clipped_samples(y))
    assert clipping_warnings(y, 1000.0) == []


@pytest.mark.parametrize("at_max, at_next, clipped", [(3, 1, True), (6, 2, True), (5, 2, False), (2, 0, False)])
def test_a_pile_up_is_three_times_the_next_level_and_three_samples(at_max, at_next, clipped):
    y = np.r_[np.linspace(-1, 0.5, 50), [0.9] * at_next, [1.0] * at_max]
    (found,) = clipped_samples(y[:, None])
    assert (found.size > 0) == clipped
    if clipped:
        np.testing.assert_array_equal(found, np.arange(50 + at_next, 50 + at_next + at_max))


def test_identify_record_warns_naming_the_channel_and_the_times():
    acc, dt, _ = ambient_beam(200.0)
    acc = acc.copy()
    top = 0.5 * acc[:, 1].max()
    acc[:, 1] = np.minimum(acc[:, 1], top)  # channel 1 clipped at half its peak
    first = np.flatnonzero(acc[:, 1] == top)[0]
    with pytest.raises(ValueError, match="channel_labels: 3 labels for 5 channels used"):
        modal.identify_record(acc, dt, "ambient", channel_labels=["a", "b", "c"])
    with pytest.warns(modal.ModalWarning, match=rf"channel b: clipped\? \d+ samples at its extreme values .* t = "
                                                 rf"{first * dt:.6g}, "):
        modal.identify_record(acc, dt, "ambient", channel_labels=list("abcde"), max_order=20)
    with warnings.catch_warnings():
        warnings.simplefilter("error", modal.ModalWarning)
        messages = clipping_warnings(ambient_beam(200.0)[0], 1 / dt)
    assert messages == []
