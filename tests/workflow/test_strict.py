"""Issue 13: no silent wrong answer from a config, a record or an interrupted
run. Bad configs and records are refused before any job with the key named;
intermediate files are checked by their readers; an interrupted run resumes
with the main command alone."""

import copy
import os
import re
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest
import yaml

import modal.thesis.config as mc
from modal.thesis.intermediates import read_grid_identified, read_identified, read_interpretations, read_selection
from workflow_run import (DELETE, ROOT, SMALL_CONFIG_FILE, base_config, regenerate, regenerate_project, run_snakemake,
                          set_key)

SCHEMA = ROOT / "workflow/schemas/config.schema.yaml"


def refused(config, *fragments):
    """``check_workflow_config`` on ``config`` (no files) refuses with every fragment in the message."""
    with pytest.raises(ValueError) as err:
        os.chdir(ROOT)
        mc.normalise_numbers(config)
        mc.validate(config, SCHEMA)
        mc.check(config)
    for fragment in fragments:
        assert fragment in str(err.value), str(err.value)


# (dotted key, bad value, fragments the refusal must contain)
BAD = [
    # bounds, with the likely intent
    ("studies.demo.cases.c3.noise", 5, ["studies.demo.cases.c3.noise = 5", "5 % is 0.05"]),
    ("studies.demo.cases.c3.noise", 1.5, ["studies.demo.cases.c3.noise"]),
    ("studies.demo.cases.c3.noise", -0.05, ["studies.demo.cases.c3.noise"]),
    ("studies.noise.noise_sweep.noise", [0.03, 3], ["studies.noise.noise_sweep.noise.1", "3 % is 0.03"]),
    ("studies.demo.cases.c2.damping", 5, ["studies.demo.cases.c2.damping", "5 % is 0.05"]),
    ("studies.demo.cases.c2.damping", 1.0, ["studies.demo.cases.c2.damping"]),
    ("studies.noise.noise_sweep.damping", -0.01, ["studies.noise.noise_sweep.damping"]),
    ("grid.test.noise", 2, ["grid.test.noise", "2 % is 0.02"]),
    ("grid.test.damping", 1.2, ["grid.test.damping"]),
    # integers must be integers
    ("seeds.count", 3.0, ["seeds.count = 3.0", "write an integer: 3"]),
    ("seeds.first", 0.5, ["seeds.first"]),
    ("studies.demo.methods.era.n_modes", 6.0, ["studies.demo.methods.era.n_modes = 6.0"]),
    ("studies.demo.methods.era.rows", 24.0, ["studies.demo.methods.era.rows = 24.0"]),
    ("studies.demo.methods.era.cols", True, ["studies.demo.methods.era.cols"]),
    ("beams.beam5.n_samples", 3594.0, ["beams.beam5.n_samples"]),
    ("beams.beam5.sensors", [1, 2, 3.0], ["beams.beam5.sensors.2"]),
    ("grid.test.n_samples", 4096.0, ["grid.test.n_samples"]),
    ("grid.runs.era.rows", 36.0, ["grid.runs.era.rows"]),
    ("grid.seeds.count", 2.0, ["grid.seeds.count"]),
    ("noise_figures.9", 1.0, ["noise_figures.9"]),
    # closed schema: typos are unknown keys
    ("grid.model.thicknes", 0.001, ["grid.model: unknown key(s) ['thicknes']"]),
    ("seeds.cout", 3, ["seeds: unknown key(s) ['cout']"]),
    ("studies.demo.methods.era.colums", 100, ["studies.demo.methods.era: unknown key(s) ['colums']"]),
    ("studies.demo.cases.c1.nosie", 0.1, ["studies.demo.cases.c1: unknown key(s) ['nosie']"]),
    ("grid.test.sensor", [0], ["grid.test: unknown key(s) ['sensor']"]),
    ("grid.measured.file", "x.npz", ["grid.measured: unknown key(s) ['file']"]),
    ("tables.1.titel", "x", ["tables.1: unknown key(s) ['titel']"]),
    ("extra_top_level", 1, ["unknown key(s) ['extra_top_level']"]),
    ("seeds", DELETE, ["'seeds' is a required property"]),
    ("published", "", ["published"]),
    # cross-checks
    ("published", "config/missing.csv", ["published = 'config/missing.csv': no such file"]),
    ("studies.noise.noise_sweep.noise", [0.03, 0.030000001],
     ["studies.noise.noise_sweep.noise[1] = 0.030000001 gives the case name 'eta_0.03'"]),
    ("studies.noise.noise_sweep.noise", [0.03, 0.03], ["studies.noise.noise_sweep.noise[1]"]),
    ("noise_figures.9", 7, ["noise_figures.9 = 7: the noise study's beam beam5 has 6 modes"]),
    ("grid.accelerometers", [0, 3, 11], ["grid.accelerometers[2] = 11", "0..10"]),
    ("tables.3.title", "Identified frequencies with zeta = 0, eta = 6 %",
     ["tables.3.title says 'eta = 6 %' but studies.demo.cases.c3.noise = 0.05"]),
    ("tables.2.title", "Identified frequencies with zeta = .02, eta = 0 %", ["tables.2.title says 'zeta = .02'"]),
    ("tables.3.case", "c9", ["tables.3.case = 'c9'"]),
    ("tables.01", {"study": "demo", "case": "c9"}, ["tables.1.case = 'c9'"]),
    ("shape_figures.1.method", "cera", ["shape_figures.1.method = 'cera'"]),
    ("grid.source", "measured", ["grid.measured.path is required"]),
    ("grid.tables.x", {"title": "t", "case": "raw", "runs": {}}, ["grid.tables: key 'x' is not a table or figure number"]),
    # the measured records list: opened and checked before any job
    ("measured.palisaden.path", "tests/data/missing.npy", ["measured.palisaden.path = 'tests/data/missing.npy': no such"]),
    ("measured.palisaden.channels", [0, 9], ["measured.palisaden.channels [9]: the record has channels 0 ... 5"]),
    ("measured.palisaden.refs", [1, 7], ["measured.palisaden.refs [7]: the record has channels 0 ... 5"]),
    ("measured.palisaden.excitation", "impact", ["measured.palisaden.excitation = 'impact'"]),
    ("measured.palisaden.max_order", 61, ["measured.palisaden.max_order = 61"]),
]


