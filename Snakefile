# Regenerates the thesis's tables and figures. Run through
# `bash workflow/regenerate.sh` (sets up .venv first) or `snakemake --cores all`.
from snakemake.utils import min_version

min_version("8.0")

# A config is data: before `configfile:` reads config/config.yaml (Snakemake
# runs the yte template engine over a file that sets `__use_yte__: true`),
# every config file's raw text is checked (no yte, bounded size and aliases)
# and a command line giving --configfile twice is refused (Snakemake keeps
# only the last). The --configfile files themselves Snakemake has already
# loaded when this runs: workflow/regenerate.sh checks them before it starts.
import sys
import modal.thesis.config

modal.thesis.config.check_or_exit(
    modal.thesis.config.check_config_files,
    ["config/config.yaml", *workflow.configfiles],
    sys.argv,
)


configfile: "config/config.yaml"


# Before any job: every config file re-read strictly (duplicate keys), table
# and figure numbers normalised, numbers finite, the schema (integers are
# integers), then cross-checks, paths, a measured record, the plan's size and
# the run's name (modal.thesis.config).
modal.thesis.config.check_or_exit(
    modal.thesis.config.check_workflow_config,
    config,
    ["config/config.yaml", *workflow.configfiles],
    "workflow/schemas/config.schema.yaml",
)


include: "workflow/rules/common.smk"
include: "workflow/rules/beam.smk"


# The searches of unstated settings are parameter studies (minutes of CPU):
# only with `run_searches: true` (common.smk).
if RUN_SEARCHES:

    include: "workflow/rules/search.smk"


include: "workflow/rules/grid.smk"
include: "workflow/rules/measured.smk"
include: "workflow/rules/report.smk"


rule all:
    input:
        beam_outputs(),
        grid_outputs(),
        search_outputs(),
        measured_outputs(),
        report_outputs(),
