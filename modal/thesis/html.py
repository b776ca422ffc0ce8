"""The HTML report: tables to HTML through pandas, the page through the
jinja2 template ``workflow/report/report.html.j2``. Nothing here formats
HTML by hand; the numbers come from the workflow's CSV files."""

from __future__ import annotations

import base64
import datetime
import subprocess
from collections.abc import Mapping, Sequence
from importlib.metadata import PackageNotFoundError, version
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
    "cause": "Cause",
    "stable": "Noise test stable",
    "why": "Why",
}


#: Packages whose versions the report names.
PACKAGES = ("modal-identification", "numpy", "scipy", "pandas", "matplotlib", "snakemake", "papermill", "jinja2")


def _flatten(mapping, prefix=""):
    out = {}
    for key, value in mapping.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping) and value:
            out.update(_flatten(value, name + "."))
        else:
            out[name] = value
    return out


def config_diff(default: Mapping, used: Mapping) -> list[dict]:
    """The keys where the config a run used differs from the default
    (``config/config.yaml``), as ``{"key", "default", "used"}`` with dotted
    keys (``seeds.count``); values absent on one side are ``"(absent)"``."""
    flat_default, flat_used = _flatten(default), _flatten(used)
    rows = []
    for key in sorted(set(flat_default) | set(flat_used)):
        a, b = flat_default.get(key, "(absent)"), flat_used.get(key, "(absent)")
        if a != b:
            rows.append(dict(key=key, default=str(a), used=str(b)))
    return rows