@pytest.mark.parametrize("path, value, fragments", BAD, ids=[f"{p}={v!r}"[:60] for p, v, _ in BAD])
def test_bad_config_is_refused_naming_the_key(path, value, fragments):
    refused(set_key(copy.deepcopy(base_config()), path, value), *fragments)


def test_schema_is_closed_everywhere():
    """Every object of the schema says what else it allows: nothing
    (``additionalProperties: false``) or a schema for user-named entries."""
    open_objects = []

    def walk(node, where):
        if isinstance(node, dict):
            if (node.get("type") == "object" or "properties" in node) and "additionalProperties" not in node:
                open_objects.append(where)
            if "properties" in node and node.get("additionalProperties") is not False:
                open_objects.append(where + " (fixed keys but additionalProperties not false)")
            for key, value in node.items():
                walk(value, f"{where}.{key}")
        elif isinstance(node, list):
            for i, value in enumerate(node):
                walk(value, f"{where}[{i}]")

    walk(yaml.safe_load(SCHEMA.read_text()), "schema")
    assert not open_objects, open_objects


def test_default_and_small_configs_pass():
    config = base_config()
    mc.check_workflow_config(config, [ROOT / "config/config.yaml", ROOT / SMALL_CONFIG_FILE], SCHEMA)


@pytest.mark.parametrize("text, key", [
    ("seeds: {first: 0, count: 3}\nseeds: {first: 0, count: 5}\n", "'seeds'"),
    ("studies:\n  demo:\n    cases:\n      c3: {damping: 0.0, noise: 0.05, noise: 0.5}\n", "'noise'"),
    ("tables:\n  3: {title: a}\n  3: {title: b}\n", "3"),
])
def test_duplicate_yaml_keys_are_refused(tmp_path, text, key):
    path = tmp_path / "dup.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"{path}: key {key} given twice"):
        mc.check_workflow_config(base_config(), [ROOT / "config/config.yaml", path], SCHEMA)


