"""``benchmarks/bench_regeneration.py --help`` explains and exits; it never
starts the minutes-long benchmark by mistake."""

import subprocess
import sys

from workflow_run import ROOT


def test_help_prints_usage_without_running():
    proc = subprocess.run([sys.executable, "benchmarks/bench_regeneration.py", "--help"], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0
    assert "usage:" in proc.stdout and "Benchmark the whole regeneration" in proc.stdout


def test_unknown_option_refused_without_running():
    proc = subprocess.run([sys.executable, "benchmarks/bench_regeneration.py", "--cores", "1"], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and "unrecognized arguments" in proc.stderr
