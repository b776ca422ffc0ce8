"""Where the project's files are, so a notebook opened anywhere finds them.

The report notebooks take their paths as papermill parameters (the workflow
injects its run's folders); opened by hand in Jupyter, from any folder, they
default to the committed results under :data:`PROJECT`.
"""

from pathlib import Path

#: The checkout: the folder holding ``modal/``, ``results/`` and ``config/``.
PROJECT = Path(__file__).resolve().parents[2]


def project_path(relative: str) -> str:
    """``relative`` (e.g. ``"results/tables"``) under :data:`PROJECT`, as a string."""
    return str(PROJECT / relative)
