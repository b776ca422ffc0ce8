#!/usr/bin/env bash
# The main job: set up .venv (first run only) and regenerate every table,
# figure, notebook and the report. Extra arguments go to snakemake,
# e.g. `bash workflow/regenerate.sh --configfile my.yaml`.
set -euo pipefail
EXTRA=workflow
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
snakemake --workflow-profile workflow/profiles/default --cores "${CORES:-all}" "$@"
