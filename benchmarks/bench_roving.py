"""A roving test merged: the Weimar frame's 15 setups (pyOMA's layout, in
``../shared/data/weimar_frame`` beside the checkout, or ``--folder``), read,
identified and merged on one core, then the 11 modes drawn.

Prints the time of each step, best of ``--repeat`` runs. Pin it to one core
from the shell so LAPACK uses one thread too::

    OPENBLAS_NUM_THREADS=1 taskset -c 0 .venv/bin/python benchmarks/bench_roving.py

Run: ``.venv/bin/python benchmarks/bench_roving.py [--folder DIR] [--repeat 3]``
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import modal
from modal.setups import draw_modes

DEFAULT = Path(__file__).resolve().parents[2] / "shared" / "data" / "weimar_frame"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=DEFAULT)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    folders = sorted(args.folder.glob("measurement_*"), key=lambda p: int(p.name.split("_")[1]))
    best = {}
    for _ in range(args.repeat):
        times = {}
        t = time.perf_counter()
        geometry = modal.read_geometry(args.folder)
        setups = [modal.read_setup(f, geometry=geometry) for f in folders]
        times["read"] = time.perf_counter() - t
        t = time.perf_counter()
        results = [modal.identify_setup(s, "ambient", fmax=15)[0] for s in setups]
        times["identify"] = time.perf_counter() - t
        t = time.perf_counter()
        merged = modal.merge_setups(setups, results)
        times["merge"] = time.perf_counter() - t
        times["read + identify + merge"] = times["read"] + times["identify"] + times["merge"]
        with tempfile.TemporaryDirectory() as folder:
            t = time.perf_counter()
            draw_modes(geometry, merged, folder, animate=False)
            times["pictures (png)"] = time.perf_counter() - t
            t = time.perf_counter()
            draw_modes(geometry, merged, folder, animate=True)
            times["pictures (png + gif)"] = time.perf_counter() - t
        best = {k: min(v, best.get(k, v)) for k, v in times.items()}
    print(f"{len(setups)} setups, {len(merged.modes)} modes, best of {args.repeat}:")
    for step, seconds in best.items():
        print(f"  {step:26s} {seconds:6.2f} s")


if __name__ == "__main__":
    main()
