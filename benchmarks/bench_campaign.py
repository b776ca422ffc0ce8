"""Monitoring campaigns: how long a 10,000-record index takes to plan, and
how many ten-minute 4-channel records at 50 Hz a campaign identifies per
minute on this machine's cores, beside pyOMA2's SSI-cov on the same
records in one process.

Run: ``.venv/bin/python benchmarks/bench_campaign.py [--records 40] [--cores 2]``

Needs the ``bench`` extra for pyOMA2 (``pyoma-2``); without it the
comparison is left out.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

import modal
from modal.campaign import simulate_campaign


def plan_seconds(folder: Path, n_records: int) -> float:
    """``modal campaign --dry-run`` on an index of ``n_records`` tiny records."""
    (folder / "records").mkdir(parents=True)
    for k in range(n_records):
        (folder / "records" / f"r{k:05d}.npy").write_bytes(b"")
    times = pd.Timestamp("2025-01-01") + pd.to_timedelta(np.arange(n_records), unit="h")
    pd.DataFrame({"path": [f"records/r{k:05d}.npy" for k in range(n_records)],
                  "time": times.astype(str)}).to_csv(folder / "index.csv", index=False)
    (folder / "c.yaml").write_text("records: {index: index.csv}\nidentify: {excitation: ambient, fs: 50}\n")
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "modal", "campaign", str(folder / "c.yaml"), "--out", str(folder / "out"),
                    "--dry-run"], check=True, capture_output=True)
    return time.perf_counter() - t


def seconds_per_record(identify_one, paths) -> float:
    """Mean seconds of ``identify_one(path)`` over ``paths[1:]``; the first
    path is a warm-up, not timed (the first call imports what it needs, as a
    campaign job does once per chunk)."""
    identify_one(paths[0])
    t = time.perf_counter()
    for p in paths[1:]:
        identify_one(p)
    return (time.perf_counter() - t) / len(paths[1:])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=40)
    parser.add_argument("--cores", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        print(f"plan a 10,000-record index (modal campaign --dry-run): {plan_seconds(tmp / 'plan', 10_000):.1f} s")
        simulate_campaign(tmp / "c", n_records=args.records, every_hours=6, duration=600.0, fs=50.0)
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "modal", "campaign", str(tmp / "c" / "campaign.yaml"), "--out",
                        str(tmp / "out"), "--cores", str(args.cores)], check=True, capture_output=True)
        wall = time.perf_counter() - t
        print(f"campaign of {args.records} records (10 min, 4 channels, 50 Hz) on {args.cores} cores: {wall:.1f} s, "
              f"{60 * args.records / wall:.0f} records per minute (start-up, tracking and report included)")
        paths = sorted((tmp / "c" / "records").glob("*.npz"))[:11]

        def ours_one(p):
            record = modal.read_record(p)
            modal.identify_record(record.acc, record.dt, "ambient", max_order=40, fmax=10)

        ours = seconds_per_record(ours_one, paths)
        print(f"modal.identify_record per record, one process: {ours:.3f} s")
        try:
            from pyoma2.algorithms import SSI
            from pyoma2.setup import SingleSetup
        except ImportError:
            print("pyOMA2 not installed (the bench extra): no comparison")
            return

        def theirs_one(p):
            record = modal.read_record(p)
            setup = SingleSetup(record.acc, fs=record.fs)
            setup.decimate_data(q=2)
            setup.add_algorithms(SSI(name="SSIcov", method="cov", br=60, ordmin=2, ordmax=40, step=2))
            setup.run_by_name("SSIcov")

        theirs = seconds_per_record(theirs_one, paths)
        print(f"pyOMA2 SSI-cov per record (decimated to 25 Hz, 60 block rows, orders 2-40; no mode selection): "
              f"{theirs:.3f} s, {theirs / ours:.1f} x ours")


if __name__ == "__main__":
    main()
