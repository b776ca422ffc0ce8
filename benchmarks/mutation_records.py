"""Mutation run of the record readers against their fast tests.

    .venv/bin/python benchmarks/mutation_records.py --workers 1                 # all mutants, one at a time
    .venv/bin/python benchmarks/mutation_records.py --list                      # the mutants only
    .venv/bin/python benchmarks/mutation_records.py --workers 1 --within _load_csv,_sniff_delimiter --json r.json
    .venv/bin/python benchmarks/mutation_records.py --workers 1 --again r.json  # the survivors, after adding tests

The machinery is :mod:`mutation_campaign`'s (the same systematic edits, a
forked child per mutant on its own copy of the tree, a timeout); only the
targets, the tests and the list of equivalent survivors
(``benchmarks/mutation_records_equivalent.txt``) differ. Targets, whole:
``modal/records/_io.py`` (``read_record`` and its readers of ``.npy``,
``.npz``, CSV and whitespace text, LabVIEW ``.lvm`` and UFF 58, and the
writers ``save_record_npz`` and ``write_uff58``) and
``modal/records/_units.py`` (``unit_key``, the one spelling of a unit).

The tests are the fast ones that read records (no Snakemake run, no
identification of a measured record), the quickest first: the child stops
at the first failure. The FIFO and device refusals start a Python process
each (about a second), so they come last.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mutation_campaign as machinery  # noqa: E402

RECORDS = "tests/engine/records/"
REFUSALS = RECORDS + "test_read_refusals.py::"
SETUPS = "tests/engine/setups/test_setups.py::"

#: read_record and its readers: records written to tmp_path, read back.
READING = [RECORDS + "test_io_mutants.py", RECORDS + "test_io.py"] + [REFUSALS + t for t in (
    "test_directory_is_refused", "test_csv_whose_last_row_is_cut_short_is_refused_naming_the_row",
    "test_uff_cut_short_is_refused_not_read_as_fewer_channels", "test_corrupt_uff_is_refused_naming_the_file",
    "test_lvm_with_fewer_rows_than_its_header_says_is_refused", "test_npy_without_a_rate_says_how_to_give_it",
    "test_non_numeric_npy_is_refused", "test_non_numeric_npz_is_refused", "test_csv_header_names_the_channels")] + [
    "tests/engine/test_bad_input.py::test_more_bad_input",
    # a child process each, last
    REFUSALS + "test_fifo_is_refused_without_blocking", REFUSALS + "test_device_is_refused_without_reading_it"]

#: unit_key: the channel tables' units and a campaign's records' units.
UNITS = [SETUPS + "test_unit_spellings_are_one_unit", SETUPS + "test_a_unit_of_another_quantity_is_refused",
         RECORDS + "test_io_mutants.py::test_unit_key_spellings",
         "tests/workflow/test_campaign_units.py::test_a_record_in_other_units_fails_naming_them"]

machinery.TARGETS = [("modal/records/_io.py", None), ("modal/records/_units.py", None)]
machinery.TESTS = {"_io.py": READING, "_units.py": UNITS}
machinery.EQUIVALENT = machinery.ROOT / "benchmarks" / "mutation_records_equivalent.txt"

if __name__ == "__main__":
    sys.exit(machinery.main())
