"""The Snakemake workflow end to end on a small config, its config checks,
determinism, failure hygiene and lint."""

import copy
import inspect
import os
import re
import subprocess
import sys

import pandas as pd
import pytest
import yaml
from snakemake.utils import validate

import modal
import modal.campaign
import modal.thesis.config

from workflow_run import DELETE, ROOT, SMALL_CONFIG_FILE, run_snakemake as snakemake, set_key

SMALL = yaml.safe_load((ROOT / SMALL_CONFIG_FILE).read_text())

SCHEMA = str(ROOT / "workflow/schemas/config.schema.yaml")


def base_config():
    return yaml.safe_load((ROOT / "config/config.yaml").read_text())


@pytest.fixture(scope="module")
def workdir(small_workflow):
    """A copy of the workflow in a temporary directory with a small config
    (tests/workflow/conftest.small_workflow, shared with the notebook tests)."""
    return small_workflow


def test_config_is_valid():
    config = base_config()
    validate(config, SCHEMA)
    modal.thesis.config.check(config)


# (dotted key, new value, text the error must contain)
BAD_SCHEMA = [
    ("studies.demo.cases.c3.noise", -0.05, "noise"),
    ("studies.demo.methods.ssi", {}, "ssi"),
    ("beams.beam5.n_samples", "many", "n_samples"),
    ("seeds", DELETE, "seeds"),
    ("beams.beam5.length", -5.0, "length"),
    ("studies.demo.methods.era.rows", 2.5, "rows"),
    ("studies.demo.cases.c2.damping", 1.5, "damping"),
    ("interpretations.named.era", "jerk", "jerk"),
    ("studies.demo.methods.era.colums", 100, "colums"),
    ("measured.palisaden.excitation", "forced", "forced"),
    ("measured.palisaden.max_order", 61, "61"),
    ("studies.cera.methods.cera.eigenproblem", "literal", "literal"),
    ("interpretations.guideline.studies.cera.beam.length", 7.0, "length"),
]
BAD_CHECK = [
    ("studies.demo.methods.era.cols", 4000, "studies.demo.methods.era: rows + cols"),
    ("studies.cera.cols_sweep", [300, 5000], "studies.cera.methods.cera: rows + cols"),
    ("studies.spillover.n_identified", [3, 7], "studies.spillover.methods.tcm: n = 7 modes exceeds the 6 sensors"),
    ("studies.demo.methods.era.n_modes", 80, "studies.demo.methods.era: 2 n_modes = 160 exceeds"),
    ("studies.demo.beam", "beam7", "studies.demo.beam = 'beam7'"),
    ("tables.3.case", "c9", "tables.3.case = 'c9'"),
    ("beams.beam5.sensors", [1, 2, 3, 4, 5, 7], "beams.beam5.sensors[5] = 7 must be < stations = 7"),
    ("interpretations.guideline.studies.cera.methods.cera.cols", 950,
     "studies.cera as interpretations.guideline reads it.methods.cera: rows + cols = 951"),
    ("interpretations.guideline.studies.demo", {"cols_sweep": []},
     "interpretations.guideline.studies.demo: not a study that lists 'guideline'"),
    ("studies.cera.methods.era.eigenproblem", "as_printed", "singular_values and eigenproblem are CERA settings"),
    ("studies.cera.methods.cera.singular_values", 7, "studies.cera.methods.cera.singular_values = 7"),
    ("beams.beam10.period_mode", 7, "beams.beam10.period_mode = 7 exceeds its n_modes = 6"),
]


BAD_GRID = [
    ("grid.cases.lp10", 150.0, "grid.cases.lp10 = 150.0 Hz must be below the Nyquist frequency 100.0 Hz"),
    ("grid.runs.tcm.n_identified", [2, 7], "grid.runs.tcm: n = 7 modes needs 7 sensors, but 6 accelerometers"),
    ("grid.runs.era_m3.sets", 40, "grid.runs.era_m3: rows + cols = 136 exceeds the 102 samples"),
    ("grid.test.sensors", [0, 3, 25], "grid.test.sensors[2] = 25 is not a strip crossing"),
    ("grid.tables.13.runs.era m=3", "era_m9", "grid.tables.13.runs.era m=3 = 'era_m9'"),
    ("tables.10", {"study": "demo", "case": "c1", "title": "x"}, "tables.10: table 10 is a grid table"),
]


