"""The results folder of a record, written completely or not at all.

:func:`write_identification` writes into a hidden folder beside the target
(``.NAME.XXXX.partial``) and moves the files into place only when all of them
are written: a failure part-way (a full disk, an interrupt, an error while
drawing) leaves the previous results untouched and no partial file. The
target is checked before any computation, so that a path that can never hold
the results is refused at once rather than after minutes of identification.
"""

from __future__ import annotations

import os
import shutil
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path


class OutputError(ValueError):
    """The output folder cannot hold the results (found before any computation)."""


def _kind(mode: int) -> str:
    if stat.S_ISREG(mode):
        return "a file"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    return "not a folder"


def check_output(out, inputs=()) -> Path:
    """``out`` as a Path if it can be the results folder, else :class:`OutputError`.

    Refused: a path that is, holds or lies inside one of ``inputs``
    (:func:`overlapping_input`: a record, a setup's folder, a channel table,
    a geometry, a campaign's files), an existing path that is not a folder
    (``/proc/version``),
    a path below something that is not a folder (``/dev/null/x``), and a
    folder (or its nearest existing parent, where it would be created) that
    is on a read-only file system or not writable by this user.
    """
    out = Path(out)
    try:
        return _check_output(out, inputs)
    except OSError as exc:  # e.g. a parent that is not searchable
        raise OutputError(f"out: {out}: {exc.strerror or exc}") from None


def _check_output(out: Path, inputs) -> Path:
    overlap = overlapping_input(out, [source for source in inputs if source is not None])
    if overlap is not None:
        raise OutputError(f"out: {out} {overlap}: the results would overwrite or mix with the inputs; give a "
                          "folder of its own")
    if out.exists():
        mode = out.stat().st_mode
        if not stat.S_ISDIR(mode):
            raise OutputError(f"out: {out} exists and is {_kind(mode)}, not a folder")
        existing = out
    else:
        existing = out.parent
        while not existing.exists() and existing != existing.parent:
            existing = existing.parent
        if os.path.lexists(out):  # exists() is False for a dangling symlink
            raise OutputError(f"out: {out} is a broken link")
        mode = existing.stat().st_mode
        if not stat.S_ISDIR(mode):
            raise OutputError(f"out: {out} cannot be created: {existing} is {_kind(mode)}, not a folder")
    if _read_only(existing):
        raise OutputError(f"out: {existing} is on a read-only file system")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputError(f"out: {existing} is not writable (permission denied)")
    return out


def overlapping_input(out, inputs) -> str | None:
    """How ``out`` overlaps one of ``inputs`` (is it, holds it, lies inside
    it), or None: the one rule of every command that writes results (``modal
    identify`` with a record or setups, ``modal campaign``). Paths are
    compared resolved (links followed), so a second name of an input is
    caught too. A folder that holds an input is refused even when no result
    bears an input's name: the results of one run would mix with the data
    of the next (a setup folder given as ``--out`` once replaced that
    setup's ``channels.csv``)."""
    out = Path(out).resolve()
    for source in inputs:
        source = Path(source).resolve()
        if source == out:
            return f"is the input {source}"
        if out in source.parents:
            return f"holds the input {source}"
        if source in out.parents:
            return f"lies inside the input {source}"
    return None


def _read_only(path: Path) -> bool:
    try:
        return bool(os.statvfs(path).f_flag & os.ST_RDONLY)
    except OSError:
        return False


@contextmanager
def staged_folder(out: Path):
    """Yield an empty hidden folder beside ``out``; on normal exit move what
    was written there into ``out``, on any exception remove it (and the
    parents of ``out`` that were created for it) and re-raise.

    A new ``out`` is the staging folder renamed (atomic); in an existing
    folder each file is replaced (``os.replace``, atomic per file) after all
    of them are written, a sub-folder as a whole (the old one moved aside,
    the new one in its place), and other files in it are left alone.

    Raises
    ------
    OutputError
        The staging folder cannot be created (before any work is done).
    """
    out = Path(out)
    created = []
    try:
        missing = [p for p in [out.parent, *out.parent.parents] if not p.exists()]
        for parent in reversed(missing):
            parent.mkdir()
            created.append(parent)
        staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".partial", dir=out.parent))
    except OSError as exc:
        _remove_created(created)
        raise OutputError(f"out: cannot create the results folder {out} ({exc.strerror or exc})") from None
    try:
        yield staging
        os.chmod(staging, 0o777 & ~_umask())  # mkdtemp makes it private; results are ordinary files
        if not out.exists():
            try:
                os.rename(staging, out)
                return
            except OSError:
                if not out.is_dir():
                    raise
        for item in sorted(staging.iterdir()):
            target = out / item.name
            if item.is_dir() and target.is_dir():  # a folder of results (setups/<name>/): the old one aside, then gone
                old = Path(tempfile.mkdtemp(prefix=f".{item.name}.", suffix=".old", dir=out))
                os.replace(target, old / item.name)
                os.replace(item, target)
                shutil.rmtree(old)
            else:
                os.replace(item, target)
        staging.rmdir()
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        _remove_created(created)
        raise


def _remove_created(created):
    for parent in reversed(created):
        try:
            parent.rmdir()
        except OSError:
            pass


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
