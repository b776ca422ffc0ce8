"""Command line: ``modal identify`` (also ``python -m modal identify``).

::

    modal identify PATH [--fs HZ] [--channels i,j,...] [--refs i,j,...]
                        (--ambient | --free-decay) [--fmax HZ] [--max-order N]
                        [--rows N] [--highpass HZ] [--delimiter C] [--decimal C]
                        [--skip-rows N] --out DIR

reads a record (:func:`modal.read_record`), identifies its modes
(:func:`modal.write_identification`: NExT correlations for ambient data, the decay
after the impact for free decay, a stabilisation diagram with automatic mode
selection, the singular values of the spectral density matrix as a witness)
and writes ``DIR/modes.csv``, ``DIR/poles.csv``, ``DIR/stabilisation.png``,
``DIR/mac.csv``, ``DIR/settings.json`` (every setting used, the provenance)
and ``DIR/report.html`` (one page of it all).

BLAS runs on one thread (threadpoolctl): on this project's records that is
faster than several (docs: Benchmarks), unless one of the environment
variables of :data:`THREAD_VARIABLES` says how many threads to use.

::

    modal identify SETUP [SETUP ...] [--geometry DIR] (--ambient | --free-decay)
                   [--fmax HZ] ... --out DIR

identifies the setups of a roving test (folders in pyOMA's layout, or with a
``channels.csv`` beside the record; or one record whose channels the
geometry names) and merges them through their reference channels
(:func:`modal.write_setups`): ``DIR/modes.csv``, ``DIR/shapes.csv`` (one row
per mode and node in the global frame), ``DIR/matches.csv``,
``DIR/setups/<name>/`` (each setup's own results) and, with a geometry,
``DIR/mode_<k>.png`` and ``.gif``.

Exit codes (one line on stderr says why; never a traceback):

0
    success;
1
    an internal error (a bug: please report the message);
2
    bad options: argparse's, and an ``--out`` that cannot hold the results,
    found before any work (it names the input record, it is a file or a
    device such as ``/proc/version``, it lies below a file such as
    ``/dev/null/x``, its folder is read-only or not writable);
3
    the record cannot be read (not a regular file: a directory, a FIFO, a
    device; an unknown format; non-numeric data such as dates; ...);
4
    the identification cannot run on it (too short for the settings, no
    vibration in a channel, more memory than is available, ...);
5
    it ran but selected no mode (the message says what was found);
6
    the results could not be written (e.g. no space left on the device);
    ``--out`` is then as it was before: the files are written into a hidden
    folder beside it and moved into place only when all are complete.

The mode table printed gives damping as a ratio to critical (a fraction, not
%), as in ``modes.csv``.
"""

from __future__ import annotations

import argparse
import signal
import sys
import time
import warnings
from contextlib import contextmanager
from pathlib import Path

EXIT_INTERNAL = 1
EXIT_BAD_OPTIONS = 2
EXIT_BAD_FILE = 3
EXIT_CANNOT_IDENTIFY = 4
EXIT_NO_MODES = 5
EXIT_CANNOT_WRITE = 6
EXIT_WORKFLOW = 7

#: Environment variables that set BLAS's threads: when one is set, ``modal
#: identify`` leaves the threads as it says instead of holding BLAS to one.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS")

EPILOG = ("Exit codes: 0 done, 1 internal error, 2 bad options (also an --out that cannot hold the results: "
          "the input file, a file or device, below a file, read-only), 3 unreadable record (also a directory, "
          "FIFO or device), 4 identification impossible (also no vibration, or not enough memory), "
          "5 no mode selected, 6 results not written (e.g. disk full; --out is left as it was). "
          "Damping is printed and written as a ratio to critical (fraction, not %).")


def _indices(text: str) -> list[int]:
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated channel numbers (0-based), got {text!r}") from None
    if not values or min(values) < 0 or len(set(values)) != len(values):
        raise argparse.ArgumentTypeError(f"expected distinct channel numbers >= 0, got {text!r}")
    return values