@pytest.mark.parametrize("path, value, message", BAD_SCHEMA)
def test_schema_rejects(path, value, message):
    config = set_key(copy.deepcopy(base_config()), path, value)
    with pytest.raises(Exception, match=message):
        validate(config, SCHEMA)


@pytest.mark.parametrize("path, value, message", BAD_CHECK + BAD_GRID)
def test_semantic_check_rejects(path, value, message):
    config = set_key(copy.deepcopy(base_config()), path, value)
    validate(config, SCHEMA)
    with pytest.raises(ValueError, match=re.escape(message)):
        modal.thesis.config.check(config)


def test_invalid_config_stops_before_any_job(workdir, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({"studies": {"demo": {"cases": {"c3": {"damping": 0.0, "noise": -0.05}}}}}))
    proc = snakemake(workdir, "--configfile", str(bad), "--forceall", "-n", check=False)
    assert proc.returncode != 0
    assert "noise" in proc.stdout + proc.stderr
    bad.write_text(yaml.safe_dump({"studies": {"spillover": {"n_identified": [3, 9]}}}))
    proc = snakemake(workdir, "--configfile", str(bad), "--forceall", "-n", check=False)
    assert proc.returncode != 0
    assert "n = 9 modes exceeds the 6 sensors" in proc.stdout + proc.stderr


def test_end_to_end_outputs(workdir):
    for n in range(1, 10):
        for ext in ("csv", "md"):
            assert (workdir / f"results/tables/table_{n:02d}.{ext}").stat().st_size > 0
    for n in range(1, 12):
        assert (workdir / f"results/figures/figure_{n:02d}.png").read_bytes()[:4] == b"\x89PNG"
    assert (workdir / "results/figures/cera_sensitivity.png").exists()


def test_end_to_end_tables_1_and_2_reproduce_printed_digits(workdir):
    for n in (1, 2):
        table = pd.read_csv(workdir / f"results/tables/table_{n:02d}.csv", dtype={"printed": str})
        named = table[(table["interpretation"] == "named") & table["method"].isin(["tcm", "era", "actual"])]
        assert len(named) == 9
        assert named["printed_match"].all(), named
        for col in ("mode", "method", "published", "reproduced", "rel_dev"):
            assert col in table


def test_end_to_end_noisy_table_has_seed_statistics(workdir):
    table = pd.read_csv(workdir / "results/tables/table_04.csv")
    tcm = table[(table["method"] == "tcm") & (table["interpretation"] == "lower")]
    assert (tcm["n_seeds"] == 3).all()
    assert (tcm["std"] > 0).all() and tcm["z"].notna().all()
    # the lower interpretation's TCM mode 1 is 2.1611 +- 0.001: within 0.2 % of the published 2.1655
    assert abs(tcm.loc[tcm["mode"] == 1, "rel_dev"].iloc[0]) < 2e-3


def test_spillover_inclusion_note(workdir):
    md = (workdir / "results/tables/table_05.md").read_text()
    assert "inclusion principle (Eq. 20) over n = 3..6 holds for the reproduced" in md


def test_nothing_to_do_when_up_to_date(workdir):
    proc = snakemake(workdir, "--configfile", SMALL_CONFIG_FILE, "-n")
    assert "Nothing to be done" in proc.stdout + proc.stderr


