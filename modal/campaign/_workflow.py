"""The Python entry point of a campaign: :func:`run` checks the campaign file
and the options, then runs the campaign's workflow (:data:`SNAKEFILE`) in the
output folder with this interpreter's Snakemake. ``modal campaign`` calls it.

Snakemake runs as a separate process through its command line, the interface
it keeps stable (its Python API changed between versions 7, 8 and 9), and so
that a job's failure cannot take the caller's process with it.
"""

from __future__ import annotations

import importlib.util
import json
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from .._locks import FolderBusy, clear_stale_locks, descendants, hold_folder, stop_leftover_run
from ._config import campaign_inputs, read_campaign

#: The workflow :func:`run` (and ``modal campaign``) runs.
SNAKEFILE = Path(__file__).with_name("Snakefile")
#: The shipped Snakemake profiles, by name (a folder of this one each).
PROFILES = Path(__file__).with_name("profiles")


def profile_folder(profile) -> Path:
    """The Snakemake profile folder ``profile`` names.

    A folder that exists is used as it is, and Snakemake reads its settings
    (so a folder ``slurm`` in the working directory wins over the shipped
    profile of that name); otherwise a name of :data:`PROFILES` gives the
    shipped folder.

    Parameters
    ----------
    profile : path-like
        A folder holding ``config.yaml``, or a shipped profile's name.

    Returns
    -------
    pathlib.Path
        The folder, absolute.

    Raises
    ------
    ValueError
        ``profile`` is neither a folder nor a shipped name (the message lists
        the names).
    """
    folder = Path(profile)
    if folder.is_dir():
        return folder.resolve()
    shipped = sorted(p.name for p in PROFILES.iterdir() if (p / "config.yaml").is_file())
    if str(profile) not in shipped:
        raise ValueError(f"profile: {profile} is neither a folder nor a shipped profile ({', '.join(shipped)}); "
                         "a Snakemake profile is a folder with config.yaml")
    return (PROFILES / str(profile)).resolve()


class WorkflowStopped(RuntimeError):
    """The campaign's workflow stopped before it was done: Snakemake exited
    with ``returncode``. Its log is under ``log`` (``out/.snakemake/log``),
    each job's under ``out/logs``. Running again resumes: finished jobs are
    kept."""

    #: The signal (SIGINT, SIGTERM, SIGHUP) that stopped it, if one did (:class:`WorkflowInterrupted`).
    signum: int | None = None

    def __init__(self, returncode: int, log: Path):
        super().__init__(f"the workflow stopped (exit {returncode}); its log is in {log}; run again to resume")
        self.returncode = returncode
        self.log = log


class WorkflowInterrupted(WorkflowStopped):
    """The campaign's workflow was stopped by signal ``signum`` (SIGINT,
    SIGTERM or SIGHUP) sent to the calling process: Snakemake and its jobs
    were stopped as Ctrl-C stops them. Running again resumes."""

    def __init__(self, signum: int, returncode: int, log: Path):
        super().__init__(returncode, log)
        self.signum = signum
        self.args = (f"interrupted by {signal.Signals(signum).name}: the workflow stopped; its log is in {log}; "
                     "run again to resume",)


#: The signals that stop a campaign's workflow (and its jobs) as Ctrl-C does.
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
#: Seconds a SIGINT is left to stop Snakemake and its jobs by itself (it may
#: have reached them too) before it is passed on to them.
SIGINT_GRACE = 3.0

#: Seconds the workflow a killed run left in its folder (Snakemake and its
#: jobs, :func:`modal._locks.stop_leftover_run`) is given to stop on SIGINT
#: before the next run is refused instead of resuming.
LEFTOVER_GRACE = 60.0


def _in_terminal_foreground() -> bool:
    """Whether this process's group is the foreground of its terminal: then
    a Ctrl-C there reached Snakemake and its jobs (this group) directly."""
    try:
        fd = os.open("/dev/tty", os.O_RDONLY | os.O_NOCTTY)
    except OSError:
        return False  # no terminal
    try:
        return os.tcgetpgrp(fd) == os.getpgrp()
    except OSError:
        return False
    finally:
        os.close(fd)


