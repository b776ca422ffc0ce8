"""Monitoring campaigns: how long a 10,000-record index takes to plan, and
how many ten-minute 4-channel records at 50 Hz a campaign identifies per
minute on this machine's cores, beside pyOMA2's SSI-cov on the same
records in one process.

Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_campaign.py [--records 40] [--cores 2]``
(``--per-record``: only the per-record times, on ``--records`` records).

Per record, ours and pyOMA2's SSI-cov run in turn on each record (so a
change of the machine's load hits both alike) with one BLAS thread, and
the medians are compared; the spectral witness (:func:`modal.fdd` on the
record as identified, and :func:`modal.spectral_support`) is timed on its
own, as its share of ours.

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


def seconds_per_record(calls: dict, paths) -> dict[str, np.ndarray]:
    """Seconds of each ``calls[name](path)`` on each of ``paths[1:]``, the
    calls in turn on each record (a call that returns a number: its own
    timing of the part it measures); the first path is a warm-up, not timed
    (the first call imports what it needs, as a campaign job does once per
    chunk)."""
    for call in calls.values():
        call(paths[0])
    times = {name: [] for name in calls}
    for p in paths[1:]:
        for name, call in calls.items():
            t = time.perf_counter()
            own = call(p)
            times[name].append(time.perf_counter() - t if own is None else own)
    return {name: np.array(t) for name, t in times.items()}


def ours_one(path) -> None:
    """``modal.identify_record`` on the record, as the campaign's records are identified."""
    record = modal.read_record(path)
    modal.identify_record(record.acc, record.dt, "ambient", max_order=40, fmax=10)


def witness_one(path) -> float:
    """Seconds of the spectral witness alone, as :func:`modal.identify_record`
    computes it: the singular values of the record as identified (decimated
    to 25 Hz; the decimation not timed) and their support of four modes."""
    record = modal.read_record(path)
    y, dt = modal.decimate(record.acc, record.dt, 2)
    shapes = np.linalg.qr(np.random.default_rng(0).standard_normal((y.shape[1], 4)))[0]
    t = time.perf_counter()
    spectrum = modal.fdd(y, dt)
    modal.spectral_support(spectrum, np.array([1.6, 4.2, 6.2, 7.8]), shapes, damping=np.full(4, 0.015))
    return time.perf_counter() - t


def theirs_one(path) -> None:
    """pyOMA2's SSI-cov with the same decimation, block rows and orders."""
    from pyoma2.algorithms import SSI
    from pyoma2.setup import SingleSetup

    record = modal.read_record(path)
    setup = SingleSetup(record.acc, fs=record.fs)
    setup.decimate_data(q=2)
    setup.add_algorithms(SSI(name="SSIcov", method="cov", br=60, ordmin=2, ordmax=40, step=2))
    setup.run_by_name("SSIcov")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=40)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--per-record", action="store_true", help="only the per-record times")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        simulate_campaign(tmp / "c", n_records=args.records, every_hours=6, duration=600.0, fs=50.0)
        if not args.per_record:
            campaign(tmp, args.records, args.cores)
        per_record(sorted((tmp / "c" / "records").glob("*.npz"))[:max(args.records, 2) if args.per_record else 11])


def campaign(tmp: Path, records: int, cores: int) -> None:
    """The planning of a 10,000-record index and the simulated campaign's wall time."""
    print(f"plan a 10,000-record index (modal campaign --dry-run): {plan_seconds(tmp / 'plan', 10_000):.1f} s")
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "modal", "campaign", str(tmp / "c" / "campaign.yaml"), "--out",
                    str(tmp / "out"), "--cores", str(cores)], check=True, capture_output=True)
    wall = time.perf_counter() - t
    print(f"campaign of {records} records (10 min, 4 channels, 50 Hz) on {cores} cores: {wall:.1f} s, "
          f"{60 * records / wall:.0f} records per minute (start-up, tracking and report included)")


def per_record(paths) -> None:
    """Ours, the witness within it and pyOMA2's SSI-cov on each record in
    turn, one BLAS thread; medians (and quartiles) over ``paths[1:]``."""
    import logging
    import os

    from threadpoolctl import threadpool_limits

    os.environ.setdefault("TQDM_DISABLE", "1")  # pyOMA2's progress bars

    calls = {"ours": ours_one, "witness": witness_one}
    try:
        import pyoma2  # noqa: F401
    except ImportError:
        print("pyOMA2 not installed (the bench extra): no comparison")
    else:
        logging.getLogger("pyoma2").setLevel(logging.WARNING)  # its INFO lines per run
        calls["theirs"] = theirs_one
    with threadpool_limits(limits=1):
        times = seconds_per_record(calls, paths)

    def say(t):
        return f"median {np.median(t):.3f} s (quartiles {np.percentile(t, 25):.3f}-{np.percentile(t, 75):.3f})"

    ours = np.median(times["ours"])
    print(f"{len(paths) - 1} records, one BLAS thread, each record in turn by each")
    print(f"modal.identify_record per record: {say(times['ours'])}")
    print(f"  of which the spectral witness (FDD, its support): {say(times['witness'])}, "
          f"{100 * np.median(times['witness']) / ours:.0f} %")
    if "theirs" in times:
        theirs = np.median(times["theirs"])
        ratio = np.median(times["theirs"] / times["ours"])
        print(f"pyOMA2 SSI-cov per record (decimated to 25 Hz, 60 block rows, orders 2-40; no mode selection): "
              f"{say(times['theirs'])}; {theirs / ours:.2f} x ours (median of the per-record ratios {ratio:.2f})")


if __name__ == "__main__":
    main()
