"""Mutation run of the spike check's screen against its fast tests.

    .venv/bin/python benchmarks/mutation_quality.py --workers 1                 # all mutants, one at a time
    .venv/bin/python benchmarks/mutation_quality.py --list                      # the mutants only
    .venv/bin/python benchmarks/mutation_quality.py --workers 1 --within _within --json q.json
    .venv/bin/python benchmarks/mutation_quality.py --workers 1 --again q.json  # the survivors, after adding tests

The machinery is :mod:`mutation_campaign`'s (the same systematic edits, a
forked child per mutant on its own copy of the tree, a timeout); only the
targets, the tests and the list of equivalent survivors
(``benchmarks/mutation_quality_equivalent.txt``) differ. Targets, in
``modal/records/_quality.py``: ``_within`` (the screen that tells, without
the variation's second median, that no second difference reaches the edge)
and, of ``_spike_runs`` (the one function that calls it), the lines that
use it: from the edge it is given to the variation's check that follows it
(``USE``; the rest of the rule is not mutated here).

The tests are the fast ones of ``tests/engine/records/test_spikes.py`` (not
the identification of a record, not the records beside the project), the
quickest first: the child stops at the first failure. The command-line test
starts the command's parser and reads a file, so it comes last.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

SOURCE = "modal/records/_quality.py"
FUNCTIONS = ("_within", "_spike_runs")
SPIKES = "tests/engine/records/test_spikes.py::"

#: the fast spike tests: the screen's own first, the command line last
SPIKE_TESTS = [SPIKES + t for t in (
    "test_the_screen_on_second_differences_small_enough_to_check_by_hand",
    "test_the_screen_tells_only_what_is_true", "test_the_screen_gives_the_rules_result",
    "test_the_statistic_is_the_departure_over_the_channel_variation_whatever_its_curvature",
    "test_a_dead_channel_has_no_spike_and_the_others_are_still_checked",
    "test_a_spike_is_found_sample_for_sample_in_its_own_channel",
    "test_the_threshold_is_fifty_times_the_channel_variation",
    "test_what_is_not_a_spike", "test_the_onset_of_an_impact_is_not_a_spike_but_a_spike_in_its_decay_is",
    "test_a_spike_before_an_impact_is_judged_by_what_follows_it",
    "test_despiked_puts_the_samples_on_the_line_between_their_neighbours",
    "test_the_warning_names_the_channel_the_count_and_the_times", "test_no_spike_in_the_shipped_records",
    "test_simulated_ambient_and_impact_records_raise_no_alarm",
    # starts the command's parser, last
    "test_cli_names_the_channel_and_the_count")]

#: _spike_runs's use of the screen: the lines from the first of these statements to the second, both included
USE = ("edge = 0.5 * SPIKE_EDGE * threshold", "if not variation > 0:")


def _use_lines() -> range:
    lines = (machinery.ROOT / SOURCE).read_text().splitlines()
    first, last = (next(k for k, line in enumerate(lines, 1) if line.strip() == text) for text in USE)
    return range(first, last + 2)  # and the return under the check


_all_mutants = machinery.mutants


def mutants(path, function):
    found = _all_mutants(path, function)
    return found if function != "_spike_runs" else [m for m in found if m["line"] in _use_lines()]


machinery.mutants = mutants
machinery.TARGETS = [(SOURCE, name) for name in FUNCTIONS]
machinery.TESTS = {"_quality.py": SPIKE_TESTS}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_quality_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
