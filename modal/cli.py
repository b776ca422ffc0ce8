"""Command line: ``modal identify`` (also ``python -m modal identify``).

::

    modal identify PATH [--fs HZ] [--channels i,j,...] [--refs i,j,...]
                        (--ambient | --free-decay) [--fmax HZ] [--max-order N]
                        [--rows N] [--highpass HZ] [--delimiter C] [--decimal C]
                        [--skip-rows N] --out DIR

reads a record (:func:`modal.read_record`), identifies its modes
(:func:`modal.write_identification`: NExT correlations for ambient data, the decay
after the impact for free decay, a stabilisation diagram with automatic mode
selection) and writes ``DIR/modes.csv``, ``DIR/poles.csv`` and
``DIR/stabilisation.png``.

Exit codes: 0 success; 2 bad options (argparse); 3 the record cannot be read;
4 the identification cannot run on it (too short for the settings, ...);
5 it ran but selected no mode.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

EXIT_BAD_FILE = 3
EXIT_CANNOT_IDENTIFY = 4
EXIT_NO_MODES = 5


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


def parser() -> argparse.ArgumentParser:
    main = argparse.ArgumentParser(prog="modal", description="Modal identification of measured records.")
    commands = main.add_subparsers(dest="command", required=True)
    cmd = commands.add_parser(
        "identify",
        help="modes of a record: stabilisation diagram and automatic selection",
        description="Identify the modes of a measured record (ERA on NExT correlations or on a free decay).",
        epilog="Exit codes: 2 bad options, 3 unreadable record, 4 identification impossible, 5 no mode found.",
    )
    cmd.add_argument("path", type=Path, help="record: .npy .npz .csv .txt .tsv .lvm .uff .unv")
    cmd.add_argument("--fs", type=_positive(float), help="sampling rate (Hz); overrides a text file's time column")
    cmd.add_argument("--channels", type=_indices, help="channels to use, 0-based, e.g. 0,1,2 (default all)")
    cmd.add_argument("--refs", type=_indices, help="reference channels among --channels' numbering of the file, "
                     "for the correlations (default all)")
    kind = cmd.add_mutually_exclusive_group(required=True)
    kind.add_argument("--ambient", action="store_true", help="output-only (operational) record")
    kind.add_argument("--free-decay", action="store_true", help="impact test: the decay after the impact")
    cmd.add_argument("--fmax", type=_positive(float), help="highest frequency of interest (Hz); decimates to 2.5 fmax")
    cmd.add_argument("--max-order", type=_positive(int), default=60, help="largest model order, even (default 60)")
    cmd.add_argument("--rows", type=_positive(int), help="block rows of the Hankel matrix (default 60 or more)")
    cmd.add_argument("--highpass", type=_positive(float), help="zero-phase high-pass before identification (Hz)")
    cmd.add_argument("--delimiter", help="text files: column delimiter (default: sniffed)")
    cmd.add_argument("--decimal", default=".", choices=[".", ","], help="text files: decimal mark")
    cmd.add_argument("--skip-rows", type=int, default=0, help="text files: lines to skip at the top")
    cmd.add_argument("--out", type=Path, required=True, help="output folder (created)")
    cmd.add_argument("--quiet", action="store_true", help="no progress messages")
    return main


def identify(args) -> int:
    """Run ``modal identify`` with parsed arguments; returns the exit code."""
    import modal

    def log(message):
        if not args.quiet:
            print(f"[{time.perf_counter() - started:6.1f} s] {message}", file=sys.stderr, flush=True)

    def progress(done, total):
        if not args.quiet and (done == total or done % 10 == 0):
            log(f"  order {2 * done}/{2 * total}")

    started = time.perf_counter()
    try:
        record = modal.read_record(args.path, args.fs, delimiter=args.delimiter, decimal=args.decimal,
                                   skip_rows=args.skip_rows)
    except ValueError as exc:
        print(f"modal identify: cannot read the record: {exc}", file=sys.stderr)
        return EXIT_BAD_FILE
    n_samples, n_channels = record.acc.shape
    log(f"read {args.path}: {n_samples} samples x {n_channels} channels at {record.fs:.6g} Hz")
    try:
        result, _ = modal.write_identification(
            record, args.out, "ambient" if args.ambient else "free_decay", channels=args.channels, refs=args.refs,
            max_order=args.max_order, fmax=args.fmax, rows=args.rows, highpass_hz=args.highpass,
            title=args.path.name, log=log, progress=progress,
        )
    except ValueError as exc:
        print(f"modal identify: {args.path}: {exc}", file=sys.stderr)
        return EXIT_CANNOT_IDENTIFY
    log(f"wrote {args.out / 'modes.csv'}, poles.csv and stabilisation.png")
    modes = result.modes
    print(f"{args.path.name}: {len(modes)} modes ({args.max_order // 2} orders, {len(result.poles)} poles)")
    if len(modes):
        print(modes.assign(damping_pct=100 * modes["damping"])[
            ["mode", "freq_hz", "freq_std_hz", "damping_pct", "n_poles", "mpc", "mamc"]
        ].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        return 0
    print("no mode selected: raise --max-order or --rows, or check --fmax", file=sys.stderr)
    return EXIT_NO_MODES


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    if args.command == "identify":
        return identify(args)
    return 2  # unreachable: argparse requires a command


if __name__ == "__main__":
    sys.exit(main())
