"""Monte Carlo seeds split into chunks, one workflow job each, and the merge
that gives back, byte for byte, the file the unsplit run writes.

A seeds mapping ``{"first": f, "count": c, "chunk": k}`` (``chunk`` optional,
default ``count``: one chunk) splits the seeds ``f ... f + c - 1`` into
``ceil(c / k)`` consecutive ranges. The number of identification jobs grows
with the number of seeds, so a cluster can spread them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import pandas as pd


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
    frames = [pd.read_csv(p, dtype=str, keep_default_na=False, na_filter=False) for p in paths]
    merged = pd.concat(frames, ignore_index=True)
    if group_by is not None:
        order = {value: i for i, value in enumerate(dict.fromkeys(frames[0][group_by]))}
        missing = set(merged[group_by]) - set(order)
        if missing:
            raise ValueError(f"paths: {group_by} {sorted(missing)} missing from the first chunk {paths[0]}")
        merged = merged.iloc[merged[group_by].map(order).argsort(kind="stable")]
    merged.to_csv(out, index=False)


def merge_grid_chunks(identified: Sequence, selection: Sequence, first_record, out: Mapping) -> None:
    """The grid's chunks -> ``out["identified"]``, ``out["selection"]`` (seed-major,
    as :func:`modal.thesis.grid_study.run_grid_study` writes them) and
    ``out["record"]``, a copy of the first chunk's first record."""
    import shutil

    merge_chunks(identified, out["identified"])
    merge_chunks(selection, out["selection"])
    shutil.copyfile(first_record, out["record"])
