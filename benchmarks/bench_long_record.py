"""Long records in bounded memory: ``modal.identify_record`` on an hour at
1 kHz on 32 channels (a simulated ambient record of a four-mode structure).

Prints the identification time and the memory it needed beyond the record
itself, measured two ways: the peak of Python's traced allocations
(tracemalloc, which sees every NumPy array) and the growth of the process's
peak resident set (``VmHWM``, which also sees LAPACK's own workspace).

Run: ``.venv/bin/python benchmarks/bench_long_record.py [--minutes 60] [--channels 32]``
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import numpy as np
from scipy.signal import lfilter

import modal

MODES_HZ = (0.9, 2.7, 5.1, 8.3)
DAMPING = (0.015, 0.012, 0.02, 0.01)


def peak_rss_mb() -> float:
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmHWM")) / 1024


def ambient_record(n_samples, n_channels, dt, seed=0, block=2**18):
    """White noise through four modal filters, spread over the channels by
    smooth shapes, plus 2 % sensor noise; written block by block into one
    array, so making it needs little beyond the record."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0, 1, n_channels)
    shapes = np.column_stack([np.sin((k + 0.5) * np.pi * x) for k in range(len(MODES_HZ))])
    filters = []
    for f, zeta in zip(MODES_HZ, DAMPING):
        w = 2 * np.pi * f * dt
        r = np.exp(-zeta * w)
        filters.append(([1.0], [1.0, -2 * r * np.cos(w), r * r]))
    state = [np.zeros(2) for _ in filters]
    y = np.empty((n_samples, n_channels))
    for start in range(0, n_samples, block):
        n = min(block, n_samples - start)
        q = np.empty((n, len(filters)))
        for k, (b, a) in enumerate(filters):
            q[:, k], state[k] = lfilter(b, a, rng.standard_normal(n), zi=state[k])
        y[start:start + n] = q @ shapes.T
        y[start:start + n] += 0.02 * rng.standard_normal((n, n_channels))  # sensor noise
    return y


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--minutes", type=float, default=60)
    parser.add_argument("--channels", type=int, default=32)
    parser.add_argument("--fs", type=float, default=1000.0)
    parser.add_argument("--refs", type=int, default=4, help="reference channels (the first N)")
    args = parser.parse_args()
    dt = 1 / args.fs
    n = int(args.minutes * 60 * args.fs)
    y = ambient_record(n, args.channels, dt)
    record_mb = y.nbytes / 2**20
    before = peak_rss_mb()
    tracemalloc.start()
    started = time.perf_counter()
    result, dt_used = modal.identify_record(y, dt, "ambient", refs=list(range(args.refs)), log=print)
    seconds = time.perf_counter() - started
    traced = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    grown = peak_rss_mb() - before
    found = result.modes["freq_hz"].to_numpy()
    hits = [bool(len(found)) and np.min(np.abs(found - f)) / f < 0.01 for f in MODES_HZ]
    print(f"| record | samples x channels | record (MB) | identification (s) | traced peak beyond the record (MB) "
          f"| peak RSS growth (MB) | modes found |")
    print("|---|---|---|---|---|---|---|")
    print(f"| {args.minutes:g} min at {args.fs:g} Hz | {n} x {args.channels} | {record_mb:.0f} | {seconds:.1f} "
          f"| {traced:.0f} | {grown:.0f} | {sum(hits)} of {len(MODES_HZ)} |")


if __name__ == "__main__":
    main()