@pytest.mark.parametrize("key", [3, "3", "03"])
def test_table_keys_are_normalised(key):
    """An override keyed 3, "3" or "03" changes table 3 (and only it)."""
    config = base_config()
    config["tables"][key] = {**config["tables"].get(key, {}), "title": "Identified frequencies, eta = 5 %"}
    mc.normalise_numbers(config)
    assert config["tables"][3]["title"] == "Identified frequencies, eta = 5 %"
    assert config["tables"][3]["study"] == "demo" and sorted(config["tables"]) == list(range(1, 10))


# --- measured records: opened and checked before any job -----------------------
def measured_config(tmp_path, path, **measured):
    config = base_config()
    config["grid"]["source"] = "measured"
    config["grid"]["measured"] = {"path": str(path), "fs": None, "channels": None, **measured}
    config["grid"]["test"]["n_samples"] = 512
    return config


def _acc(n=512, ch=6):
    rng = np.random.default_rng(13)
    return rng.standard_normal((n, ch))


def test_good_measured_record_passes(tmp_path):
    np.savez(tmp_path / "rec.npz", acc=_acc(), fs=200.0)
    config = measured_config(tmp_path, tmp_path / "rec.npz")
    mc.normalise_numbers(config), mc.validate(config, SCHEMA), mc.check(config)


def _csv_with_time(path, acc, fs):
    t = np.arange(acc.shape[0]) / fs
    np.savetxt(path, np.column_stack([t, acc]), delimiter=",")


def test_time_column_with_fs_is_dropped_not_a_channel(tmp_path):
    # fs given with a time column: the time column is dropped (modal.io), so the
    # record has its 6 channels and passes; the sensors' count would be off otherwise
    _csv_with_time(tmp_path / "r.csv", _acc(), 200.0)
    config = measured_config(tmp_path, tmp_path / "r.csv", fs=200.0, channels=[0, 5])
    mc.normalise_numbers(config), mc.validate(config, SCHEMA), mc.check(config)
    refused(measured_config(tmp_path, tmp_path / "r.csv", fs=200.0, channels=[0, 6]),
            "grid.measured.channels[1] = 6: the record has 6 channels")


BAD_RECORDS = [
    ("npz dt=True", lambda p: np.savez(p / "r.npz", acc=_acc(), dt=True), "r.npz", {}, "dt"),
    ("transposed", lambda p: np.savez(p / "r.npz", acc=_acc().T, fs=200.0), "r.npz", {}, "transposed"),
    ("missing file", lambda p: None, "none.npz", {}, "grid.measured.path"),
    ("channel out of range", lambda p: np.savez(p / "r.npz", acc=_acc(), fs=200.0), "r.npz",
     {"channels": [0, 6]}, "grid.measured.channels[1] = 6"),
    ("fs differs", lambda p: np.savez(p / "r.npz", acc=_acc(), fs=100.0), "r.npz", {}, "grid.test.fs = 200.0"),
    ("n_samples differs", lambda p: np.savez(p / "r.npz", acc=_acc(600), fs=200.0), "r.npz", {},
     "grid.test.n_samples = 512"),
    ("NaN", lambda p: np.savez(p / "r.npz", acc=np.where(_acc() > 3, np.nan, _acc()), fs=200.0), "r.npz", {},
     "grid.measured.path"),
    ("unknown format", lambda p: (p / "r.mat").write_text("x"), "r.mat", {}, "unknown record format"),
    ("no sampling rate", lambda p: np.savez(p / "r.npz", acc=_acc()), "r.npz", {}, "no sampling rate"),
]


@pytest.mark.parametrize("label, make, name, measured, fragment", BAD_RECORDS, ids=[b[0] for b in BAD_RECORDS])
def test_bad_measured_record_is_refused(tmp_path, label, make, name, measured, fragment):
    make(tmp_path)
    refused(measured_config(tmp_path, tmp_path / name, **measured), fragment)