def _git(root, *args) -> str | None:
    try:
        done = subprocess.run(["git", *args], cwd=root, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def provenance(root, default: Mapping, used: Mapping, configfiles: Sequence[str] = ()) -> dict:
    """What a report came from: the commit and whether the work tree had
    uncommitted changes (``git status --porcelain``), the config files and
    the config's differences from the default (:func:`config_diff`), the
    versions of :data:`PACKAGES`, the Python version and the date (UTC)."""
    import platform

    commit = _git(root, "rev-parse", "HEAD")
    status = _git(root, "status", "--porcelain", "--untracked-files=no")
    versions = {}
    for package in PACKAGES:
        try:
            versions[package] = version(package)
        except PackageNotFoundError:
            versions[package] = "not installed"
    versions["python"] = platform.python_version()
    return dict(
        commit=commit or "unknown (not a git work tree)",
        dirty=None if status is None else bool(status),
        changed=status.splitlines() if status else [],
        configfiles=list(configfiles),
        config_diff=config_diff(default, used),
        versions=versions,
        date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
    )


def claims_html(claims: pd.DataFrame) -> str:
    """``claims.csv`` (:func:`modal.thesis.claims.evaluate_claims`) as an HTML table."""
    shown = claims.rename(columns={"claim": "Claim (quoted)", "section": "Section", "criterion": "Criterion",
                                   "holds": "Holds", "numbers": "Numbers"})
    return shown.to_html(index=False, border=0, classes="claims", na_rep="")


def searches_html(searches: pd.DataFrame) -> str:
    """``searches.csv`` (:func:`modal.thesis.search.search_summary`) as an HTML table."""
    shown = searches[["search", "question", "table", "n_settings", "default", "default_verdict", "default_fit",
                      "best", "best_interpretation", "best_verdict", "best_fit", "explains"]]
    shown = shown.assign(explains=shown["explains"].map({True: "yes", False: "no"}).fillna(shown["explains"]))
    shown = shown.rename(columns={
        "search": "Search", "question": "Question", "table": "Table", "n_settings": "Settings",
        "default": "Config's setting", "default_verdict": "Its verdict", "default_fit": "Its fit",
        "best": "Best setting", "best_interpretation": "Signals", "best_verdict": "Best verdict",
        "best_fit": "Best fit", "explains": "Explains"})
    return shown.to_html(index=False, border=0, classes="searches", na_rep="")


def summary_frame(summary: pd.DataFrame) -> pd.DataFrame:
    """``summary.csv`` as a reader sees it: counts as integers, the largest
    deviation in percent (three significant digits), headings in words."""
    shown = summary[[c for c in SUMMARY_COLUMNS if c in summary]].copy()
    shown["n_within_noise"] = shown["n_within_noise"].map(lambda v: "" if pd.isna(v) else str(int(v)))
    shown["max_abs_rel_dev"] = shown["max_abs_rel_dev"].map(lambda v: "" if pd.isna(v) else f"{100 * v:.3g} %")
    return shown.fillna("").rename(columns=SUMMARY_COLUMNS)


def summary_html(summary: pd.DataFrame) -> str:
    return summary_frame(summary).to_html(index=False, border=0, classes="summary", na_rep="")


#: Words for the method and column codes of the thesis's layout.
HEADINGS = {"tcm": "TCM", "era": "ERA", "cera": "CERA", "actual": "Exact", "est": "Est. (peak picking)",
            "true": "True frequency", "pct_change_from_10hz": "% change from 10 Hz"}


def human_heading(label: str) -> tuple[str, str]:
    """A column of :func:`~modal.thesis.tables.thesis_layout` as a two-level
    heading: ``"era n=3 (named)"`` -> ``("ERA, n = 3", "ours, named")``,
    ``"tcm (thesis)"`` -> ``("TCM", "thesis")``."""
    name, _, source = label.rpartition(" (")
    source = source.rstrip(")")
    words = [HEADINGS.get(w, w.replace("=", " = ")) for w in name.split(" ")]
    group = words[0] + (", " + " ".join(words[1:]) if len(words) > 1 else "")
    if source not in ("thesis", "exact", "ours", "model"):
        source = f"ours, {source}"
    return group, source


def layout_html(table: pd.DataFrame) -> str:
    """A tidy table (``table_NN.csv``) in the thesis's layout, as HTML, with
    two-level headings in words (:func:`human_heading`)."""
    layout = thesis_layout(table)
    layout.columns = pd.MultiIndex.from_tuples([human_heading(c) for c in layout.columns])
    layout.index.name = "mode r"
    return layout.to_html(border=0, na_rep="")


def png_data_uri(path) -> str:
    return "data:image/png;base64," + base64.b64encode(Path(path).read_bytes()).decode("ascii")


def render_report(template: Path, summary: pd.DataFrame, definitions: Sequence[str],
                  tables: Mapping[int, dict], figures: Mapping[int, dict], extras: Sequence[dict],
                  provenance: Mapping[str, str], claims: pd.DataFrame | None = None,
                  searches: pd.DataFrame | None = None) -> str:
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
        Results beyond the thesis: ``{"heading", "caption", "png"}`` and
        optionally ``"frame"``, a table shown under the figure (a measured
        record's modes).
    provenance : mapping
        What the page came from (config files), shown at its foot.
    claims : DataFrame, optional
        ``results/tables/claims.csv``: the thesis's findings as checks, shown
        in their own section with their count.
    searches : DataFrame, optional
        ``results/tables/searches.csv``: the searches of unstated settings,
        shown in their own section.
    """
    from .claims import claims_headline
    from .report import headline

    import jinja2

    template = Path(template)
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(template.parent), autoescape=True,
                             undefined=jinja2.StrictUndefined, keep_trailing_newline=True)
    markup = jinja2.utils.markupsafe.Markup
    return env.get_template(template.name).render(
        summary=markup(summary_html(summary)),
        headline=headline(summary),
        claims=markup(claims_html(claims)) if claims is not None else None,
        claims_headline=claims_headline(claims) if claims is not None else "",
        searches=markup(searches_html(searches)) if searches is not None and len(searches) else None,
        definitions=definitions,
        tables=[dict(number=n, title=t["title"], notes=t.get("notes", []),
                     html=markup(layout_html(t["frame"])) if t["frame"] is not None else None)
                for n, t in sorted(tables.items())],
        figures=[dict(number=n, caption=f["caption"], src=png_data_uri(f["png"]) if f["png"] else None)
                 for n, f in sorted(figures.items())],
        extras=[dict(e, src=png_data_uri(e["png"]),
                     table=markup(e["frame"].to_html(index=False, border=0, classes="modes", na_rep=""))
                     if e.get("frame") is not None else None) for e in extras],
        provenance=provenance,
    )
