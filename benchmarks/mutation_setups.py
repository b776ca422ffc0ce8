"""Mutation run of the roving tests' code (issue 33) against its fast tests.

    .venv/bin/python benchmarks/mutation_setups.py                 # all mutants, 2 at a time
    .venv/bin/python benchmarks/mutation_setups.py --list          # the mutants only
    .venv/bin/python benchmarks/mutation_setups.py --only _merge.py --json merge.json
    .venv/bin/python benchmarks/mutation_setups.py --again merge.json   # the survivors, after adding tests

The machinery is :mod:`mutation_campaign`'s (the same systematic edits, a
forked child per mutant on its own copy of the tree, a timeout); only the
targets, the tests and the list of equivalent survivors
(``benchmarks/mutation_setups_equivalent.txt``) differ. Targets: the
modules of ``modal/setups/`` that hold logic, whole: the merge
(``_merge.py``), the checks that the setups agree (``_agreement.py``), the
channel tables (``_channels.py``), the geometry (``_geometry.py``) and the
results written to a folder (``_results.py``). The drawing
(``_drawing.py``) and the simulated plate (``_simulated.py``, the tests'
own data) are not mutated.

The tests are the fast ones that reach each module (no Snakemake run, not
the Weimar frame's 15 identifications, not the simulated plate's
identifications marked slow), the quickest first: the child stops at the
first failure.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

CHECKS = "tests/engine/setups/test_merge_checks.py::"
SETUPS = "tests/engine/setups/test_setups.py::"

#: The merge on synthetic identifications: no identification is run.
SYNTHETIC = [CHECKS + t for t in (
    "test_frequency_uncertainty_and_tolerance", "test_a_constant_frequency_ratio_is_found",
    "test_complex_modes_rescaled_with_a_complex_scale_per_setup_keep_their_phases",
    "test_the_majority_rule_rounds_up_and_needs_both_of_two", "test_a_mode_joins_the_nearest_cluster_within_its_own_scatter",
    "test_a_bad_setup_is_named_and_left_out", "test_one_mode_of_a_setup_that_disagrees_is_left_out_of_that_mode_only",
    "test_normalisation_is_not_set_by_a_node_that_disagrees_with_its_neighbours",
    "test_without_a_geometry_a_node_is_judged_against_three_others_at_least",
    "test_normalisation_flags_down_to_the_first_node_that_agrees_and_no_further",
    "test_a_shape_without_a_finite_or_nonzero_component_is_left_as_it_is",
    "test_what_matches_csv_says_of_a_setup_left_out",
    "test_a_mode_whose_reference_part_is_another_is_left_out_with_its_number",
    "test_a_mode_a_setup_did_not_select_comes_from_its_stable_poles",
    "test_one_setup_without_references_gives_its_own_modes",
    "test_a_node_far_above_its_neighbours_on_the_geometry_is_flagged_in_shapes",
    "test_the_merged_tables_hold_the_setups_statistics_and_directions")] + [
    SETUPS + "test_node_shapes_resolve_oblique_directions", SETUPS + "test_two_close_modes_of_one_setup_stay_two",
    "tests/engine/setups/test_merge_bounds.py", "tests/engine/setups/test_merge_tables.py",
    "tests/engine/setups/test_merge_parts.py"]

#: Reading channel tables, pyOMA's and pyOMA2's files and geometries.
READING = [SETUPS + t for t in (
    "test_direction_from_angles_follows_pyoma", "test_pyoma_layout_is_read", "test_pyoma_layout_refusals",
    "test_channel_table_refusals", "test_channel_table_angles_and_defaults",
    "test_pyoma2_geometry_1_groups_sensors_into_nodes", "test_pyoma_geometry_and_links", "test_geometry_refusals",
    "test_unit_spellings_are_one_unit", "test_a_unit_of_another_quantity_is_refused",
    "test_pyoma_setup_in_latin1_reads_as_in_utf8", "test_channel_table_with_xyz_and_angles_that_disagree_is_refused",
    "test_geometry_files_name_the_bad_row", "test_a_setup_given_twice_through_a_link_is_refused")] + [
    "tests/workflow/test_config_refusals.py::test_roving_test_refusals", "tests/engine/setups/test_setup_reading.py",
    "tests/engine/setups/test_channel_tables.py", "tests/engine/setups/test_geometry_defaults.py"]

#: Identifications (seconds each) and whole commands, last.
IDENTIFYING = [
    CHECKS + "test_declared_velocity_and_displacement_channels_reach_the_identification",
    "tests/engine/measured/test_options.py::test_a_roving_setup_is_identified_with_the_options_and_its_own_channels",
    CHECKS + "test_out_over_an_input_of_the_setups_is_refused_before_any_work",
    SETUPS + "test_roving_report_settings_and_drawing_progress",
    CHECKS + "test_a_setup_with_a_unit_slip_is_named_by_the_command"]

#: The merge's log (log_merge), on synthetic identifications.
LOG = "tests/engine/setups/test_merge_bounds.py::test_the_log_names_each_setup_left_out_and_each_node_flagged"

machinery.TARGETS = [(f"modal/setups/{name}", None)
                     for name in ("_agreement.py", "_merge.py", "_channels.py", "_geometry.py", "_results.py")]
#: The tests of reading a setup (read_setup, check_setups).
SETUP_FILES = [SETUPS + "test_pyoma_layout_is_read", SETUPS + "test_a_setup_given_twice_through_a_link_is_refused",
               "tests/engine/setups/test_setup_reading.py"]

machinery.TESTS = {  # each module's: what reaches it, not more (a survivor runs them all)
    "_agreement.py": SYNTHETIC + IDENTIFYING[-1:],
    "_merge.py": SYNTHETIC + SETUP_FILES + IDENTIFYING,
    "_channels.py": READING + SYNTHETIC + IDENTIFYING[:1],
    "_geometry.py": ["tests/engine/setups/test_geometry_readers.py"] + READING
    + [CHECKS + "test_a_node_far_above_its_neighbours_on_the_geometry_is_flagged_in_shapes"] + IDENTIFYING[2:4],
    "_results.py": [LOG, "tests/engine/setups/test_roving_results.py"] + IDENTIFYING[2:],
}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_setups_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
