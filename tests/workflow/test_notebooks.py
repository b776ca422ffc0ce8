"""The report notebooks: hygiene of the committed notebooks, then the executed
notebooks and results/report.html of the workflow run on a small config
(conftest.small_workflow), and a failing notebook keeping its traceback."""

import ast
import base64
import json
import re
import sys

import nbformat
import papermill as pm
import pytest

from workflow_run import ROOT, SMALL_CONFIG_FILE, run_snakemake

from tests.browser import assert_readable, rendered

NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
NAMES = ["00_summary", "01_method_demo", "02_noise_study", "03_spillover", "04_cera", "05_grid"]
# the figures each notebook shows (those that exist in the run)
FIGURES = {
    "01_method_demo": [f"figure_{n:02d}.png" for n in range(1, 9)],
    "02_noise_study": [f"figure_{n:02d}.png" for n in (9, 10, 11)],
    "04_cera": ["cera_sensitivity.png"],
    "05_grid": [f"figure_{n:02d}.png" for n in range(12, 22)],
}
BEAM_FIGURES = {"01_method_demo", "02_noise_study", "04_cera"}  # must all exist after the beam stage
# figures the notebooks draw themselves: 00 the deviation per table, 01 the live case's shapes,
# 02 the per-seed distributions of Tables 3 and 4, 03 frequency against n
DRAWN = {"00_summary": 1, "01_method_demo": 1, "02_noise_study": 2, "03_spillover": 1}
# parameters that are not paths: the live case of 01 (ζ, η, Hankel size, seeds, the beam and the
# signals from config) and the noisy tables of 02
CASE_PARAMETERS = {"zeta", "eta", "rows", "cols", "n_seeds", "compare_with", "beam", "interpretations",
                   "noisy_cases", "claims_interpretation", "claims_config"}


def code_cells(nb):
    return [c for c in nb.cells if c.cell_type == "code"]


def outputs(nb):
    return [o for c in code_cells(nb) for o in c.outputs]


def test_every_chapter_has_a_notebook_and_a_rule():
    assert [p.stem for p in NOTEBOOKS] == NAMES
    rules = (ROOT / "workflow/rules/common.smk").read_text()
    listed = re.search(r"NOTEBOOKS = \[(.*?)\]", rules, flags=re.S).group(1)
    assert re.findall(r'"([^"]+)"', listed) == NAMES


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_committed_notebook_hygiene(path):
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    assert json.loads(path.read_text())["nbformat"] == 4
    assert nb.metadata["kernelspec"]["name"] == "python3"
    assert nb.metadata["language_info"]["name"] == "python"
    for cell in code_cells(nb):
        assert cell.outputs == [], cell.source[:60]
        assert cell.execution_count is None, cell.source[:60]
    tagged = [c for c in nb.cells if "parameters" in c.metadata.get("tags", [])]
    assert len(tagged) == 1 and tagged[0].cell_type == "code"
    # plain assignments of relative paths (and numbers), so papermill can override them
    tree = ast.parse(tagged[0].source)
    assert tree.body and all(isinstance(s, ast.Assign) for s in tree.body)
    for statement in tree.body:
        ast.literal_eval(statement.value)
    params = pm.inspect_notebook(str(path))
    assert params and all(name.endswith(("_dir", "_file", "_numbers")) or name in CASE_PARAMETERS
                          for name in params)
    # no chdir, no helper copied into the notebook: helpers come from the package
    assert "chdir" not in path.read_text() and "def " not in "".join(c.source for c in code_cells(nb))
    assert all(not p["default"].strip("'\"").startswith("/") for name, p in params.items() if name.endswith("_file"))
    assert "MPLBACKEND" not in path.read_text()


def test_no_mplbackend_in_the_report_rules():
    for path in [*sorted((ROOT / "workflow/rules").glob("*.smk")), *sorted((ROOT / "workflow/scripts").glob("*.py"))]:
        assert "MPLBACKEND" not in path.read_text(), path


