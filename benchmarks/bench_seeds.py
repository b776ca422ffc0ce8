"""Benchmark the Monte Carlo seeds (not a test; prints rates and wall times).

1. Identifications per second: :func:`modal.thesis.study.run_study` on one
   chunk of the noise study's seeds, in this process, single-threaded BLAS
   (one identification = one method on one noisy record; the record's noise
   is drawn per seed).
2. A 10,000-seed noise study through the workflow, in a temporary copy of
   the project: ``seeds.count = 10000`` in chunks of ``--chunk`` seeds, the
   identify jobs and their merge for the noise study only, on ``--cores``
   cores. By default one noise level and one interpretation (20,000
   identifications); ``--full`` runs the whole sweep of config/config.yaml
   under both interpretations (8 levels: 320,000 identifications).

Run: ``.venv/bin/python benchmarks/bench_seeds.py [--chunk 1000] [--cores 2] [--full]``
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = "1"

from modal.thesis.study import run_study  # noqa: E402  (after the thread variables)


def identifications_per_second(config, n_seeds=100):
    """Rate of one chunk of ``n_seeds`` seeds of the noise study, first noise level, interpretation lower."""
    study = dict(config["studies"]["noise"])
    study["noise_sweep"] = dict(study["noise_sweep"], noise=study["noise_sweep"]["noise"][:1])
    beam = config["beams"][study["beam"]]
    t0 = time.perf_counter()
    frame = run_study(study, beam, config["interpretations"]["lower"], {"first": 0, "count": n_seeds})
    elapsed = time.perf_counter() - t0
    n_ids = frame.groupby(["case", "method", "seed"]).ngroups
    return n_ids / elapsed, n_ids


def noise_study(config, chunk, cores, full):
    """Wall time of the identify jobs and merges of a 10,000-seed noise study."""
    study = {"seeds": {"first": 0, "count": 10_000, "chunk": chunk}, "run": "bench_seeds"}
    if not full:
        sweep = config["studies"]["noise"]["noise_sweep"]
        study["studies"] = {"noise": {"interpretations": ["lower"],
                                      "noise_sweep": {"damping": sweep["damping"], "noise": [0.03]}}}
    interpretations = study.get("studies", config["studies"])["noise"]["interpretations"]
    levels = len(study.get("studies", config["studies"])["noise"]["noise_sweep"]["noise"])
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for item in ("Snakefile", "workflow", "config", "modal", "notebooks"):
            src = ROOT / item
            (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp / item)
        (tmp / "seeds.yaml").write_text(yaml.safe_dump(study))
        targets = [f"results/runs/bench_seeds/identified/noise_{i}.csv" for i in interpretations]
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "snakemake", *targets, "--cores", str(cores),
                               "--configfile", "seeds.yaml"], cwd=tmp, capture_output=True, text=True)
        if proc.returncode:
            sys.exit(proc.stderr[-3000:])
        elapsed = time.perf_counter() - t0
    n_ids = 10_000 * levels * len(interpretations) * len(config["studies"]["noise"]["methods"])
    jobs = -(-10_000 // chunk) * len(interpretations)
    return elapsed, n_ids, jobs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--chunk", type=int, default=1000, help="seeds per identify job")
    parser.add_argument("--cores", type=int, default=os.cpu_count())
    parser.add_argument("--full", action="store_true", help="the whole noise sweep, both interpretations")
    args = parser.parse_args()
    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    rate, n = identifications_per_second(config)
    print(f"# {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at start")
    print(f"in-process: {n} identifications (TCM + ERA, 6 channels x 3594 samples), {rate:.0f} per second, one core")
    elapsed, n_ids, jobs = noise_study(config, args.chunk, args.cores, args.full)
    print(f"10,000-seed noise study: {n_ids} identifications in {jobs} identify jobs of {args.chunk} seeds "
          f"on {args.cores} cores: {elapsed:.1f} s wall, {n_ids / elapsed:.0f} identifications per second")


if __name__ == "__main__":
    main()
