"""A study's cases, its Monte Carlo seeds split into chunks (one workflow job
each), and the merge that gives back, byte for byte, the file the unsplit run
writes.

A seeds mapping ``{"first": f, "count": c, "chunk": k}`` (``chunk`` optional,
default ``count``: one chunk) splits the seeds ``f ... f + c - 1`` into
``ceil(c / k)`` consecutive ranges. The number of identification jobs grows
with the number of seeds, so a cluster can spread them.

Plain Python (no numpy, pandas or engine): Snakemake plans the jobs with
these functions before any job runs, and the merge jobs run nothing else.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping, Sequence


def study_cases(study: Mapping) -> dict[str, dict]:
    """Cases of a study as ``{name: {"damping": zeta, "noise": eta}}``: the
    explicit ``cases`` mapping, plus one case per entry of ``noise_sweep``
    (``{"damping": zeta, "noise": [eta, ...]}``) named ``eta_<eta>``."""
    cases = {name: dict(case) for name, case in study.get("cases", {}).items()}
    sweep = study.get("noise_sweep")
    if sweep:
        for eta in sweep["noise"]:
            cases[f"eta_{eta:g}"] = {"damping": sweep["damping"], "noise": eta}
    return cases


def seed_chunks(seeds: Mapping) -> list[range]:
    """The seed ranges of ``seeds`` (``first``, ``count``, optional ``chunk``).

    Examples
    --------
    >>> seed_chunks({"first": 10, "count": 5, "chunk": 2})
    [range(10, 12), range(12, 14), range(14, 15)]
    """
    first, count = seeds["first"], seeds["count"]
    size = seeds.get("chunk")
    size = count if size is None else size
    for key, value, low in (("first", first, 0), ("count", count, 1), ("chunk", size, 1)):
        if not isinstance(value, int) or isinstance(value, bool) or value < low:
            raise ValueError(f"seeds.{key} must be an integer >= {low}, got {value!r}")
    return [range(start, min(start + size, first + count)) for start in range(first, first + count, size)]


def chunk_seeds(seeds: Mapping, chunk: int | None) -> range:
    """The seeds of chunk number ``chunk`` (0-based); ``None``: every seed."""
    chunks = seed_chunks(seeds)
    if chunk is None:
        return range(seeds["first"], seeds["first"] + seeds["count"])
    if not 0 <= chunk < len(chunks):
        raise ValueError(f"chunk must be in 0 ... {len(chunks) - 1} for seeds {dict(seeds)}, got {chunk!r}")
    return chunks[chunk]


def merge_chunks(paths: Sequence, out, group_by: str | None = None) -> None:
    """Concatenate the CSV files of the chunks, in chunk order, into ``out``.

    The cells are copied as text (never parsed as numbers), so the merged file
    equals, byte for byte, the one an unsplit run writes, provided the unsplit
    run orders its rows as the chunks do: seed-major (the grid), or, with
    ``group_by="case"``, grouped by case in the first chunk's order and by
    seed within a case (a beam study, whose noise-free cases only the first
    chunk holds).
    """
    if not paths:
        raise ValueError("paths: at least one chunk file is needed")
    tables = [_read_csv(p) for p in paths]
    header = tables[0][0]
    for path, (other, _) in zip(paths, tables):
        if other != header:
            raise ValueError(f"paths: {path} has the columns {other}, {paths[0]} has {header}")
    rows = [row for _, chunk_rows in tables for row in chunk_rows]
    if group_by is not None:
        column = header.index(group_by)
        order = {value: i for i, value in enumerate(dict.fromkeys(row[column] for row in tables[0][1]))}
        missing = {row[column] for row in rows} - set(order)
        if missing:
            raise ValueError(f"paths: {group_by} {sorted(missing)} missing from the first chunk {paths[0]}")
        rows.sort(key=lambda row: order[row[column]])  # stable: seed order within a case
    with open(out, "w", encoding="utf-8", newline="") as fh:
        writer = csv.writer(fh, lineterminator="\n")  # as pandas' to_csv writes them
        writer.writerow(header)
        writer.writerows(rows)


def _read_csv(path) -> tuple[list[str], list[list[str]]]:
    """Header and rows of a CSV file, every cell as its text."""
    with open(path, encoding="utf-8", newline="") as fh:
        lines = [row for row in csv.reader(fh) if row]
    if not lines:
        raise ValueError(f"paths: {path} is empty (not even a header)")
    return lines[0], lines[1:]


def merge_grid_chunks(identified: Sequence, selection: Sequence, first_record, out: Mapping) -> None:
    """The grid's chunks -> ``out["identified"]``, ``out["selection"]`` (seed-major,
    as :func:`modal.thesis.grid_study.run_grid_study` writes them) and
    ``out["record"]``, a copy of the first chunk's first record."""
    import shutil

    merge_chunks(identified, out["identified"])
    merge_chunks(selection, out["selection"])
    shutil.copyfile(first_record, out["record"])
