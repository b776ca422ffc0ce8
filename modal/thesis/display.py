"""What the report notebooks show, in one place: a table in the thesis's
layout with its computed notes, its tidy rows, a figure with the thesis's
caption, the verdicts of ``summary.csv``, and what has not been produced.
Every notebook imports these (``from modal.thesis.display import Results``);
they read the workflow's files and compute nothing."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from .report import REFERENCE_METHODS, VERDICT_DEFINITIONS, headline, read_notes
from .tables import read_table

#: The columns of a tidy table a reader wants first.
TIDY = ["mode", "method", "interpretation", "column", "printed", "reproduced", "std", "n_seeds", "z", "rel_dev",
        "printed_match"]


def _display(*objects):
    from IPython.display import display

    display(*objects)


def show_figure(fig) -> None:
    """A matplotlib Figure (no pyplot) as a PNG in the notebook."""
    import io

    from IPython.display import Image

    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    _display(Image(data=buffer.getvalue(), format="png"))


#: How the numeric columns of a tidy table are shown.
FORMATS = {"reproduced": "{:.4f}", "std": "{:.4f}", "seed0": "{:.4f}", "published": "{:.4f}", "z": "{:+.2f}",
           "rel_dev": "{:+.3%}", "real_pole_frac": "{:.0%}", "missed_frac": "{:.0%}", "max_abs_rel_dev": "{:.3g}",
           "n_within_noise": "{:.0f}"}


def styled(frame: pd.DataFrame, formats=None):
    """A table for reading: numbers to the digits that matter (``formats``
    adds column -> format), a relative deviation in percent, missing values
    blank, no index, text escaped (a title from a config is text, never HTML)."""
    formats = {c: f for c, f in {**FORMATS, **(formats or {})}.items() if c in frame}
    text = [c for c in frame if c not in formats and not pd.api.types.is_numeric_dtype(frame[c])]
    style = frame.style.hide(axis="index").format(formats, na_rep="")
    return style.format(subset=text, escape="html", na_rep="") if text else style


def escape_markdown_html(text: str) -> str:
    """``<``, ``>`` and ``&`` outside code spans as HTML entities: Markdown
    passes raw HTML through, and a table title or note is text, never HTML
    (inside backticks Markdown shows them literally already)."""
    import html

    parts = text.split("`")
    return "`".join(part if i % 2 else html.escape(part, quote=False) for i, part in enumerate(parts))


def markdown(text: str) -> None:
    """Markdown with '*' (the thesis's real-pole mark) kept literal and any
    HTML in it shown as text (:func:`escape_markdown_html`)."""
    from IPython.display import Markdown

    _display(Markdown(escape_markdown_html(text).replace("*", r"\*")))


class Results:
    """The workflow's outputs, read from the paths of a notebook's
    ``parameters`` cell (relative to where the notebook runs)."""

    def __init__(self, tables_dir, figures_dir=None, captions_file=None, summary_file=None, notes_dir=None):
        self.tables_dir = Path(tables_dir)
        # the notes of each table sit beside results/tables, in results/notes
        self.notes_dir = Path(notes_dir) if notes_dir else self.tables_dir.parent / "notes"
        self.figures_dir = Path(figures_dir) if figures_dir else None
        self.summary_file = Path(summary_file) if summary_file else None
        self.captions = {}
        if captions_file:
            import yaml

            self.captions = yaml.safe_load(Path(captions_file).read_text(encoding="utf-8"))

    def table(self, number: int) -> pd.DataFrame | None:
        """Show ``table_NN.md`` (the thesis's layout and the notes); return the tidy ``table_NN.csv``."""
        path = self.tables_dir / f"table_{number:02d}.md"
        if not path.exists():
            markdown(f"**Table {number} is missing:** `{path}` has not been produced.")
            return None
        markdown(path.read_text(encoding="utf-8"))
        return read_table(path.with_suffix(".csv"))

    def read(self, number: int) -> pd.DataFrame | None:
        """The tidy ``table_NN.csv``, or None when not produced."""
        path = self.tables_dir / f"table_{number:02d}.csv"
        return read_table(path) if path.exists() else None

    def notes(self, number: int) -> list[str]:
        """The computed notes of a table (``results/notes/table_NN.txt``)."""
        return read_notes(self.notes_dir / f"table_{number:02d}.txt")

    def tidy(self, frame: pd.DataFrame | None) -> None:
        """The identified values of a table, one row per value (reference
        columns and the thesis's empty cells "-----" left out)."""
        if frame is not None:
            shown = ~frame["method"].isin(REFERENCE_METHODS) & (frame["flag"] != "absent")
            _display(styled(frame.loc[shown, [c for c in TIDY if c in frame]]))

    def figure(self, number: int | None = None, name: str | None = None, caption: str | None = None) -> None:
        """A figure (PNG) with the thesis's caption, or a note that it is missing."""
        from IPython.display import Image

        png = self.figures_dir / (name or f"figure_{number:02d}.png")
        caption = caption or f"Figure {number}. {self.captions.get('figures', {}).get(number, '')}"
        if not png.exists():
            markdown(f"**Missing:** `{png}` ({caption}) has not been produced.")
            return
        _display(Image(filename=str(png)))
        markdown(f"_{caption}_")

    def summary(self, numbers=None) -> pd.DataFrame | None:
        """The rows of ``summary.csv`` (rule ``summary``) for these tables (all by default)."""
        if self.summary_file is None or not self.summary_file.exists():
            markdown(f"**The summary `{self.summary_file}` has not been produced yet.**")
            return None
        frame = pd.read_csv(self.summary_file)
        return frame if numbers is None else frame[frame["table"].isin(list(numbers))]

    def verdicts(self, numbers=None, definitions: bool = False) -> pd.DataFrame | None:
        """Show the verdicts of these tables, optionally with their definitions."""
        frame = self.summary(numbers)
        if frame is None:
            return None
        from IPython.display import HTML

        markdown(f"**{headline(frame)}**")
        shown = frame[[c for c in ("table", "title", "interpretation", "n_match", "n_compared", "n_within_noise",
                                   "max_abs_rel_dev", "worst", "stable", "verdict", "cause", "why") if c in frame]]
        shown = shown.assign(max_abs_rel_dev=100 * shown["max_abs_rel_dev"]).rename(
            columns={"max_abs_rel_dev": "largest |deviation| (%)"})
        _display(HTML(styled(shown, {"largest |deviation| (%)": "{:.3g}"}).to_html()))
        if definitions:
            markdown("\n".join(f"- {d}" for d in VERDICT_DEFINITIONS))
        return frame

    def claims(self, claims_file) -> pd.DataFrame | None:
        """Show ``claims.csv`` (rule ``claims``) with its count; return it."""
        from IPython.display import HTML

        from .claims import claims_headline

        path = Path(claims_file)
        if not path.exists():
            markdown(f"**The claims `{path}` have not been produced yet.**")
            return None
        frame = pd.read_csv(path)
        markdown(f"**{claims_headline(frame)}**")
        _display(HTML(styled(frame).to_html()))
        return frame

    def inventory(self, tables, figures) -> pd.DataFrame:
        """Which of these tables and figures exist; shows a one-line count."""
        rows = [(f"Table {n}", str(self.tables_dir / f"table_{n:02d}.{ext}"),
                 (self.tables_dir / f"table_{n:02d}.{ext}").exists()) for n in tables for ext in ("csv", "md")]
        rows += [(f"Figure {n}", str(self.figures_dir / f"figure_{n:02d}.png"),
                  (self.figures_dir / f"figure_{n:02d}.png").exists()) for n in figures]
        frame = pd.DataFrame(rows, columns=["item", "file", "produced"])
        missing = list(dict.fromkeys(frame.loc[~frame["produced"], "item"]))
        markdown(f"**{int(frame['produced'].sum())} of {len(frame)} output files produced.**"
                 + (" Not produced: " + ", ".join(missing) + "." if missing else ""))
        return frame