def _positive(kind):
    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a positive {kind.__name__}, got {text!r}") from None
        if not value > 0:
            raise argparse.ArgumentTypeError(f"expected a positive {kind.__name__}, got {text!r}")
        return value
    return parse


def _quantities(text: str) -> list[str]:
    names = {"d": "displacement", "v": "velocity", "a": "acceleration"}
    values = [v.strip().lower() for v in text.split(",") if v.strip()]
    full = [names.get(v, v) for v in values]
    if not full or any(v not in names.values() for v in full):
        raise argparse.ArgumentTypeError(f"expected comma-separated d, v or a (displacement, velocity, "
                                         f"acceleration), got {text!r}")
    return full


#: How the command line reads each kind of option of :class:`modal.IdentifyOptions`.
_PARSERS = {"number": _positive(float), "integer": _positive(int), "integer-list": _indices,
            "quantity-list": _quantities}


def _identify_options(cmd) -> None:
    """The options of :class:`modal.IdentifyOptions` as command-line options,
    derived from its fields: the flag, help, kind and default are the
    field's; ``excitation`` is the required choice ``--ambient`` |
    ``--free-decay``. Each option left out is ``None`` (the field's default)."""
    import dataclasses

    from modal.measured import IdentifyOptions

    for f in dataclasses.fields(IdentifyOptions):
        schema, help = f.metadata["schema"], f.metadata["help"]
        if f.metadata["flag"] is None:  # a choice: one flag per value
            group = cmd.add_mutually_exclusive_group(required=f.default is dataclasses.MISSING)
            for value in schema["enum"]:
                group.add_argument(f"--{value.replace('_', '-')}", dest=f.name, action="store_const", const=value,
                                   help=f.metadata["choices"][value])
            continue
        kind = schema["type"][0] if isinstance(schema["type"], list) else schema["type"]
        if kind == "array":
            kind = "quantity-list" if "enum" in schema["items"] else "integer-list"
        cmd.add_argument(f.metadata["flag"], dest=f.name, type=_PARSERS[kind], metavar=f.metadata["metavar"],
                         help=help)


def identify_options(args):
    """The :class:`modal.IdentifyOptions` of parsed arguments (``ValueError``
    naming the option when they contradict each other)."""
    from modal.measured import IdentifyOptions

    return IdentifyOptions.from_mapping({name: getattr(args, name) for name in IdentifyOptions.names()})


def parser() -> argparse.ArgumentParser:
    main = argparse.ArgumentParser(prog="modal", description="Modal identification of measured records.")
    commands = main.add_subparsers(dest="command", required=True)
    cmd = commands.add_parser(
        "identify",
        help="modes of a record: stabilisation diagram and automatic selection",
        description="Identify the modes of a measured record (ERA on NExT correlations or on a free decay).",
        epilog=EPILOG,
    )
    cmd.add_argument("paths", type=Path, nargs="+", metavar="SETUP",
                     help="a record (.npy .npz .csv .txt .tsv .asc .dat .lvm .uff .unv), or the setups of a roving test: "
                          "folders in pyOMA's layout or with a channels.csv beside the record (merged into one "
                          "set of modes)")
    _identify_options(cmd)
    cmd.add_argument("--delimiter", help="text files: column delimiter (default: sniffed)")
    cmd.add_argument("--decimal", choices=[".", ","],
                     help="text files: decimal mark (default: '.', or ',' where only a comma reads the numbers)")
    cmd.add_argument("--skip-rows", type=int, default=0, help="text files: lines to skip at the top")
    cmd.add_argument("--out", type=Path, required=True,
                     help="output folder (created; its files are replaced only once all are written)")
    cmd.add_argument("--geometry", type=Path, help="folder of the structure's geometry (nodes.csv; pyOMA's grid.txt; "
                     "pyOMA2's pts_coord.txt or sens_coord.txt): the shapes drawn on it, mode_<k>.png and .gif")
    cmd.add_argument("--min-setups", type=_positive(int), help="setups a merged mode must be selected in "
                     "(default more than half of them: both of two)")
    cmd.add_argument("--no-animation", action="store_true", help="with --geometry: no mode_<k>.gif")
    cmd.add_argument("--quiet", action="store_true", help="no progress messages")
    run = commands.add_parser(
        "campaign",
        help="a monitoring campaign: many records identified, their modes tracked over time",
        description="Identify every record of a campaign (a YAML file naming the records and the options of "
                    "modal identify), track the modes over time and write a report; a Snakemake workflow that "
                    "resumes after an interruption and, with --profile, runs on a cluster.",
        epilog="Exit codes: 0 done, 2 bad options or campaign file (also: another run is active in --out), "
               "4 done but no record identified (failed.csv says why), "
               "7 the workflow stopped (its log says why; run again to resume), 128+N stopped by signal N "
               "(130 SIGINT, 143 SIGTERM, 129 SIGHUP: the workflow and its jobs are stopped with it; run again "
               "to resume).",
    )
    run.add_argument("campaign", type=Path, help="the campaign's YAML file (docs: Monitoring campaigns)")
    run.add_argument("--out", type=Path, required=True, help="output folder (kept between runs: a rerun resumes)")
    run.add_argument("--cores", type=_positive(int), default=1, help="cores on this machine (default 1)")
    run.add_argument("--profile", help="a Snakemake profile folder, or 'slurm' for the shipped Slurm profile")
    run.add_argument("--dry-run", action="store_true", help="plan only: list the jobs that would run")
    return main


