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
``refined_hz``, ``maxima_near``, ``supporting_peak``, ``matching_maximum``), the enhanced FDD (``efdd``,
``_efdd``, ``_window_correlation``), the support check
(``support_tolerance_hz``, ``spectral_support``, ``own_shapes``), two modes on one peak
(``shared_peaks``) and ``auto_mac``; and of ``modal/measured/_pipeline.py``
the witness of a record (``with_spectral_witness``, ``onset_spectrum``)
with the damping it vouches for (``_without_reasons``, ``_vouched_notes``).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

SOURCE = "modal/identification/_fdd.py"
FUNCTIONS = ("df", "decibels", "height_above_median_db", "peaks", "refined_hz", "maxima_near", "supporting_peak", "matching_maximum", "fdd", "efdd",
             "_window_correlation", "_efdd", "support_tolerance_hz", "spectral_support", "own_shapes", "shared_peaks",
             "auto_mac")  # not the module's constants

PIPELINE = "modal/measured/_pipeline.py"
PIPELINE_FUNCTIONS = ("with_spectral_witness", "onset_spectrum", "_without_reasons", "_vouched_notes",
                      "quadrature_warning")
INDICATORS = "modal/identification/_indicators.py"  # the channels a derivative apart, which the record's warning names
PIPELINE_TESTS = "tests/engine/measured/test_pipeline.py::"

machinery.TARGETS = [(SOURCE, name) for name in FUNCTIONS] + [(PIPELINE, name) for name in PIPELINE_FUNCTIONS] + [
    (INDICATORS, "quadrature_groups")]
machinery.TESTS = {"_fdd.py": [  # the quickest first
    "tests/engine/identification/test_fdd.py",
    "tests/engine/identification/test_shape_support.py",
    "tests/engine/identification/test_auto_band.py::test_a_peaks_height_is_over_the_median_within_a_quarter_of_its_frequency",
    "tests/engine/measured/test_pipeline.py::test_spectral_witness_compares_shapes_in_each_channels_quantity",
    "tests/engine/measured/test_pipeline.py::test_a_second_mode_on_the_first_ones_peak_and_shape_is_named_so",
    "tests/engine/measured/test_report.py::test_modes_are_checked_against_the_singular_value_peaks",
    "tests/engine/measured/test_report.py::test_mac_csv_is_the_auto_mac_of_the_complex_shapes"],
    "_pipeline.py": [PIPELINE_TESTS + t for t in (
        "test_the_witness_carries_each_entry_into_its_channels_quantity_by_the_damped_pole",
        "test_a_free_decays_onset_spectrum_supports_a_mode_within_its_half_power_band",
        "test_the_onset_spectrums_first_window_peaks_at_the_impact",
        "test_a_mode_with_a_peak_of_its_own_keeps_no_implausibly_high_damping",
        "test_a_heavily_damped_mode_with_its_own_peak_is_trusted",
        "test_a_second_mode_on_the_first_ones_peak_and_shape_is_named_so",
        "test_spectral_witness_compares_shapes_in_each_channels_quantity",
        "test_a_mode_that_decays_within_a_welch_segment_has_its_peak_in_a_free_decay",
        "test_velocities_among_accelerations_taken_as_one_quantity_draw_a_warning",
        "test_the_quadrature_warning_judges_only_well_identified_shapes")] + [
        "tests/engine/identification/test_shape_support.py::test_the_witness_asks_the_selections_trusted_modes_for_the_shape",
        "tests/engine/identification/test_shape_support.py::test_a_free_decays_onset_spectrum_supports_by_direction_too",
        "tests/engine/identification/test_shape_support.py::test_a_peak_of_exactly_the_bound_takes_an_implausible_damping_back",
        "tests/engine/identification/test_blends.py",
        "tests/engine/identification/test_shape_support.py::test_a_direction_does_not_take_back_an_implausibly_high_damping",
        "tests/engine/identification/test_shape_support.py::test_a_storey_frames_overlapping_upper_modes_are_each_trusted_once",
        "tests/engine/measured/test_report.py::test_modes_are_checked_against_the_singular_value_peaks"],
    "_indicators.py": ["tests/engine/identification/test_indicators.py",
                       PIPELINE_TESTS + "test_velocities_among_accelerations_taken_as_one_quantity_draw_a_warning"]}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_witness_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
