"""Before `workflow/regenerate.sh` starts Snakemake: clear the locks a killed
run left behind, or stop with a clear message when a run is really active.

Snakemake locks its working directory (``.snakemake/locks``) while it runs
and removes the locks when it ends, unless it is killed (SIGKILL, a power
cut). A later run is then refused ("Directory cannot be locked") until
someone runs ``--unlock``. Here a lock is stale when no Snakemake run is
alive in this directory: no live process working here is Snakemake itself
(``snakemake ...``, ``python -m snakemake ...``) or a job it started (a
script of ``.snakemake/scripts``); a command that merely names Snakemake
(``tail -f .snakemake/log/...``) is no run (``modal._locks``). Stale locks
are removed, which is what ``snakemake --unlock`` does. Incomplete
outputs are then rerun by ``--rerun-incomplete`` (regenerate.sh passes it).

Exit status: 0 (no lock, or stale locks cleared), 3 (a run is active).
Linux only (``/proc``); elsewhere the locks are left alone.
"""

from __future__ import annotations

import sys
from pathlib import Path

from modal._locks import clear_stale_locks

ACTIVE = 3


def main(root=".") -> int:
    root = Path(root)
    cleared, live = clear_stale_locks(root)
    if live:
        listed = "\n".join(f"  pid {pid}: {cmd[:160]}" for pid, cmd in sorted(live.items()))
        print(f"Another Snakemake run is active in {root.resolve()}:\n{listed}\n"
              "Wait for it to finish, or stop it (kill <pid>; Ctrl-C in its terminal), then run "
              "`bash workflow/regenerate.sh` again: it resumes where the run stopped.", file=sys.stderr)
        return ACTIVE
    if cleared:
        print(f"Cleared {cleared} stale Snakemake lock(s) of an interrupted run (no live Snakemake process "
              f"in {root.resolve()}); resuming.", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