def _fail(code: int, message: str) -> int:
    print(f"modal identify: {message}", file=sys.stderr)
    return code


def _logger(args):
    """Progress messages on stderr with the time since the command began
    (none with ``--quiet``)."""
    started = time.perf_counter()

    def log(message):
        if not args.quiet:
            print(f"[{time.perf_counter() - started:6.1f} s] {message}", file=sys.stderr, flush=True)
    return log


def _wrote(out: Path) -> str:
    """What the results folder holds, every file named (it is written
    whole: what is there is what this run wrote)."""
    names = sorted(p.name + ("/" if p.is_dir() else "") for p in out.iterdir())
    return f"wrote {out}/: {', '.join(names)}"


def _written(args, call, subject=""):
    """Run ``call`` (which identifies and writes ``--out``); returns its value
    and None, or None and the exit code of its failure (message printed)."""
    from modal.measured import OutputError

    try:
        with _one_line_warnings():
            return call(), None
    except OutputError as exc:
        return None, _fail(EXIT_BAD_OPTIONS, f"bad --out: {str(exc).removeprefix('out: ')}")
    except (ValueError, MemoryError) as exc:
        return None, _fail(EXIT_CANNOT_IDENTIFY, f"{subject}{exc or 'out of memory'}")
    except OSError as exc:
        return None, _fail(EXIT_CANNOT_WRITE, f"cannot write the results to {args.out} ({exc.strerror or exc}); "
                                              "it is left as it was")


@contextmanager
def blas_threads():
    """Hold BLAS to one thread for the block (threadpoolctl), unless one of
    :data:`THREAD_VARIABLES` is set: the identification's matrices are too
    small for threads to pay (docs/benchmarks.md measures it)."""
    import os

    if any(os.environ.get(name) for name in THREAD_VARIABLES):
        yield
        return
    import numpy  # noqa: F401  threadpoolctl limits the libraries loaded when it is called:
    import scipy.linalg  # noqa: F401  numpy's and scipy's BLAS (each may ship its own)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _command(args) -> str:
    """The command line as typed (for settings.json and the report)."""
    import shlex

    return shlex.join(["modal", *args.argv]) if getattr(args, "argv", None) is not None else None


def identify(args) -> int:
    """Run ``modal identify`` with parsed arguments; returns the exit code."""
    with blas_threads():
        return _identify(args)


