"""Mutation run of the spectral witness (FDD) against its fast tests.

    .venv/bin/python benchmarks/mutation_witness.py --workers 1            # all mutants, one at a time
    .venv/bin/python benchmarks/mutation_witness.py --list                 # the mutants only
    .venv/bin/python benchmarks/mutation_witness.py --workers 1 --json w.json

The machinery is :mod:`mutation_campaign`'s (the same systematic edits, a
forked child per mutant on its own copy of the tree, a timeout); only the
targets, the tests and the list of equivalent survivors
(``benchmarks/mutation_witness_equivalent.txt``) differ. Target: every
function of ``modal/identification/_fdd.py``: the singular-value spectrum
(``fdd``, ``SingularValueSpectrum.df``, ``decibels``, ``peaks``,
``refined_hz``, ``supporting_peak``), the enhanced FDD (``efdd``,
``_efdd``, ``_window_correlation``), the support check
(``support_tolerance_hz``, ``spectral_support``), two modes on one peak
(``shared_peaks``) and ``auto_mac``.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

SOURCE = "modal/identification/_fdd.py"
FUNCTIONS = ("df", "decibels", "peaks", "refined_hz", "supporting_peak", "fdd", "efdd", "_window_correlation", "_efdd",
             "support_tolerance_hz", "spectral_support", "shared_peaks", "auto_mac")  # not the module's constants

machinery.TARGETS = [(SOURCE, name) for name in FUNCTIONS]
machinery.TESTS = {"_fdd.py": [  # the quickest first
    "tests/engine/identification/test_fdd.py",
    "tests/engine/measured/test_pipeline.py::test_spectral_witness_compares_shapes_in_each_channels_quantity",
    "tests/engine/measured/test_pipeline.py::test_a_second_mode_on_the_first_ones_peak_and_shape_is_named_so",
    "tests/engine/measured/test_report.py::test_modes_are_checked_against_the_singular_value_peaks",
    "tests/engine/measured/test_report.py::test_mac_csv_is_the_auto_mac_of_the_complex_shapes"]}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_witness_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