@pytest.mark.parametrize("name", NAMES)
def test_executed_notebook(small_workflow, name):
    nb = nbformat.read(small_workflow / f"results/notebooks/{name}.ipynb", as_version=4)
    outs = outputs(nb)
    errors = [f"{o.ename}: {o.evalue}" for o in outs if o.output_type == "error"]
    assert not errors
    stderr = [o.text for o in outs if o.output_type == "stream" and o.name == "stderr"]
    assert not stderr, stderr
    assert all(c.execution_count is not None for c in code_cells(nb))
    assert any("injected-parameters" in c.metadata.get("tags", []) for c in nb.cells)
    shown = [f for f in FIGURES.get(name, []) if (small_workflow / "results/figures" / f).exists()]
    if name in BEAM_FIGURES:
        assert len(shown) == len(FIGURES[name])
    pngs = [o for o in outs if "image/png" in o.get("data", {})]
    assert len(pngs) == len(shown) + DRAWN.get(name, 0)
    for o in pngs:
        assert base64.b64decode(o.data["image/png"])[:4] == b"\x89PNG"


def html_outputs(nb):
    return "\n".join(o.data["text/html"] for o in outputs(nb) if "text/html" in o.get("data", {}))


def markdown_outputs(nb):
    return "\n".join(o.data["text/markdown"] for o in outputs(nb) if "text/markdown" in o.get("data", {}))


def test_chapter_notebooks_show_their_tables(small_workflow):
    for name, numbers in {"01_method_demo": (1, 2, 3, 4), "03_spillover": (5, 6), "04_cera": (7, 8, 9)}.items():
        nb = nbformat.read(small_workflow / f"results/notebooks/{name}.ipynb", as_version=4)
        text = markdown_outputs(nb)
        for n in numbers:
            assert f"### Table {n}. " in text, (name, n)
            assert re.search(rf"<td [^>]*>{n}</td>", html_outputs(nb)), (name, n)  # its verdict row
    text = markdown_outputs(nbformat.read(small_workflow / "results/notebooks/03_spillover.ipynb", as_version=4))
    assert "inclusion principle (Eq. 20)" in text


def test_grid_notebook_names_what_is_missing(small_workflow):
    text = markdown_outputs(nbformat.read(small_workflow / "results/notebooks/05_grid.ipynb", as_version=4))
    for n in range(10, 16):
        if not (small_workflow / f"results/tables/table_{n:02d}.md").exists():
            assert f"Table {n} is missing" in text
    for n in range(12, 22):
        if not (small_workflow / f"results/figures/figure_{n:02d}.png").exists():
            assert f"figure_{n:02d}.png" in text and f"Figure {n}. " in text


def test_summary_notebook_ran_on_this_venv_kernel(small_workflow):
    nb = nbformat.read(small_workflow / "results/notebooks/00_summary.ipynb", as_version=4)
    streams = "".join(o.text for o in outputs(nb) if o.output_type == "stream")
    assert f"sys.prefix: {sys.prefix}\n" in streams
    text = html_outputs(nb)
    assert re.search(r"<td [^>]*>1</td>", text) and "reproduced to the printed digits" in text


def test_report_html(small_workflow):
    html = (small_workflow / "results/report.html").read_text()
    assert html.startswith("<!DOCTYPE html>")
    assert html.index('id="summary"') < html.index('id="tables"') < html.index('id="figures"')
    for n in range(1, 16):
        assert f"<h3>Table {n}. " in html
        assert re.search(rf"<tr>\s*<td>{n}</td>\s*<td>[^<]*</td>", html), n  # its summary row
    # Tables 1 and 2 reproduce to the printed digits even with 3 seeds (noise-free cases)
    for n in (1, 2):
        row = re.search(rf"<tr>\s*<td>{n}</td>.*?</tr>", html, flags=re.S).group(0)
        assert "reproduced to the printed digits" in row
    for n in range(1, 12):
        figure = re.search(rf'<figure id="figure-{n}"><img alt="[^"]*" src="data:image/png;base64,([A-Za-z0-9+/=]+)">'
                           rf"<figcaption>Figure {n}\. ([^<]+)</figcaption>", html)
        assert figure, n
        assert base64.b64decode(figure.group(1))[:4] == b"\x89PNG"
    assert "Figure 9. Effect of noise (1st natural frequency)" in html
    assert "Figure 1. Identified mode shapes of a simply supported beam using the TCM" in html
    assert not re.search(r'(src|href)="(https?:|file:)', html)  # self-contained


