"""Every table of rule ``table`` (beam) or ``grid_table`` (grid) in one process:
``params.script`` (table.py or grid_table.py) runs once per table with that
table's ``snakemake`` object (``_helpers.item_job``), so the thesis layer is
imported once instead of once per table. Each table keeps its own log.

By hand: ``python workflow/scripts/tables.py`` (all beam tables), or one
table with its own script, e.g. ``python workflow/scripts/table.py``.
"""
from _helpers import mock_snakemake, run_items

if "snakemake" not in globals():
    snakemake = mock_snakemake("table")
run_items(snakemake, snakemake.params.script)