def _run_snakemake(call) -> tuple[int, int | None]:
    """Run Snakemake's command line ``call``; returns its exit status and the
    stop signal this process received meanwhile, if any.

    A signal of :data:`STOP_SIGNALS` sent to this process stops the workflow
    as Ctrl-C does: Snakemake and every process it started get SIGINT (each
    once per signal received, also a job started after it), so the jobs end
    at once and Snakemake removes its locks; this process waits for them. A
    SIGINT may have reached them already (Ctrl-C in a terminal signals the
    whole foreground group): it is passed on only if they still run
    :data:`SIGINT_GRACE` seconds later, and not at all when this process is
    in the terminal's foreground (a second one is). Snakemake and its jobs
    ignore SIGHUP: a closing terminal's hangup stops them through this
    process as the other signals do, not by killing Snakemake mid-run.
    Handled only in the main thread (Python's rule); in another thread the
    signals keep their handlers."""
    received = []

    def keep(signum, frame):
        received.append(signum)

    previous = {}
    main_thread = threading.current_thread() is threading.main_thread()
    if main_thread:
        previous = {signum: signal.signal(signum, keep) for signum in STOP_SIGNALS}
        signal.signal(signal.SIGHUP, signal.SIG_IGN)  # inherited by Snakemake (an ignored signal stays ignored)
    try:
        try:
            proc = subprocess.Popen(call)
        finally:
            if main_thread:
                signal.signal(signal.SIGHUP, keep)
        signalled, passed_on, pass_on_at = set(), 0, None
        while True:
            try:
                return proc.wait(timeout=0.2 if not received else 0.05), (received[0] if received else None)
            except subprocess.TimeoutExpired:
                pass
            if not received:
                continue
            if pass_on_at is None:  # the first signal: when to pass it on
                seen_already = received[0] == signal.SIGINT
                pass_on_at = time.monotonic() + (SIGINT_GRACE if seen_already else 0.0)
                if seen_already and _in_terminal_foreground():
                    pass_on_at = float("inf")
            due = len(received) - (time.monotonic() < pass_on_at)  # signals to pass on by now
            if due > passed_on:  # one more round: every process gets SIGINT once more
                signalled, passed_on = set(), due
            elif not passed_on:
                continue
            for pid in [proc.pid, *descendants(proc.pid)]:
                if pid not in signalled:
                    signalled.add(pid)
                    try:
                        os.kill(pid, signal.SIGINT)
                    except ProcessLookupError:
                        pass  # ended meanwhile
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


class NoRecordIdentified(RuntimeError):
    """The campaign's workflow ran to the end but every one of its
    ``n_records`` records failed (could not be read or identified, or did
    not share the campaign's layout): ``failed`` (``out/failed.csv``) says
    why for each. The outputs are written (with no mode tracked)."""

    def __init__(self, n_records: int, failed: Path):
        super().__init__(f"no record was identified: all {n_records} failed; {failed} says why for each")
        self.n_records = n_records
        self.failed = failed


