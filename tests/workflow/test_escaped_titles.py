"""Table titles come from a config: the notebooks and the HTML report show
them as text, never as HTML (modal.thesis.display, modal.thesis.html)."""

import pandas as pd

import modal.thesis.display as display
from modal.thesis.html import render_report
from workflow_run import ROOT

TITLE = 'Modes <img src=x onerror="alert(1)"> & <b>bold</b>'


def _shown(monkeypatch):
    shown = []
    monkeypatch.setattr(display, "_display", lambda *objects: shown.extend(objects))
    return shown


def _html(obj):
    return obj._repr_html_() if hasattr(obj, "_repr_html_") and obj._repr_html_() else getattr(obj, "data", str(obj))


def test_notebook_table_title_escaped(tmp_path, monkeypatch):
    (tmp_path / "table_01.md").write_text(f"### {TITLE}\n\n| a |\n|---|\n| `x<y` |\n")
    (tmp_path / "table_01.csv").write_text("mode,method,published,reproduced,rel_dev\n")
    shown = _shown(monkeypatch)
    display.Results(tmp_path).table(1)
    text = shown[0].data
    assert "<img" not in text and "<b>" not in text and "&lt;img" in text and "&amp;" in text, text
    assert "`x<y`" in text  # a code span shows its text literally already


def test_notebook_verdicts_title_escaped(tmp_path, monkeypatch):
    summary = tmp_path / "summary.csv"
    pd.DataFrame([dict(table=1, title=TITLE, interpretation="named", n_match=1, n_compared=1, n_within_noise=1,
                       max_abs_rel_dev=0.01, worst="mode 1", verdict="reproduced", why="x")]).to_csv(summary,
                                                                                                  index=False)
    shown = _shown(monkeypatch)
    display.Results(tmp_path, summary_file=summary).verdicts()
    html = shown[-1].data  # after the headline, the table
    assert "<table" in html and "<img" not in html and "&lt;img" in html, html


def test_report_title_escaped():
    summary = pd.DataFrame([dict(table=1, title=TITLE, n_published=1, n_compared=1, interpretation="named",
                                 n_match=1, n_within_noise=1, max_abs_rel_dev=0.01, worst="", verdict="reproduced",
                                 why="")])
    page = render_report(ROOT / "workflow/report/report.html.j2", summary, [], {1: dict(title=TITLE, frame=None)},
                         {}, [], dict(commit="c", dirty=False, changed=[], configfiles=[], config_diff=[],
                                      versions={}, date="d"))
    assert "<img" not in page and "&lt;img" in page
