"""Snakemake's locks left by a killed run, for both workflows.

Snakemake locks its working directory (``.snakemake/locks``) while it runs
and removes the locks when it ends, unless it is killed (SIGKILL, a power
cut). A later run is then refused ("Directory cannot be locked") until
someone runs ``--unlock``. A lock is stale when no Snakemake run is alive
in the directory: no live process working there is Snakemake itself (its
command is ``snakemake ...``, ``python -m snakemake ...`` or ``python
.../snakemake ...``) or a job it started (``python`` running a script of
``.snakemake/scripts``). A command that merely names Snakemake (``tail -f
.snakemake/log/...``, an editor) is no run. Removing stale locks is what
``snakemake --unlock`` does. Linux only (``/proc``).

:func:`hold_folder` takes the lock of one run of ``modal campaign`` on its
output folder (``flock`` on the folder itself, released by the kernel when
the process ends however it ends), and :func:`descendants` finds the
processes a run started, to stop them with it. A Snakemake run working in a
folder that no such lock holds was left by a run killed alone (``kill -9``
of its ``modal campaign``): :func:`stop_leftover_run` stops it as Ctrl-C
would, so that the same command resumes.
"""

from __future__ import annotations

import fcntl
import os
import signal
import time
from pathlib import Path


def _argv(pid) -> list[str]:
    raw = Path(f"/proc/{pid}/cmdline").read_bytes()
    return [a.decode(errors="replace") for a in raw.split(b"\0")[:-1]] if raw else []


def is_snakemake_run(argv, cwd, root) -> bool:
    """Whether a process with command ``argv`` working in ``cwd`` is a
    Snakemake run in ``root`` (both resolved): Snakemake itself working there,
    or a job it started there (a Python script of ``root/.snakemake/scripts``)."""
    if not argv or Path(cwd) != Path(root):
        return False
    if os.path.basename(argv[0]) == "snakemake":
        return True
    if not os.path.basename(argv[0]).startswith("python") or len(argv) < 2:
        return False  # (less .snakemake/scripts/x.py is no job)
    return (argv[1:3] == ["-m", "snakemake"] or os.path.basename(argv[1]) == "snakemake"
            or (Path(cwd) / argv[1]).parent == Path(root) / ".snakemake" / "scripts")


def live_snakemake_processes(root, exclude=()) -> dict[int, str]:
    """``{pid: command line}`` of the live processes that are a Snakemake run
    in ``root`` (:func:`is_snakemake_run`)."""
    root = Path(root).resolve()
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) in exclude:
            continue
        try:
            argv = _argv(entry.name)
            cwd = Path(os.readlink(entry / "cwd")).resolve()
        except (OSError, ValueError):
            continue  # gone, or not ours to inspect
        if is_snakemake_run(argv, cwd, root) and _alive(int(entry.name)):
            found[int(entry.name)] = " ".join(argv)
    return found


class FolderBusy(OSError):
    """Another process holds the folder (:func:`hold_folder`): ``holders``,
    ``{pid: command line}``, names it (empty when it cannot be seen)."""

    def __init__(self, folder, holders: dict[int, str]):
        super().__init__(f"{folder} is held by another run")
        self.holders = holders


def hold_folder(folder) -> int:
    """An exclusive lock on ``folder`` (an existing directory) for as long as
    the returned file descriptor is open (close it to release; the kernel
    releases it when the process ends, also on ``kill -9``). Not inherited by
    child processes.

    Raises
    ------
    FolderBusy
        Another open descriptor holds it: a run in that folder; its
        ``holders`` are the processes named by ``/proc/locks``, or if that
        process is gone, the Snakemake run it left in the folder.
    """
    fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        st = os.fstat(fd)
        os.close(fd)
        holders = {}
        for pid in lock_holders(st.st_dev, st.st_ino):
            try:
                holders[pid] = " ".join(_argv(pid))
            except OSError:
                pass  # ended: the lock lives on in a process it left (a Snakemake run)
        raise FolderBusy(folder, holders or live_snakemake_processes(folder, exclude={os.getpid()})) from None
    except BaseException:
        os.close(fd)
        raise
    return fd


def lock_holders(device: int, inode: int) -> list[int]:
    """The processes ``/proc/locks`` names as holding a lock on the file
    (``device``, ``inode``); none without ``/proc``."""
    wanted = f"{os.major(device):02x}:{os.minor(device):02x}:{inode}"
    try:
        lines = Path("/proc/locks").read_text().splitlines()
    except OSError:
        return []
    pids = []
    for line in lines:
        fields = line.split()
        if "->" not in fields and len(fields) >= 6 and fields[5] == wanted and fields[4].isdigit():
            pids.append(int(fields[4]))
    return pids


def descendants(pid: int) -> list[int]:
    """The live processes started by ``pid``, its children's children and so
    on (parents before children); none without ``/proc``."""
    parents = {}
    try:
        entries = [e for e in os.listdir("/proc") if e.isdigit()]
    except OSError:
        return []
    for entry in entries:
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()  # after the command's name, which may hold anything
        if fields[0] != "Z":
            parents.setdefault(int(fields[1]), []).append(int(entry))
    found, todo = [], [pid]
    while todo:
        children = parents.get(todo.pop(0), [])
        found += children
        todo += children
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


def stop_leftover_run(root, grace: float) -> tuple[dict[int, str], dict[int, str]]:
    """Stop the Snakemake run left working in ``root`` by a caller killed
    alone, for the caller's next run to resume it.

    Call it only while holding ``root`` (:func:`hold_folder`): a run holds
    its folder until it ends however it ends, so a Snakemake run working
    there with locks held (:func:`stale_locks`) belongs to no live caller.
    Its processes (Snakemake and its jobs, and what they started) get SIGINT,
    as from Ctrl-C: the jobs end, Snakemake marks their outputs incomplete
    (redone by ``--rerun-incomplete``) and removes its locks. Waits up to
    ``grace`` seconds for them to end.

    Returns
    -------
    stopped, alive : dict
        ``{pid: command line}`` of the run's processes that ended, and of
        those still alive after ``grace`` (then the run is left alone).
    """
    _, live = stale_locks(root)  # no lock held: no live run either
    if not live or 0 in live:  # 0: no /proc, no process can be seen (nor signalled: 0 is this process's group)
        return {}, {}
    processes = dict(live)
    for pid in list(live):
        for child in descendants(pid):
            try:
                processes.setdefault(child, " ".join(_argv(child)))
            except OSError:
                pass  # ended meanwhile
    for pid in processes:
        try:
            os.kill(pid, signal.SIGINT)
        except (ProcessLookupError, PermissionError):
            pass  # ended meanwhile, or not ours: waited for below like the others
    deadline = time.monotonic() + grace
    alive = dict(processes)
    while alive and time.monotonic() < deadline:
        time.sleep(0.05)
        alive = {pid: cmd for pid, cmd in alive.items() if _alive(pid)}
    return {pid: cmd for pid, cmd in processes.items() if pid not in alive}, alive


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is no zombie."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    return not any(line.startswith("State:") and "zombie" in line for line in status.splitlines())
