"""The generalised Hankel matrix (thesis Eq. 34): its size against the record."""

import numpy as np
import pytest

import modal

DT = 0.01


@pytest.fixture
def y():
    t = DT * np.arange(400)
    return np.column_stack([np.sin(2 * t), np.sin(5 * t + 1), np.cos(9 * t)])


@pytest.mark.parametrize("method", ["era", "cera"])
def test_hankel_larger_than_record(y, method):
    call = {"era": lambda: modal.era(y, DT, 1, 5, 400), "cera": lambda: modal.cera(y, DT, 1, 400)}[method]
    with pytest.raises(ValueError, match="reduce rows or cols"):
        call()


def test_hankel_rows_too_many(y):
    with pytest.raises(ValueError, match="reduce rows or cols"):
        modal.era(y, DT, 1, rows=301, cols=100)  # needs 402 samples with H(1)
