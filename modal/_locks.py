"""Snakemake's locks left by a killed run, for both workflows.

Snakemake locks its working directory (``.snakemake/locks``) while it runs
and removes the locks when it ends, unless it is killed (SIGKILL, a power
cut). A later run is then refused ("Directory cannot be locked") until
someone runs ``--unlock``. A lock is stale when no live process works in the
directory whose command line names Snakemake (the scheduler, or a job it
started: a job's script lives under ``.snakemake/scripts``); removing stale
locks is what ``snakemake --unlock`` does. Linux only (``/proc``).
"""

from __future__ import annotations

import os
from pathlib import Path


def live_snakemake_processes(root, exclude=()) -> dict[int, str]:
    """``{pid: command line}`` of live processes whose working directory is
    ``root`` and whose command line mentions snakemake."""
    root = Path(root).resolve()
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) in exclude:
            continue
        try:
            cmdline = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
            cwd = Path(os.readlink(entry / "cwd")).resolve()
            state = next((line for line in (entry / "status").read_text().splitlines()
                          if line.startswith("State:")), "")
        except (OSError, ValueError):
            continue  # gone, or not ours to inspect
        if cwd == root and "snakemake" in cmdline.lower() and "zombie" not in state:
            found[int(entry.name)] = cmdline
    return found


def stale_locks(root) -> tuple[list[Path], dict[int, str]]:
    """The Snakemake locks held in ``root`` and the live Snakemake processes
    working there (besides this one and its parent). With no live process
    the locks are stale; with one, a run is active. Without ``/proc`` no
    process can be seen: the locks are returned with no live process only
    if there are none, else with ``{0: "unknown"}`` so they are left alone."""
    locks = Path(root) / ".snakemake" / "locks"
    held = sorted(locks.glob("*.lock")) if locks.is_dir() else []
    if not held:
        return [], {}
    if not Path("/proc/self").exists():
        return held, {0: "unknown (no /proc): if no run is active, run `snakemake --unlock` once"}
    return held, live_snakemake_processes(root, exclude={os.getpid(), os.getppid()})


def clear_stale_locks(root) -> tuple[int, dict[int, str]]:
    """Remove the locks of an interrupted run in ``root``; returns how many
    were removed and the live Snakemake processes (then none is removed)."""
    held, live = stale_locks(root)
    if live:
        return 0, live
    for lock in held:
        lock.unlink(missing_ok=True)
    return len(held), {}
