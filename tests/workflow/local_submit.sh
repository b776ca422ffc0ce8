#!/usr/bin/env bash
# A "cluster" on this machine for snakemake-executor-plugin-cluster-generic:
# each job script runs as its own detached process, sharing nothing with the
# submitting snakemake but the files. Prints the job id (the process id).
set -euo pipefail
mkdir -p cluster_logs
nohup bash "$1" > "cluster_logs/$(basename "$1").log" 2>&1 < /dev/null &
echo $!
