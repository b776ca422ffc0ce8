# Regenerates the thesis's tables and figures. Run through
# `bash workflow/regenerate.sh` (sets up .venv first) or `snakemake --cores all`.
from snakemake.utils import min_version, validate

min_version("8.0")


configfile: "config/config.yaml"


validate(config, "workflow/schemas/config.schema.yaml")

import modal.thesis.config

modal.thesis.config.check(config)


include: "workflow/rules/common.smk"
include: "workflow/rules/beam.smk"
include: "workflow/rules/grid.smk"
include: "workflow/rules/measured.smk"
include: "workflow/rules/report.smk"


rule all:
    input:
        beam_outputs(),
        grid_outputs(),
        measured_outputs(),
        report_outputs(),