def run(campaign, out, cores: int = 1, profile=None, dry_run: bool = False, *, command: str | None = None,
        log: Callable[[str], None] | None = None) -> Path:
    """Identify every record of a campaign, track the modes and write the report.

    Everything is checked before any job runs: the campaign file
    (:func:`modal.campaign.read_campaign`), the output folder (never one of
    the inputs, never holding one), the profile and Snakemake's presence.
    Locks left by a killed run in ``out`` are cleared, and a workflow it
    left running there (``kill -9`` of this process alone) is stopped as by
    Ctrl-C (:func:`modal._locks.stop_leftover_run`); a live run there is
    refused. Then the campaign's workflow runs in ``out``; a second call
    with the same campaign resumes, and records added to the index add only
    their jobs (docs: Monitoring campaigns).

    Parameters
    ----------
    campaign : path-like
        The campaign's YAML file.
    out : path-like
        The output folder (created; kept between runs). It receives
        ``tracked.csv``, ``untracked.csv``, ``failed.csv``, ``modes.csv``,
        ``references.csv``, ``tracked_shapes.csv``, ``report.html``, the chunks' files under
        ``chunks/`` and the jobs' logs under ``logs/``.
    cores : int
        Cores to use on this machine (with a cluster profile: jobs at once).
    profile : path-like, optional
        A Snakemake profile: a folder holding ``config.yaml``, or the name
        of a shipped one (``"slurm"``, :func:`profile_folder`).
    dry_run : bool
        Plan only: Snakemake prints the jobs that would run; no job runs.
    command : str, optional
        How the results were asked for, for the report's provenance; by
        default this call, written as Python. Leave out what does not change
        the results (cores, profile): the report is rerun when it changes.
    log : callable, optional
        Called with each progress message (a ``str``): the number of records
        and chunks before the workflow starts, the files written after it.

    Returns
    -------
    pathlib.Path
        ``out``.

    Raises
    ------
    ValueError
        The campaign file is refused (the message names the key and the
        fix), ``cores`` is not a positive integer, ``profile`` is neither a
        folder nor a shipped profile's name, or another run is active in ``out`` (its process named:
        a run holds ``out`` from before it reads the campaign until it ends),
        or the workflow a killed run left there did not stop within
        :data:`LEFTOVER_GRACE` seconds;
        :class:`modal.measured.OutputError` (a ``ValueError``) when ``out``
        is not a folder, cannot be created, or is, holds or lies inside one
        of the campaign's inputs (the campaign file, the index, the
        reference modes, a record).
    ImportError
        The workflow extra (Snakemake, jsonschema, PyYAML) is not installed.
    WorkflowStopped
        The workflow stopped: a job failed (a record that cannot be read or
        identified is not a failure: ``failed.csv`` lists it), or it was
        interrupted: :class:`WorkflowInterrupted` when this process received
        SIGINT, SIGTERM or SIGHUP (in the main thread), which stop Snakemake
        and its jobs as Ctrl-C does.
    NoRecordIdentified
        The workflow ran to the end (its outputs are written) but no record
        was identified: every one is in ``failed.csv``.
    """
    from ..measured import OutputError, check_output

    log = log or (lambda message: None)
    if isinstance(cores, bool) or not isinstance(cores, int) or cores < 1:
        raise ValueError(f"cores: {cores!r} is not a positive integer")
    out = Path(out)
    # One run per folder, held from before the campaign is read (a second run is refused at once; a folder
    # still to be created is held as soon as it is) to the end of the run
    held = _hold(out, unless_unreadable=True) if out.is_dir() else None
    try:
        config, index = read_campaign(campaign, out=out)
        if importlib.util.find_spec("snakemake") is None:
            raise ImportError("snakemake is not installed")
        profile = None if profile is None else profile_folder(profile)
        # not an input, not holding or inside one (the rule modal identify follows), and a folder (or where one
        # can be made) on a writable file system
        check_output(out, inputs=campaign_inputs(campaign, config, index))
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"out: cannot create {out}: {exc.strerror or exc}") from None
        if held is None:
            held = _hold(out)
        if not dry_run:  # a workflow left running by a run killed alone: stopped, to be resumed
            stopped, alive = stop_leftover_run(out, LEFTOVER_GRACE)
            if alive:
                listed = "; ".join(f"pid {pid}: {cmd[:120]}" for pid, cmd in sorted(alive.items()))
                raise ValueError(f"out: the workflow a killed run left in {out} did not stop within "
                                 f"{LEFTOVER_GRACE:g} s of SIGINT ({listed}): stop it (kill -9 <pid>), then run "
                                 "again to resume")
            if stopped:
                log(f"stopped the workflow a killed run left running in {out} (pid "
                    f"{', '.join(map(str, sorted(stopped)))}); resuming")
        cleared, live = clear_stale_locks(out)
        if live:
            listed = "; ".join(f"pid {pid}: {cmd[:120]}" for pid, cmd in sorted(live.items()))
            raise ValueError(f"out: a campaign run is active in {out} ({listed}): wait for it or stop it, then "
                             "run again to resume")
        if cleared:
            log(f"cleared {cleared} stale lock(s) of an interrupted run in {out}; resuming")
        if command is None:
            command = f"modal.campaign.run({str(campaign)!r}, {str(out)!r})"
        # The workflow's config as a file (JSON, which YAML reads): Snakemake parses
        # --config values itself, and a path such as "run #1/a: b" does not survive it.
        settings = out / ".modal" / "config.json"
        settings.parent.mkdir(exist_ok=True)
        settings.write_text(json.dumps({"campaign": str(Path(campaign).resolve()), "command": command}))
        call = [sys.executable, "-m", "snakemake", "--snakefile", str(SNAKEFILE), "--directory", str(out),
                "--cores", str(cores), "--rerun-incomplete", "--keep-going", "--configfile",
                str(settings.resolve())]
        if profile is not None:
            call += ["--profile", str(profile)]
        if dry_run:
            call += ["--dry-run", "--quiet", "rules"]
        log(f"{len(index)} records in {-(-len(index) // config['chunk'])} chunks of up to {config['chunk']}")
        report = out / "report.html"
        before = report.stat().st_mtime_ns if report.exists() else None
        returncode, signum = _run_snakemake(call)
    finally:
        if held is not None:
            os.close(held)
    if signum is not None:
        raise WorkflowInterrupted(signum, returncode, out / ".snakemake" / "log")
    if returncode:
        raise WorkflowStopped(returncode, out / ".snakemake" / "log")
    if not dry_run and before is not None and report.stat().st_mtime_ns == before:
        log(f"nothing to do: {out / 'tracked.csv'} and {report} were up to date")
    elif not dry_run:
        log(f"wrote {out / 'tracked.csv'} and {report}")
    if not dry_run:
        import pandas as pd

        failed = pd.read_csv(out / "failed.csv")["record"].nunique()
        if failed >= len(index):
            raise NoRecordIdentified(len(index), out / "failed.csv")
    return out


def _hold(out: Path, unless_unreadable: bool = False) -> int | None:
    """:func:`modal._locks.hold_folder` of ``out``, or the ValueError naming
    the run that holds it. ``unless_unreadable``: None for a folder that
    cannot be opened (left to :func:`modal.measured.check_output` to name);
    else the OutputError."""
    from ..measured import OutputError

    try:
        return hold_folder(out)
    except FolderBusy as busy:
        listed = "; ".join(f"pid {pid}: {cmd[:120]}" for pid, cmd in sorted(busy.holders.items())) or "pid unknown"
        raise ValueError(f"out: a campaign run is active in {out} ({listed}): wait for it or stop it "
                         "(kill <pid>), then run again to resume") from None
    except OSError as exc:
        if unless_unreadable:
            return None
        raise OutputError(f"out: cannot open {out}: {exc.strerror or exc}") from None
