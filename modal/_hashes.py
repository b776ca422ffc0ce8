"""Contents as hashes, for both workflows' params: a job reruns when what it
reads changed, whatever the time stamps say."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path


def file_hash(path) -> str:
    """sha256 of a file's bytes, read in 1 MiB blocks."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def content_hashes(paths, cache=None) -> dict[str, str | None]:
    """``{path: sha256}`` of the files ``paths`` (None for one that does not
    exist or cannot be read).

    With ``cache`` (a JSON file, written back), a file is hashed again only
    when its inode, size, modification or status-change time differ from
    when it was hashed: a write to a file changes its status-change time
    (``st_ctime_ns``), which no user can set (``touch -d`` sets only the
    modification time), so a change of content is always seen while a
    campaign of thousands of records is not read in full at every start.
    """
    known = {}
    if cache is not None:
        try:
            known = json.loads(Path(cache).read_text())
        except (OSError, ValueError):
            known = {}
    hashes, fresh = {}, {}
    for path in map(str, paths):
        try:
            st = os.stat(path)
        except OSError:
            hashes[path] = None
            continue
        key = [st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns]
        entry = known.get(path)
        if entry is not None and entry[0] == key:
            hashes[path] = entry[1]
        else:
            try:
                hashes[path] = file_hash(path)
            except OSError:
                hashes[path] = None
                continue
        fresh[path] = [key, hashes[path]]
    if cache is not None and fresh != known:
        cache = Path(cache)
        cache.parent.mkdir(parents=True, exist_ok=True)
        staged = cache.with_name(cache.name + ".tmp")
        staged.write_text(json.dumps(fresh))
        staged.replace(cache)
    return hashes