def test_config_edit_reruns_only_affected_jobs(workdir, tmp_path):
    edit = tmp_path / "edit.yaml"
    edit.write_text(yaml.safe_dump({**SMALL, "studies": {**SMALL["studies"],
                                    "demo": {"cases": {"c4": {"damping": 0.01, "noise": 0.04}}}},
                                    "tables": {4: {"title": "Identified frequencies with zeta = .01, eta = 4 %"}}},
                                   sort_keys=False))  # snakemake compares params in key order
    proc = snakemake(workdir, "--configfile", str(edit), "-n", "--rerun-triggers", "params", "input")
    out = proc.stdout + proc.stderr
    jobs = [line.split()[0] for line in out.splitlines() if line.strip() and line.split()[0] in
            ("identify", "table", "shape_figures", "noise_figures", "cera_sensitivity")]
    assert "noise_figures" not in jobs and "cera_sensitivity" not in jobs
    assert "identify" in jobs and "table" in jobs


def test_failed_job_leaves_no_table_and_rerun_recovers(workdir):
    ident = workdir / "results/identified/demo_named.csv"
    good = ident.read_bytes()
    table = workdir / "results/tables/table_01.csv"
    try:
        ident.write_text("not,a\nvalid,identified,table\n")
        table.unlink()
        # the target goes before --configfile, which takes several values
        proc = snakemake(workdir, "results/tables/table_01.csv", "--configfile", SMALL_CONFIG_FILE, check=False)
        assert proc.returncode != 0
        assert "Error in rule table" in proc.stdout + proc.stderr
        assert not table.exists()
    finally:
        ident.write_bytes(good)
    snakemake(workdir, "--configfile", SMALL_CONFIG_FILE, "--rerun-incomplete", "results/tables/table_01.csv")
    assert table.exists()


def _lints(*args, cwd=ROOT):
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--lint", *args], cwd=cwd, capture_output=True,
                          text=True)
    return [line.strip() for line in (proc.stdout + proc.stderr).splitlines() if line.strip().startswith("* ")]


@pytest.mark.slow
def test_lint_clean_apart_from_conda():
    lints = _lints()
    assert lints, "expected at least the conda lint"
    assert all("conda environment or container" in lint for lint in lints), lints


def test_campaign_workflow_lint_clean_apart_from_conda(tmp_path):
    """The campaign's workflow (modal/campaign/Snakefile) meets the same bar,
    on a campaign of one record (the index is read, the record not; a .npy
    record needs identify.fs, checked before any job)."""
    (tmp_path / "index.csv").write_text("path,time\na.npy,2025-01-01\n")
    (tmp_path / "campaign.yaml").write_text("records: {index: index.csv}\nidentify: {excitation: ambient, fs: 50}\n")
    lints = _lints("--snakefile", str(modal.campaign.SNAKEFILE), "--config",
                   f"campaign={tmp_path / 'campaign.yaml'}", cwd=tmp_path)
    assert lints, "expected at least the conda lint"
    assert all("conda environment or container" in lint for lint in lints), lints


@pytest.mark.parametrize("path, value", [("grid.source", "simulated"), ("grid.test.noise", -0.1),
                                         ("grid.cases.lp10", -5.0), ("grid.runs.tcm.method", "ssi")])
def test_grid_schema_rejects(path, value):
    config = set_key(copy.deepcopy(base_config()), path, value)
    with pytest.raises(Exception, match=path.split(".")[-1]):
        validate(config, SCHEMA)


def test_grid_end_to_end(workdir):
    for n in range(10, 16):
        table = pd.read_csv(workdir / f"results/tables/table_{n:02d}.csv", dtype={"printed": str})
        assert {"published", "reproduced", "actual", "rel_dev"} <= set(table)
        assert (table["method"] == "est").any()
        md = (workdir / f"results/tables/table_{n:02d}.md").read_text()
        assert "true (model)" in md
    for n in range(12, 22):
        assert (workdir / f"results/figures/figure_{n:02d}.png").read_bytes()[:4] == b"\x89PNG"
    assert "within 5 %" in (workdir / "results/tables/table_10.md").read_text()


def planned_rules(workdir, *args):
    """Rule names of the jobs ``snakemake -n`` plans (default rerun triggers)."""
    proc = snakemake(workdir, "--configfile", SMALL_CONFIG_FILE, "-n", *args)
    jobs = re.findall(r"^rule (\w+):", proc.stdout + proc.stderr, flags=re.M)
    return set(jobs) - {"all"}


