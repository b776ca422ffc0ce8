# Regenerates the thesis's tables and figures. Run through
# `bash workflow/regenerate.sh` (sets up .venv first) or `snakemake --cores all`.
from snakemake.utils import min_version

min_version("8.0")


configfile: "config/config.yaml"


# Before any job: every config file re-read strictly (duplicate keys), table
# and figure numbers normalised, the schema (integers are integers), then
# cross-checks, paths and a measured record (modal.thesis.config).
import modal.thesis.config

modal.thesis.config.check_workflow_config(
    config,
    ["config/config.yaml", *workflow.configfiles],
    "workflow/schemas/config.schema.yaml",
)


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