def test_accelerometer_beyond_the_record_is_refused(tmp_path):
    np.savez(tmp_path / "r.npz", acc=_acc(), fs=200.0)
    config = measured_config(tmp_path, tmp_path / "r.npz", channels=[0, 1, 2, 3])
    config["grid"]["accelerometers"] = [0, 1, 2, 3, 4]
    refused(config, "grid.accelerometers[4] = 4: only 4 channels are read")


# --- through a real snakemake -n: refused before any job -------------------------
@pytest.mark.parametrize("text, fragment", [
    ("studies:\n  demo:\n    cases:\n      c3: {damping: 0.0, noise: 5}\n", "5 % is 0.05"),
    ("seeds: {first: 0, count: 3}\nseeds: {first: 0, count: 4}\n", "key 'seeds' given twice"),
    ("published: config/nowhere.csv\n", "published = 'config/nowhere.csv': no such file"),
    ("grid:\n  model: {thicknes: 0.001}\n", "grid.model: unknown key(s) ['thicknes']"),
])
def test_snakemake_refuses_before_any_job(small_workflow, tmp_path, text, fragment):
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    proc = run_snakemake(small_workflow, "--configfile", str(bad), "-n", check=False)
    assert proc.returncode != 0
    assert fragment in proc.stdout + proc.stderr


def test_zero_padded_table_override_reaches_the_table(small_workflow, tmp_path):
    override = tmp_path / "o.yaml"
    override.write_text(yaml.safe_dump({**yaml.safe_load((ROOT / SMALL_CONFIG_FILE).read_text()),
                                        "tables": {"01": {"title": "Identified frequencies, zeta = 0, eta = 0 %"}}},
                                       sort_keys=False))  # snakemake compares params in key order
    proc = run_snakemake(small_workflow, "--configfile", str(override), "-n", "--rerun-triggers", "params")
    planned = re.findall(r"output: \S*results/tables/(table_\d\d)\.csv", proc.stdout + proc.stderr)
    assert planned == ["table_01"], planned


# --- intermediate files: checked by their readers, the file named -----------------
def _rewrite(src, dest, edit):
    frame = pd.read_csv(src)
    edit(frame).to_csv(dest, index=False)
    return dest