def _identify(args) -> int:
    import modal
    from modal.measured import OutputError, check_output

    try:
        options = identify_options(args)
    except ValueError as exc:
        return _fail(EXIT_BAD_OPTIONS, f"bad options: {exc}")
    first = args.paths[0]
    if len(args.paths) > 1 or args.geometry is not None or \
            any((first / name).is_file() for name in ("channel_dofs.txt", "channels.csv")):
        return identify_setups(args, options)
    args.path = args.paths[0]
    log, fail = _logger(args), _fail

    def progress(done, total):
        if not args.quiet and (done == total or done % 10 == 0):
            log(f"  order {2 * done}/{2 * total}")

    try:
        check_output(args.out, inputs=[args.path])
    except OutputError as exc:
        return fail(EXIT_BAD_OPTIONS, f"bad --out: {str(exc).removeprefix('out: ')}")
    try:
        with _one_line_warnings():
            record = modal.read_record(args.path, args.fs, delimiter=args.delimiter, decimal=args.decimal,
                                       skip_rows=args.skip_rows)
    except (ValueError, OSError) as exc:
        return fail(EXIT_BAD_FILE, f"cannot read the record: {exc}")
    n_samples, n_channels = record.acc.shape
    log(f"read {args.path}: {n_samples} samples x {n_channels} channels at {record.fs:.6g} Hz")
    problems = options.record_problems(n_channels, record.fs, n_samples)
    if problems:
        return fail(EXIT_BAD_OPTIONS, f"bad options for {args.path}: {'; '.join(problems)}")
    written, code = _written(args, lambda: modal.write_identification(
        record, args.out, options, title=args.path.name, log=log, progress=progress, command=_command(args)),
        subject=f"{args.path}: ")
    if code is not None:
        return code
    result = written[0]
    log(_wrote(args.out))
    modes, trusted = result.modes, result.trusted_modes  # doubtful modes (a flag) stay in modes.csv only
    doubtful = modes[~modes.index.isin(trusted.index)]
    print(f"{args.path.name}: {len(trusted)} modes ({options.max_order // 2} orders, {len(result.poles)} poles)"
          + (f"; {len(doubtful)} doubtful, in modes.csv with the reason in flag: "
             + ", ".join(f"{f:.4g} Hz ({why})" for f, why in zip(doubtful["freq_hz"], doubtful["flag"]))
             if len(doubtful) else ""))
    if len(modes):
        if len(trusted):
            print("damping: ratio to critical (fraction, not %), as in modes.csv; *_std: standard deviation of the "
                  "estimate; *_spread: over the model orders")
            print(trusted[["mode", "freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std", "n_poles",
                           "mpc", "mamc"]]
                  .to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        return 0
    return fail(EXIT_NO_MODES, f"no mode selected: {result.no_mode_reason()}")


def identify_setups(args, options) -> int:
    """``modal identify SETUP [SETUP ...]``: each setup identified with
    ``options`` (:class:`modal.IdentifyOptions`), the setups merged through
    their reference channels (:func:`modal.write_setups`)."""
    import modal

    log, fail = _logger(args), _fail
    given = [f"--{name}" for name in ("channels", "refs", "quantities") if getattr(args, name) is not None]
    if given:
        return fail(EXIT_BAD_OPTIONS, f"{', '.join(given)}: with setups or a geometry the channel tables say which "
                                      "channels are used, which are references and what they measure")
    try:
        with _one_line_warnings():
            geometry = None if args.geometry is None else modal.read_geometry(args.geometry)
            setups = [modal.read_setup(p, args.fs, geometry) for p in args.paths]
            modal.check_setups(setups)
    except (ValueError, OSError) as exc:
        return fail(EXIT_BAD_FILE, f"cannot read the setups: {exc}")
    written, code = _written(args, lambda: modal.write_setups(
        setups, args.out, options, geometry=geometry, min_setups=args.min_setups, animate=not args.no_animation,
        log=log, command=_command(args)))
    if code is not None:
        return code
    merged, results = written
    log(_wrote(args.out))
    doubtful = merged.modes[merged.modes["flag"] != ""]  # kept in modes.csv with the reason, not printed
    modes = merged.modes[merged.modes["flag"] == ""]
    print(f"{len(setups)} setup(s): {len(modes)} modes (selected in at least "
          f"{modal.setups.required_setups(len(setups), args.min_setups)} setups); shapes at "
          f"{merged.shapes['node'].nunique()} nodes "
          f"in {args.out / 'shapes.csv'}"
          + (f"; {len(doubtful)} doubtful, in modes.csv with the reason in flag: "
             + ", ".join(f"{f:.4g} Hz" for f in doubtful["freq_hz"]) if len(doubtful) else ""))
    if len(modes):
        print("damping: ratio to critical (fraction, not %); *_std: standard deviation of the mean over the setups; "
              "*_spread: the setups' standard deviation")
        print(modes[["mode", "freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std", "damping_spread",
                     "n_setups", "n_from_diagram", "ref_mac", "mpc", "n_nodes"]].to_string(
                         index=False, float_format=lambda v: f"{v:.4g}"))
        return 0
    found = ", ".join(f"{s.name} {len(r.modes)}" for s, r in zip(setups, results))
    bad = "".join(f"; setup {row.setup} left out ({row.check}): {row.evidence}"
                  for row in merged.disagreements.itertuples())
    return fail(EXIT_NO_MODES, f"no mode selected in enough setups (modes per setup: {found}){bad}")


@contextmanager
def _one_line_warnings():
    """Print each distinct warning of the block as one line on stderr (no
    source line), also when the block raises; the engine's own no-mode
    warning is left out: the no-mode message says more."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        finally:
            seen = set()
            for w in caught:
                text = " ".join(str(w.message).split())
                if text in seen or text.startswith("no mode selected"):
                    continue
                seen.add(text)
                print(f"modal identify: warning: {text}", file=sys.stderr)


def campaign(args) -> int:
    """``modal campaign``: :func:`modal.campaign.run` with the command line's
    options, its messages on stderr; returns the exit code."""
    import shlex

    from modal.campaign import NoRecordIdentified, WorkflowStopped, run
    from modal.measured import OutputError

    # What asks for these results, for the report; --cores and --profile change none of them.
    command = shlex.join(["modal", "campaign", str(args.campaign), "--out", str(args.out)])
    try:
        run(args.campaign, args.out, cores=args.cores, profile=args.profile, dry_run=args.dry_run, command=command,
            log=lambda message: print(f"modal campaign: {message}", file=sys.stderr))
    except OutputError as exc:
        print(f"modal campaign: bad --out: {str(exc).removeprefix('out: ')}", file=sys.stderr)
        return EXIT_BAD_OPTIONS
    except (ValueError, OSError) as exc:
        print(f"modal campaign: {exc}", file=sys.stderr)
        return EXIT_BAD_OPTIONS
    except ImportError as exc:
        print(f"modal campaign: needs the workflow extra (pip install 'modal-identification[workflow]'): {exc}",
              file=sys.stderr)
        return EXIT_BAD_OPTIONS
    except WorkflowStopped as exc:
        if exc.signum is not None:  # SIGINT, SIGTERM, SIGHUP: Snakemake and its jobs were stopped with it
            print(f"modal campaign: interrupted ({signal.Signals(exc.signum).name}); the workflow stopped; its log "
                  f"is in {exc.log}; run the same command again to resume", file=sys.stderr)
            return 128 + exc.signum
        print(f"modal campaign: the workflow stopped (exit {exc.returncode}); its log is in {exc.log}; "
              "run the same command again to resume", file=sys.stderr)
        return EXIT_WORKFLOW
    except NoRecordIdentified as exc:
        print(f"modal campaign: warning: {exc}", file=sys.stderr)
        return EXIT_CANNOT_IDENTIFY
    return 0


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    args.argv = [str(a) for a in (sys.argv[1:] if argv is None else argv)]
    try:
        return campaign(args) if args.command == "campaign" else identify(args)
    except KeyboardInterrupt:
        print(f"modal {args.command}: interrupted", file=sys.stderr)
        return 130
    except MemoryError as exc:  # reading a record whose header promises more than the memory holds, ...
        print(f"modal {args.command}: not enough memory{': ' + str(exc) if str(exc) else ''}", file=sys.stderr)
        return EXIT_CANNOT_IDENTIFY
    except Exception as exc:  # the contract: a one-line message, never a traceback
        print(f"modal {args.command}: internal error, please report: {type(exc).__name__}: {exc}", file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
