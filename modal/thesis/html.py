"""The HTML report: tables to HTML through pandas, the page through the
jinja2 template ``workflow/report/report.html.j2``. Nothing here formats
HTML by hand; the numbers come from the workflow's CSV files."""

from __future__ import annotations

import base64
from collections.abc import Mapping, Sequence
from pathlib import Path

import pandas as pd

from .tables import thesis_layout

#: Columns of ``summary.csv`` the report shows, with their headings.
SUMMARY_COLUMNS = {
    "table": "Table",
    "title": "Title",
    "n_published": "Published values",
    "n_compared": "Compared",
    "interpretation": "Best interpretation",
    "n_match": "Match printed digits",
    "n_within_noise": "Within noise spread",
    "max_abs_rel_dev": "Largest abs. deviation",
    "worst": "Where",
    "verdict": "Verdict",
    "why": "Why",
}


def summary_frame(summary: pd.DataFrame) -> pd.DataFrame:
    """``summary.csv`` as a reader sees it: counts as integers, the largest
    deviation in percent (three significant digits), headings in words."""
    shown = summary[list(SUMMARY_COLUMNS)].copy()
    shown["n_within_noise"] = shown["n_within_noise"].map(lambda v: "" if pd.isna(v) else str(int(v)))
    shown["max_abs_rel_dev"] = shown["max_abs_rel_dev"].map(lambda v: "" if pd.isna(v) else f"{100 * v:.3g} %")
    return shown.fillna("").rename(columns=SUMMARY_COLUMNS)


def summary_html(summary: pd.DataFrame) -> str:
    return summary_frame(summary).to_html(index=False, border=0, classes="summary", na_rep="")


def layout_html(table: pd.DataFrame) -> str:
    """A tidy table (``table_NN.csv``) in the thesis's layout, as HTML."""
    return thesis_layout(table).to_html(border=0, na_rep="")


def png_data_uri(path) -> str:
    return "data:image/png;base64," + base64.b64encode(Path(path).read_bytes()).decode("ascii")


def render_report(template: Path, summary: pd.DataFrame, definitions: Sequence[str],
                  tables: Mapping[int, dict], figures: Mapping[int, dict], extras: Sequence[dict],
                  provenance: Mapping[str, str]) -> str:
    """The self-contained report page.

    Parameters
    ----------
    template : path
        The jinja2 template (its folder is the loader's search path).
    summary : DataFrame
        ``results/tables/summary.csv``.
    definitions : sequence of str
        The verdict definitions (:data:`modal.thesis.report.VERDICT_DEFINITIONS`).
    tables : mapping
        Table number -> ``{"title", "frame" (tidy table or None when not
        produced), "notes"}``.
    figures : mapping
        Figure number -> ``{"caption", "png" (path or None)}``.
    extras : sequence of mapping
        Results beyond the thesis: ``{"heading", "caption", "png"}``.
    provenance : mapping
        What the page came from (config files), shown at its foot.
    """
    import jinja2

    template = Path(template)
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(template.parent), autoescape=True,
                             undefined=jinja2.StrictUndefined, keep_trailing_newline=True)
    markup = jinja2.utils.markupsafe.Markup
    return env.get_template(template.name).render(
        summary=markup(summary_html(summary)),
        counts=summary["verdict"].value_counts().to_dict(),
        n_tables=len(summary),
        definitions=definitions,
        tables=[dict(number=n, title=t["title"], notes=t.get("notes", []),
                     html=markup(layout_html(t["frame"])) if t["frame"] is not None else None)
                for n, t in sorted(tables.items())],
        figures=[dict(number=n, caption=f["caption"], src=png_data_uri(f["png"]) if f["png"] else None)
                 for n, f in sorted(figures.items())],
        extras=[dict(e, src=png_data_uri(e["png"])) for e in extras],
        provenance=provenance,
    )
