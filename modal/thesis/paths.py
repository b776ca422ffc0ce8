"""Where the project's files are, so a notebook opened anywhere finds them.

The report notebooks take their paths as papermill parameters, relative to
the project (the workflow injects its run's folders and runs from the
project). Opened by hand in Jupyter from another folder (``notebooks/``),
:func:`project_paths` finds the same files under :data:`PROJECT`.
"""

from pathlib import Path

#: The checkout: the folder holding ``modal/``, ``results/`` and ``config/``.
PROJECT = Path(__file__).resolve().parents[2]


def project_paths(*paths: str) -> list[str]:
    """Each path as given where it exists from the current folder, else under
    :data:`PROJECT` (a relative path from a notebook opened anywhere)."""
    return [p if Path(p).exists() or Path(p).is_absolute() else str(PROJECT / p) for p in paths]
