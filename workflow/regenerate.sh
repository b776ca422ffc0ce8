#!/usr/bin/env bash
# The main job: set up .venv (first run only) and regenerate every table,
# figure, notebook and the report. Extra arguments go to snakemake,
# e.g. `bash workflow/regenerate.sh --configfile my.yaml`.
# After an interruption (Ctrl-C, a killed process) the same command resumes:
# stale Snakemake locks are cleared (workflow/stale_locks.py), incomplete
# outputs rerun; a run still active in this folder is reported, not disturbed.
set -euo pipefail
EXTRA=workflow
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
mkdir -p .snakemake
# One regenerate.sh per folder at a time (released by the kernel however this
# process ends); Snakemake and its jobs inherit the descriptor.
exec 9>.snakemake/regenerate.flock
if command -v flock >/dev/null && ! flock -n 9; then
    echo "Another 'bash workflow/regenerate.sh' is running in $ROOT; wait for it or stop it, then rerun." >&2
    exit 3
fi
python workflow/stale_locks.py "$ROOT"
# Config files are data: refused here, before Snakemake loads (and would
# evaluate a yte template in) a --configfile.
python workflow/check_configfiles.py "$@"
snakemake --workflow-profile workflow/profiles/default --cores "${CORES:-all}" "$@"
