"""Before `workflow/regenerate.sh` starts Snakemake: clear the locks a killed
run left behind, or stop with a clear message when a run is really active.

Snakemake locks its working directory (``.snakemake/locks``) while it runs
and removes the locks when it ends, unless it is killed (SIGKILL, a power
cut). A later run is then refused ("Directory cannot be locked") until
someone runs ``--unlock``. Here a lock is stale when no live process works
in this directory whose command line names Snakemake (the scheduler or a
job it started: a job's script lives under ``.snakemake/scripts``); stale
locks are removed, which is what ``snakemake --unlock`` does. Incomplete
outputs are then rerun by ``--rerun-incomplete`` (regenerate.sh passes it).

Exit status: 0 (no lock, or stale locks cleared), 3 (a run is active).
Linux only (``/proc``); elsewhere the locks are left alone.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ACTIVE = 3


def live_snakemake_processes(root: Path, exclude=()) -> dict[int, str]:
    """``{pid: command line}`` of live processes whose working directory is
    ``root`` and whose command line mentions snakemake."""
    root = root.resolve()
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


def main(root=".") -> int:
    root = Path(root)
    locks = root / ".snakemake" / "locks"
    held = sorted(locks.glob("*.lock")) if locks.is_dir() else []
    if not held:
        return 0
    if not Path("/proc/self").exists():
        print(f"{locks} holds locks and this system has no /proc to tell whether a run is active: "
              "if none is, run `snakemake --unlock` once", file=sys.stderr)
        return 0
    live = live_snakemake_processes(root, exclude={os.getpid(), os.getppid()})
    if live:
        listed = "\n".join(f"  pid {pid}: {cmd[:160]}" for pid, cmd in sorted(live.items()))
        print(f"Another Snakemake run is active in {root.resolve()}:\n{listed}\n"
              "Wait for it to finish, or stop it (kill <pid>; Ctrl-C in its terminal), then run "
              "`bash workflow/regenerate.sh` again: it resumes where the run stopped.", file=sys.stderr)
        return ACTIVE
    for lock in held:
        lock.unlink(missing_ok=True)
    print(f"Cleared {len(held)} stale Snakemake lock(s) of an interrupted run (no live Snakemake process "
          f"in {root.resolve()}); resuming.", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
