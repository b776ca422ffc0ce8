"""Rule report of ``modal campaign``: the self-contained HTML report."""

from modal.campaign import report_campaign

report_campaign(".", snakemake.params.n_records, snakemake.config["campaign"],  # noqa: F821 (given by Snakemake)
                snakemake.config.get("command", ""))  # noqa: F821