def test_report_reads_in_a_browser(small_workflow):
    """results/report.html opened in Chromium in a laptop's window: every
    figure the run drew (results/figures/*.png, and the pictures of the
    measured records: Palisaden's diagram, the roving plate's shapes)
    decodes and shows, Figures 1-21 once each, nothing is fetched from
    elsewhere, no sideways scrolling; the summary table has a row per thesis
    table (15)."""
    results = small_workflow / "results"
    measured = [results / "measured/palisaden/stabilisation.png", results / "measured/roving_plate/modes.png"]
    assert all(p.is_file() for p in measured)
    seen = rendered(results / "report.html")
    assert_readable(seen, images=len(list((results / "figures").glob("*.png"))) + len(measured))
    alts = [image["alt"] for image in seen["images"]]
    assert [sum(a.startswith(f"Figure {n}. ") for a in alts) for n in range(1, 22)] == [1] * 21
    assert seen["tables"][0]["rows"] == 1 + 15


def test_failing_notebook_keeps_its_traceback(small_workflow):
    """A notebook that raises: the job fails, no output, the log notebook has the traceback; fixed, it reruns."""
    path = small_workflow / "notebooks/03_spillover.ipynb"
    out = small_workflow / "results/notebooks/03_spillover.ipynb"
    log = small_workflow / "results/logs/notebook_03_spillover.ipynb"
    good = path.read_bytes()
    try:
        nb = nbformat.reads(good.decode(), as_version=4)
        nb.cells.append(nbformat.v4.new_code_cell("raise RuntimeError('deliberate failure')"))
        nbformat.write(nb, path)
        # the target goes before --configfile, which takes several values
        proc = run_snakemake(small_workflow, str(out.relative_to(small_workflow)), "--configfile", SMALL_CONFIG_FILE,
                             check=False)
        assert proc.returncode != 0
        assert "Error in rule notebook" in proc.stdout + proc.stderr
        assert not out.exists()
        failed = nbformat.read(log, as_version=4)
        errors = [o for o in outputs(failed) if o.output_type == "error"]
        assert errors and errors[0].evalue == "deliberate failure" and errors[0].traceback
    finally:
        path.write_bytes(good)
    run_snakemake(small_workflow, str(out.relative_to(small_workflow)), "--configfile", SMALL_CONFIG_FILE)
    assert not [o for o in outputs(nbformat.read(out, as_version=4)) if o.output_type == "error"]


def test_method_demo_recomputes_live(small_workflow, tmp_path):
    """01's live section runs the engine with the parameters of its tagged cell:
    ζ = .05, η = 0 reproduces Table 2's printed digits (ERA and TCM, signals as named)."""
    out = tmp_path / "live.ipynb"
    pm.execute_notebook(str(ROOT / "notebooks/01_method_demo.ipynb"), str(out), cwd=str(small_workflow),
                        kernel_name="python3", progress_bar=False,
                        parameters=dict(tables_dir="results/tables", figures_dir="results/figures",
                                        summary_file="results/tables/summary.csv",
                                        captions_file="workflow/report/captions.yaml",
                                        published_file="config/thesis_tables.csv",
                                        zeta=0.05, eta=0.0, n_seeds=1, compare_with=2))
    nb = nbformat.read(out, as_version=4)
    live = next(c for c in code_cells(nb) if "run_study" in c.source)
    table = "".join(o.data["text/html"] for o in live.outputs if "text/html" in o.get("data", {}))
    assert "ζ = 0.05, η = 0 %" in markdown_outputs(nb)
    # Table 2 as printed: TCM 2.1711, 8.6614, 19.407; ERA 2.1623, 8.6493, 19.461 (named reproduces them)
    for printed in ("2.1711", "8.6614", "19.407", "2.1623", "8.6493", "19.461"):
        assert table.count(f"<td>{printed}</td>") >= 2, printed  # the thesis's cell and ours