#: The ERA module, wherever the engine's layout puts it (modal/era.py, modal/identification/_era.py).
ERA_MODULE = os.path.relpath(inspect.getsourcefile(inspect.unwrap(modal.era)), ROOT)


@pytest.mark.parametrize("edited, expected", [
    ("modal/thesis/plots.py", {"shape_figures", "noise_figures", "cera_sensitivity", "grid_figures", "notebook",
                               "report_html"}),
    ("workflow/report/report.html.j2", {"report_html"}),
    (ERA_MODULE, {"identify", "grid_identify", "measured_identify"}),
])
def test_code_edit_reruns_only_what_depends_on_it(workdir, edited, expected):
    """A cosmetic edit of the plotting module or a template reruns no
    identification; an edit of the ERA module reruns the identifications (and,
    by their outputs, what reads them)."""
    path = workdir / edited
    text, stat = path.read_bytes(), path.stat()
    try:
        path.write_bytes(text + b"\n# edited\n")
        planned = planned_rules(workdir)
    finally:
        path.write_bytes(text)
        os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    if edited == ERA_MODULE:
        assert expected <= planned
    else:
        assert planned == expected, planned
        assert not planned & {"identify", "grid_identify", "measured_identify", "table", "grid_table", "summary"}


def test_rules_declare_relative_code_inputs(workdir):
    proc = snakemake(workdir, "--configfile", SMALL_CONFIG_FILE, "--forceall", "-n", "--printshellcmds",
                     "results/identified/demo_named.csv")
    out = proc.stdout + proc.stderr
    assert ERA_MODULE in out and str(workdir) not in out.split("Building DAG")[-1]


def test_snakemake_files_are_snakefmt_formatted():
    files = [str(ROOT / "Snakefile"), *map(str, sorted((ROOT / "workflow/rules").glob("*.smk"))),
             str(modal.campaign.SNAKEFILE)]
    proc = subprocess.run([sys.executable, "-m", "snakefmt", "--check", *files], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_script_runs_by_hand(workdir):
    """A job's script runs by hand (in a debugger, IPython) through Snakemake's
    public route: ``--skip-script-cleanup`` keeps the script it hands the job,
    with the job's ``snakemake`` object, and plain ``python`` reruns it."""
    table = workdir / "results/tables/table_01.csv"
    before = table.read_bytes()
    proc = snakemake(workdir, "--configfile", SMALL_CONFIG_FILE, "--forcerun", "table", "--skip-script-cleanup",
                     "results/tables/table_01.csv")
    kept = re.search(r"Not cleaning up (\S+\.table\.py)", proc.stdout + proc.stderr).group(1)
    table.unlink()
    subprocess.run([sys.executable, kept], cwd=workdir, check=True, capture_output=True, text=True)
    assert table.read_bytes() == before


def test_measured_record_identified(workdir):
    """config "measured": the Palisaden fixture's modes and diagram."""
    modes = pd.read_csv(workdir / "results/measured/palisaden/modes.csv")
    for published in (1.88, 2.42, 2.68):
        assert (modes["freq_hz"] - published).abs().min() / published < 0.005
    assert (workdir / "results/measured/palisaden/stabilisation.png").read_bytes()[:4] == b"\x89PNG"



def test_roving_test_merged(workdir):
    """config "measured" with setups: the simulated plate's six setups give
    its five modes (within 0.5 %) with shapes at its 20 nodes, drawn."""
    modes = pd.read_csv(workdir / "results/measured/roving_plate/modes.csv")
    assert modes["freq_hz"].to_numpy() == pytest.approx([5.014, 9.642, 15.427, 17.355, 20.055], rel=5e-3)
    shapes = pd.read_csv(workdir / "results/measured/roving_plate/shapes.csv")
    assert len(shapes) == 5 * 20 and shapes["z"].notna().all()
    assert (workdir / "results/measured/roving_plate/modes.png").read_bytes()[:4] == b"\x89PNG"
    assert "Roving test &#39;roving_plate&#39;" in (workdir / "results/report.html").read_text(encoding="utf-8")
