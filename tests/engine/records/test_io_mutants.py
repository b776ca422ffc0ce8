"""Record readers: behaviours pinned by mutation testing
(benchmarks/mutation_records.py): exact rates, delimiters, headers and
channels of small records written to tmp_path."""

import numpy as np
import pytest

from modal.records import load_record, read_record, unit_key


@pytest.mark.parametrize("spelling, key", [
    ("m/s^2", "m/s2"), ("m s^-2", "m/s2"), ("m·s⁻²", "m/s2"), ("M/S**2", "m/s2"), (" m/s² ", "m/s2"),
    ("m s-1", "m/s"), ("µm/s", "um/s"), ("\u03bcm", "um"), ("mm s^-1", "mm/s"), ("g", "g"), ("s-3", "s-3"),
])
def test_unit_key_spellings(spelling, key):
    assert unit_key(spelling) == key