CORRUPT = [
    ("truncated", lambda f: f.iloc[: len(f) // 2], "expected (case, seed, method) combinations missing"),
    ("column dropped", lambda f: f.drop(columns="case"), "missing columns ['case']"),
    ("NaN label", lambda f: f.assign(omega=f["omega"].where(f.index != 3)), "NaN in columns ['omega']"),
    ("a seed lost", lambda f: f[f["seed"] != 1], "(c3, 1, tcm)"),
    ("a method lost", lambda f: f[f["method"] != "era"], "(c1, -1, era)"),
]


@pytest.mark.parametrize("label, edit, fragment", CORRUPT, ids=[c[0] for c in CORRUPT])
def test_corrupt_identified_file_is_refused_naming_it(small_workflow, tmp_path, label, edit, fragment):
    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    seeds = {"first": 0, "count": 3}
    good = small_workflow / "results/identified/demo_named.csv"
    assert len(read_identified(good, config["studies"]["demo"], seeds)) > 0
    bad = _rewrite(good, tmp_path / "demo_named.csv", edit)
    with pytest.raises(ValueError, match=str(bad)) as err:
        read_identified(bad, config["studies"]["demo"], seeds)
    assert fragment in str(err.value)


def test_interpretations_read_together_each_checked(small_workflow, tmp_path):
    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    demo, seeds = config["studies"]["demo"], {"first": 0, "count": 3}
    files = [small_workflow / f"results/identified/demo_{i}.csv" for i in ("named", "lower")]
    frames = read_interpretations(files, ["named", "lower"], demo, seeds)
    assert list(frames) == ["named", "lower"]
    assert frames["lower"].equals(read_identified(files[1], demo, seeds))
    bad = _rewrite(files[1], tmp_path / "demo_lower.csv", lambda f: f[f["method"] != "tcm"])
    with pytest.raises(ValueError, match=str(bad)):
        read_interpretations([files[0], bad], ["named", "lower"], demo, seeds)
    with pytest.raises(ValueError, match="one file per interpretation"):
        read_interpretations(files[:1], ["named", "lower"], demo, seeds)


def test_corrupt_grid_files_are_refused_naming_them(small_workflow, tmp_path):
    spec = base_config()["grid"]
    spec["seeds"] = {"first": 0, "count": 2}
    ident = small_workflow / "results/grid/identified.csv"
    sel = small_workflow / "results/grid/selection.csv"
    assert len(read_grid_identified(ident, spec)) and len(read_selection(sel, spec))
    bad = _rewrite(ident, tmp_path / "identified.csv", lambda f: f[f["seed"] == 0])
    with pytest.raises(ValueError, match=f"{bad}: .* expected \\(seed, case, run\\)"):
        read_grid_identified(bad, spec)
    bad = _rewrite(sel, tmp_path / "selection.csv", lambda f: f[f["rank"] != 2])
    with pytest.raises(ValueError, match=f"{bad}: seed 0: ranks"):
        read_selection(bad, spec)
    (tmp_path / "garbage.csv").write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(ValueError, match="garbage.csv"):
        read_selection(tmp_path / "garbage.csv", spec)


# --- resume: the main command alone, after SIGINT or SIGKILL ----------------------
sys.path.insert(0, str(ROOT / "workflow"))
import stale_locks  # noqa: E402

FAULT_TARGETS = [f"results/tables/table_{n:02d}.csv" for n in (1, 2, 5)]


def test_stale_lock_is_cleared_and_live_run_is_reported(tmp_path):
    locks = tmp_path / ".snakemake/locks"
    locks.mkdir(parents=True)
    (locks / "0.input.lock").write_text("x")
    assert stale_locks.main(tmp_path) == 0 and not list(locks.iterdir())
    (locks / "0.output.lock").write_text("x")
    # a Snakemake running there (its command line is `python -m snakemake ...`); a command that merely names
    # snakemake is no run
    fake = tmp_path / "fake" / "snakemake"
    fake.mkdir(parents=True)
    (fake / "__main__.py").write_text("import time\ntime.sleep(60)\n")
    named = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)", "snakemake"], cwd=tmp_path)
    live = subprocess.Popen([sys.executable, "-m", "snakemake", "--cores", "1"], cwd=tmp_path,
                            env=dict(os.environ, PYTHONPATH=str(tmp_path / "fake")))
    try:
        time.sleep(0.5)
        assert stale_locks.main(tmp_path) == stale_locks.ACTIVE
        assert (locks / "0.output.lock").exists()
    finally:
        live.kill()
        live.wait()
    try:
        assert stale_locks.main(tmp_path) == 0 and not list(locks.iterdir())
    finally:
        named.kill()
        named.wait()


def regenerate_small(work):
    return regenerate(work, *FAULT_TARGETS, "--configfile", SMALL_CONFIG_FILE)


@pytest.mark.parametrize("sig, seed", [(signal.SIGKILL, 13), (signal.SIGINT, 14)])
def test_interrupted_run_resumes_with_the_main_command(small_workflow, tmp_path, sig, seed):
    """Kill a run at a seeded random point (the whole process group: a
    flaky machine, or Ctrl-C), rerun the main command once: it resumes and
    the tables equal a clean run's byte for byte. While the first run is
    alive, a second is refused with a clear message."""
    work = regenerate_project(tmp_path)
    delay = random.Random(seed).uniform(3.0, 15.0)
    first = regenerate_small(work)
    time.sleep(delay)
    if first.poll() is None:
        second = regenerate_small(work)
        out, _ = second.communicate(timeout=120)
        assert second.returncode == 3, out
        assert "Another" in out and "regenerate.sh" in out
        os.killpg(first.pid, sig)
    first.communicate(timeout=120)
    resumed = regenerate_small(work)
    out, _ = resumed.communicate(timeout=600)
    assert resumed.returncode == 0, out[-3000:]
    for target in FAULT_TARGETS:
        assert (work / target).read_bytes() == (small_workflow / target).read_bytes(), target

