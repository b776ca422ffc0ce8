"""Mutation run of the mode selection (issue 32) against its fast tests.

    .venv/bin/python benchmarks/mutation_selection.py            # all mutants, 2 at a time
    .venv/bin/python benchmarks/mutation_selection.py --list     # the mutants only
    .venv/bin/python benchmarks/mutation_selection.py --json v.json

The machinery is :mod:`mutation_campaign`'s (the same systematic edits, a
forked child per mutant on its own copy of the tree, a timeout); only the
targets, the tests and the list of equivalent survivors
(``benchmarks/mutation_selection_equivalent.txt``) differ. Targets: the
functions of ``modal/identification/_stabilisation.py`` that select,
judge and flag modes, state second estimates and notes, join clusters split
across orders, and check the criteria, and the segments' standard deviation
(``segment_std``) whose seed pole the selection now picks, and the
blends of two close modes that the spectral witness names (``blends``).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

SOURCE = "modal/identification/_stabilisation.py"
FUNCTIONS = ("_select_modes", "_consistent", "_shape_scatter", "_second_estimates", "_flags", "_side_bands", "_notes",
             "doubtful_note",
             "trusted_modes", "__post_init__", "_join_split_clusters", "segment_std",
             "matched_eigenvalues", "blends")
TRUST = "tests/engine/identification/test_selection_trust.py"
STAB = "tests/engine/identification/test_stabilisation.py::"
MUTANTS = "tests/engine/identification/test_mode_selection_mutants.py::"
SELECTION = "tests/engine/identification/test_mode_selection.py::"

machinery.TARGETS = [(SOURCE, name) for name in FUNCTIONS]
machinery.TESTS = {"_stabilisation.py": [TRUST, "tests/engine/identification/test_side_bands.py",
                                         "tests/engine/identification/test_blends.py"] + [STAB + t for t in (
    "test_stability_criteria_bounds_and_names", "test_select_modes_on_a_known_pole_table",
    "test_select_modes_needs_min_poles_candidates", "test_select_modes_without_a_large_enough_cluster",
    "test_select_modes_joins_groups_by_average_linkage", "test_select_modes_weighs_damping_with_frequency",
    "test_select_modes_numbers_modes_by_mean_frequency", "test_select_modes_one_pole_modes_have_nan_spread_silently",
    "test_stabilisation_stops_at_the_numerical_rank")] + [MUTANTS + t for t in (
        "test_one_mode_table_types", "test_no_mode_warning_names_the_reason_at_the_caller",
        "test_select_modes_small_tables", "test_select_modes_medoid_is_the_central_pole",
        "test_select_modes_candidates_need_half_of_min_poles", "test_select_modes_cut_at_cluster_distance",
        "test_select_modes_same_order_poles_never_share_a_cluster", "test_select_modes_spread_and_candidate_table",
        "test_select_modes_cuts_by_distance_and_sorts_candidates",
        "test_join_split_clusters_nearest_pair_among_many")] + [
    SELECTION + "test_a_mode_split_across_orders_is_joined", SELECTION + "test_documented_defaults"] + [
    "tests/engine/measured/test_uncertainty.py::" + t for t in (  # the fast ones: not the 40-record coverage
        "test_segments_that_agree_give_no_uncertainty", "test_two_segments_a_percent_apart",
        "test_two_segments_damped_ten_percent_apart", "test_a_segment_without_an_estimate_is_not_counted",
        "test_each_mode_takes_its_own_eigenvalue_when_modes_are_close",
        "test_each_eigenvalue_of_a_segment_is_one_modes", "test_two_close_modes_take_a_segments_two_eigenvalues",
        "test_segments_that_agree_with_each_other_but_not_with_the_record_give_their_bias",
        "test_each_mode_takes_the_state_matrix_of_its_own_fullest_order",
        "test_a_segment_singular_at_one_order_still_counts_at_the_others")]}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_selection_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
