"""Rule track of ``modal campaign``: gather the chunks, number the modes."""

from modal.campaign import read_campaign, track_campaign

_, index = read_campaign(snakemake.config["campaign"])  # noqa: F821 (given by Snakemake)
track_campaign(snakemake.input.modes, snakemake.input.failed, index, snakemake.params.tracking, ".")  # noqa: F821
