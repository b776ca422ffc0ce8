"""Mutation run of the harmonic check, the channel levels and the lowest-peak rows against their fast tests.

    .venv/bin/python benchmarks/mutation_harmonics.py --list                 # the mutants only
    .venv/bin/python benchmarks/mutation_harmonics.py --workers 1 --json h.json
    .venv/bin/python benchmarks/mutation_harmonics.py --workers 1 --again h.json   # its survivors, after new tests

The machinery is :mod:`mutation_campaign`'s (the same systematic edits, a
forked child per mutant on its own copy of the tree, a timeout); only the
targets, the tests and the list of equivalent survivors
(``benchmarks/mutation_harmonics_equivalent.txt``) differ. Targets:

- ``modal/identification/_envelope.py``: ``envelope_variation``, ``steady``
  and the module's constants (the thresholds and the band are the rule);
- ``modal/measured/_pipeline.py``: ``with_harmonic_check``, ``_with_columns``,
  ``_with_reasons``, ``lowest_peak_hz``, ``spectral_peaks`` (the peaks and
  their heights) and the constant ``LOWEST_PEAK_BINS``, and within
  ``identify_record`` only the block-rows and band rule from the peaks (the
  ``elif rows is None:`` branch) and the harmonic check's call and log line;
- ``modal/identification/_stabilisation.py``: ``channel_levels`` and, of the
  single-channel flag, the lines that use the levels (``stabilisation``'s
  call, ``_select_modes``' ``visible``, ``_flags``' share and its test).

Parts of a function are chosen by their lines (``LINES``: a target's
mutants are kept when their line is among those of the given markers), so
that a long function is not mutated whole.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

ENVELOPE = "modal/identification/_envelope.py"
PIPELINE = "modal/measured/_pipeline.py"
STABILISATION = "modal/identification/_stabilisation.py"

machinery.TARGETS = [(ENVELOPE, None), (ENVELOPE, "envelope_variation"), (ENVELOPE, "steady"),
                     (PIPELINE, "with_harmonic_check"), (PIPELINE, "_with_columns"), (PIPELINE, "_with_reasons"),
                     (PIPELINE, "lowest_peak_hz"), (PIPELINE, "spectral_peaks"), (PIPELINE, "identify_record"), (PIPELINE, None),
                     (STABILISATION, "channel_levels"), (STABILISATION, "stabilisation"),
                     (STABILISATION, "_select_modes"), (STABILISATION, "_flags")]

#: (path, function) -> the lines kept: each marker is a line's text, or a pair (first, last): the lines from
#: the first holding ``first`` to the one before the next holding ``last``
LINES = {
    (ENVELOPE, None): [("HARMONIC_CV = ", "def envelope_variation(")],  # the constants, not the functions again
    (PIPELINE, None): ["LOWEST_PEAK_BINS = "],
    (PIPELINE, "identify_record"): [("    elif rows is None:", "    if options.highpass_hz is not None:"),
                                    "result = with_harmonic_check(result, y, dt)",
                                    'harmonics = freq_hz[[HARMONIC in flag', 'if len(harmonics):',
                                    'log("steady amplitude (a harmonic'],
    (STABILISATION, "stabilisation"): ["channel_levels=channel_levels("],
    (STABILISATION, "_select_modes"): ["visible = np.abs(mode_shapes) / "],
    (STABILISATION, "_flags"): ["energy = visible**2", "share = energy.max(axis=0)",
                                "if len(visible) >= MIN_CHANNELS_ALIKE and share[k]", 'reasons.append("single channel")'],
}


def lines_of(path: str, markers) -> set[int]:
    text = (machinery.ROOT / path).read_text().splitlines()
    kept = set()
    for marker in markers:
        first, last = (marker, None) if isinstance(marker, str) else marker
        found = [k for k, line in enumerate(text, 1) if first in line]
        if len(found) != 1:
            raise SystemExit(f"{path}: {first!r} found on {len(found)} lines, not one")
        end = found[0] if last is None else next(k for k in range(found[0] + 1, len(text) + 1)
                                                  if last in text[k - 1]) - 1
        kept.update(range(found[0], end + 1))
    return kept


_all_mutants = machinery.mutants


def mutants(path: str, function: str | None) -> list[dict]:
    found = _all_mutants(path, function)
    if (path, function) in LINES:
        kept = lines_of(path, LINES[path, function])
        found = [m for m in found if m["line"] in kept]
    return found


machinery.mutants = mutants

TRUST = "tests/engine/identification/test_selection_trust.py::"
HARMONICS = "tests/engine/identification/test_harmonics.py::"
MUTANTS = "tests/engine/identification/test_mode_selection_mutants.py::"
AUTO_BAND = "tests/engine/identification/test_auto_band.py::"
NEW_ENVELOPE = [HARMONICS + t for t in (
    "test_the_band_is_f_plus_minus_four_zeta_f_or_a_percent_of_f_its_edges_included",
    "test_the_band_stops_at_bin_1_and_at_the_nyquist_bin",
    "test_a_band_of_three_bins_is_judged_of_two_not_even_at_the_nyquist_bin",
    "test_a_mode_the_record_does_not_hold_and_no_modes")]
CHECK = HARMONICS + "test_the_harmonic_check_adds_its_columns_last_and_its_reason_after_the_others"
machinery.TESTS = {  # the quickest first
    "_envelope.py": [HARMONICS + t for t in (
        "test_steady_needs_a_steady_envelope_over_enough_correlation_times",
        "test_a_band_too_narrow_to_judge_is_nan_and_bad_input_is_refused",
        "test_a_random_mode_varies_a_harmonic_does_not")] + NEW_ENVELOPE + [
        CHECK, HARMONICS + "test_identify_record_flags_a_wandering_harmonic_and_no_mode"],
    "_pipeline.py": [MUTANTS + t for t in (
        "test_lowest_peak_needs_six_db_of_prominence", "test_lowest_peak_in_a_spectrum_with_empty_bins",
        "test_lowest_peak_lies_above_three_bins", "test_lowest_peak_lies_above_ten_periods_per_record",
        "test_lowest_peak_weighs_every_channel_alike", "test_lowest_peak_welch_segments",
        "test_lowest_peak_of_a_sine_in_noise_is_its_frequency_in_hz",
        "test_lowest_peak_of_short_and_silent_records", "test_settings_from_the_lowest_peak[3.0-10-lines3-1]",
        "test_settings_from_the_lowest_peak[0.4-10-lines5-4]", "test_settings_from_the_lowest_peak[0.75-10-lines2-2]",
        "test_settings_from_the_lowest_peak[None-10-lines0-1]", "test_settings_from_the_lowest_peak[20.0-10-lines6-1]",
        "test_a_free_decay_keeps_three_periods_and_sixty_rows[10-None]",
        "test_a_free_decay_keeps_three_periods_and_sixty_rows[10-line0]")] + [
        AUTO_BAND + "test_peaks_ascending_above_the_floor",
        AUTO_BAND + "test_a_peaks_height_is_over_the_median_within_a_quarter_of_its_frequency",
        AUTO_BAND + "test_a_band_too_wide_for_one_model_is_logged",
        AUTO_BAND + "test_a_beams_modes_up_to_the_highest_peak_with_default_options",
        AUTO_BAND + "test_maxima_of_a_noise_floor_do_not_widen_the_band"] + [
        CHECK, HARMONICS + "test_the_log_names_every_harmonic_in_one_line",
        HARMONICS + "test_identify_record_flags_a_wandering_harmonic_and_no_mode"],
    "_stabilisation.py": [TRUST + t for t in (
        "test_channel_levels_are_taken_in_the_highest_derivative",
        "test_the_level_of_one_channel_or_of_one_quantity_is_its_rms_over_every_set",
        "test_a_mode_in_one_channel_of_several_is_flagged", "test_damping_bounds_and_the_share_are_inclusive",
        "test_single_channel_is_judged_on_each_channels_own_level")],
}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_harmonics_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
