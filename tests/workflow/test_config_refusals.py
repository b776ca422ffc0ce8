"""A config is data, finite, bounded and named: what the workflow refuses
before any job (docs/reliability.md). Most checks call
``modal.thesis.config`` directly; a few dry runs show the Snakefile refusing
before any job, and ``workflow/check_configfiles.py`` (run by
``workflow/regenerate.sh`` before Snakemake) refusing before anything is
evaluated."""

import copy
import os
import subprocess
import sys
import time

import pytest
import yaml

import modal.thesis.config as mc
from workflow_run import ROOT, SMALL_CONFIG_FILE, base_config, copy_project, run_snakemake, set_key

SCHEMA = ROOT / "workflow/schemas/config.schema.yaml"
YTE = """__use_yte__: true
seeds:
  first: 0
  count: ?open("evaluated.txt", "w").write("x") or 3
"""


def refusal(config, monkeypatch, configfiles=()):
    monkeypatch.chdir(ROOT)
    with pytest.raises(ValueError) as err:
        mc.check_workflow_config(config, list(configfiles), SCHEMA)
    return str(err.value)


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    """A copy of the project (no results), for dry runs."""
    return copy_project(tmp_path_factory.mktemp("refusals"))


# --- 1. a config is data: yte refused ------------------------------------------------
def test_yte_template_refused_by_the_text_check(tmp_path):
    path = tmp_path / "yte.yaml"
    path.write_text(YTE)
    with pytest.raises(ValueError, match=r"yte.yaml: seeds.count: .*yte template expression"):
        mc.check_config_text(path)
    path.write_text("__use_yte__: true\nseeds: {first: 0, count: 3}\n")
    with pytest.raises(ValueError, match="__use_yte__"):
        mc.check_config_text(path)
    assert not (tmp_path / "evaluated.txt").exists()


def test_yte_in_a_layered_config_refused_before_snakemake_evaluates_it(project):
    """regenerate.sh's pre-check refuses the file; nothing is evaluated."""
    (project / "yte.yaml").write_text(YTE)
    proc = subprocess.run([sys.executable, "workflow/check_configfiles.py", "-n", "--configfile", "yte.yaml"],
                          cwd=project, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2, proc.stderr
    assert "yte.yaml: seeds.count" in proc.stderr and "yte template" in proc.stderr
    assert not (project / "evaluated.txt").exists()


@pytest.mark.parametrize("route", ["--profile", "--profile=", "SNAKEMAKE_PROFILE", "--workflow-profile",
                                   "profile itself"])
def test_a_template_brought_by_a_profile_is_refused_before_snakemake(project, tmp_path, route):
    """A profile (named on the command line, by $SNAKEMAKE_PROFILE, or as the
    workflow profile) whose config.yaml sets configfile: to a yte template,
    or is one itself: regenerate.sh's pre-check refuses it; nothing runs."""
    (tmp_path / "yte.yaml").write_text(YTE.replace("evaluated.txt", str(tmp_path / "evaluated.txt")))
    profile = tmp_path / "P"
    profile.mkdir()
    settings = YTE.replace("evaluated.txt", str(tmp_path / "evaluated.txt")) if route == "profile itself" \
        else f"configfile: {tmp_path / 'yte.yaml'}\n"
    (profile / "config.v8+.yaml").write_text(settings)
    args, env = ["-n"], dict(os.environ)
    if route == "SNAKEMAKE_PROFILE":
        env["SNAKEMAKE_PROFILE"] = str(profile)
    elif route == "--profile=":
        args.append(f"--profile={profile}")
    else:
        args += ["--workflow-profile" if route == "--workflow-profile" else "--profile", str(profile)]
    proc = subprocess.run([sys.executable, "workflow/check_configfiles.py", *args], cwd=project, env=env,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2, proc.stderr
    assert "yte template expression" in proc.stderr and "seeds.count" in proc.stderr
    assert not (tmp_path / "evaluated.txt").exists()


def test_profile_config_files_follow_snakemakes_lookup(tmp_path, monkeypatch):
    """A profile named (not a path) is looked up in the user's configuration
    folder; every settings file of a profile counts, and the files its
    configfile(s) name; nothing without a profile but the workflow's default."""
    home = tmp_path / "home"
    (home / "snakemake" / "mine").mkdir(parents=True)
    (home / "snakemake" / "mine" / "config.yaml").write_text("configfiles: [a.yaml, b.yaml]\n")
    (home / "snakemake" / "mine" / "profile.v9+.yaml").write_text("cores: 2\n")
    (home / "snakemake" / "mine" / "notes.yaml").write_text("anything\n")
    monkeypatch.chdir(tmp_path)
    found = mc.profile_config_files(["snakemake", "--profile", "mine"], {"XDG_CONFIG_HOME": str(home)})
    assert [p.name for p in found] == ["config.yaml", "profile.v9+.yaml", "a.yaml", "b.yaml"]
    assert mc.profile_config_files(["snakemake", "-n"], {"XDG_CONFIG_HOME": str(home)}) == []
    assert mc.profile_config_files(["snakemake", "--profile", "mine"], {}) == []  # not under ~/.config


def test_yte_in_a_layered_config_refused_by_the_snakefile_before_any_job(project):
    """Plain snakemake evaluates a --configfile's template while parsing its
    command line, before the Snakefile runs (measured with Snakemake 9.27);
    the Snakefile then refuses before any job."""
    (project / "yte.yaml").write_text(YTE)
    proc = run_snakemake(project, "-n", "--configfile", "yte.yaml", check=False)
    (project / "evaluated.txt").unlink(missing_ok=True)
    assert proc.returncode != 0
    assert "yte.yaml: seeds.count" in proc.stdout + proc.stderr
    assert "Job stats" not in proc.stdout + proc.stderr


def test_yte_in_the_default_config_refused_before_it_is_evaluated(tmp_path):
    work = copy_project(tmp_path)
    default = work / "config/config.yaml"
    default.write_text("__use_yte__: true\n" + default.read_text().replace(
        "seeds:", 'unused: ?open("evaluated.txt", "w").write("x")\nseeds:', 1))
    proc = run_snakemake(work, "-n", check=False)
    assert proc.returncode != 0
    assert "config/config.yaml: " in proc.stdout + proc.stderr
    assert not (work / "evaluated.txt").exists()


# --- 2. --configfile given twice ----------------------------------------------------------
def test_configfile_twice_refused(project):
    (project / "other.yaml").write_text("seeds: {first: 0, count: 2}\n")
    proc = run_snakemake(project, "-n", "--configfile", SMALL_CONFIG_FILE, "--configfile", "other.yaml", check=False)
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert f"--configfile {SMALL_CONFIG_FILE} other.yaml" in out, out[-2000:]


@pytest.mark.parametrize("argv, refused", [
    (["snakemake", "--configfile", "a.yaml", "b.yaml"], False),
    (["snakemake", "--configfile", "a.yaml", "-n", "--configfiles", "b.yaml"], True),
    (["snakemake", "--configfile=a.yaml", "--configf", "b.yaml"], True),
    (["snakemake", "--config", "run=x", "--configfile", "a.yaml"], False),
])
def test_configfile_options_counted(argv, refused):
    if refused:
        with pytest.raises(ValueError, match="--configfile a.yaml b.yaml"):
            mc.check_config_files([], argv)
    else:
        mc.check_config_files([], argv)


# --- 3. finite numbers, physical bounds, Nyquist, run names ------------------------
NONFINITE = [
    ("studies.demo.cases.c3.noise", float("nan")),
    ("studies.demo.cases.c2.damping", float("nan")),
    ("studies.noise.noise_sweep.noise", [0.03, float("nan")]),
    ("beams.beam5.length", float("inf")),
    ("beams.beam5.bending_stiffness", float("nan")),
    ("beams.beam5.samples_per_period", float("nan")),
    ("grid.test.fs", float("inf")),
    ("grid.test.noise", float("nan")),
    ("grid.model.youngs_modulus", float("-inf")),
    ("grid.cases.lp10", float("nan")),
    ("measured.palisaden.fmax", float("nan")),
]


@pytest.mark.parametrize("path, value", NONFINITE, ids=[p for p, _ in NONFINITE])
def test_nonfinite_numbers_refused_naming_the_key(path, value, monkeypatch):
    message = refusal(set_key(base_config(), path, value), monkeypatch)
    assert "not a finite number" in message and path.split(".")[-1] in message, message


def test_nonfinite_from_yaml_text(tmp_path, monkeypatch):
    """``.nan`` and ``.inf`` as a user writes them."""
    layer = yaml.safe_load("beams: {beam5: {length: .nan}}\ngrid: {test: {fs: .inf}}")
    config = base_config()
    config["beams"]["beam5"].update(layer["beams"]["beam5"])
    config["grid"]["test"].update(layer["grid"]["test"])
    message = refusal(config, monkeypatch)
    assert "beams.beam5.length = nan" in message and "grid.test.fs = inf" in message


@pytest.mark.parametrize("changes, fragment", [
    ({"fmax": 10}, "measured.palisaden.fmax = 10 Hz must be below the Nyquist frequency 10 Hz"),
    ({"fmax": 25.0}, "measured.palisaden.fmax = 25 Hz must be below the Nyquist"),
    ({"fmax": None, "highpass_hz": 10.5}, "measured.palisaden.highpass_hz = 10.5 Hz must be below the Nyquist"),
    ({"highpass_hz": 6}, "measured.palisaden.highpass_hz = 6 Hz must be below fmax = 5 Hz"),
    ({"channels": [0, 9]}, "measured.palisaden.channels [9]: the record has channels 0 ... 5"),
    ({"quantities": ["velocity"]}, "measured.palisaden.quantities names 1 channels, the identification uses 6"),
])
def test_measured_options_the_record_cannot_take_refused(changes, fragment, monkeypatch):
    config = base_config()
    for key, value in changes.items():
        config = set_key(config, f"measured.palisaden.{key}", value)
    assert fragment in refusal(config, monkeypatch)


@pytest.mark.parametrize("name", ["x" * 65, "a/b", "../up", "a b", "_x"])
def test_bad_run_names_refused(name, monkeypatch):
    assert "run" in refusal({**base_config(), "run": name}, monkeypatch)


def test_a_64_character_run_name_is_accepted(monkeypatch):
    monkeypatch.chdir(ROOT)
    mc.check_workflow_config({**base_config(), "run": "a" * 64}, [], SCHEMA)


# --- 4. bounded reads and plans -----------------------------------------------------------
def _alias_bomb(kind):
    if kind == "list":
        lines = ["a0: &a0 [x, y]"] + [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, 10)]
    else:
        lines = ["a0: &a0 {x: 1, y: 2}"] + [
            f"a{i}: &a{i} {{" + ", ".join(f"k{j}: *a{i - 1}" for j in range(9)) + "}" for i in range(1, 10)]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("kind", ["list", "mapping"])
def test_alias_bomb_refused_quickly(kind, tmp_path):
    path = tmp_path / "bomb.yaml"
    path.write_text(_alias_bomb(kind))  # 81 aliases, 9**9 nodes once expanded
    start = time.perf_counter()
    with pytest.raises(ValueError, match=r"bomb.yaml: line 2: YAML alias \*a0: .* aliases are refused"):
        mc.check_config_text(path)
    assert time.perf_counter() - start < 2


@pytest.mark.parametrize("text, line, name", [
    ("a: &a 1\nb: *a\n", 2, "a"),  # one alias, however harmless
    ("base: &base {fmax: 20}\nrun:\n  <<: *base\n  rows: 30\n", 3, "base"),  # a merge key is an alias too
    ("x: [1, 2]\ny: &y [3]\nz: {k: [*y]}\n", 3, "y"),
])
def test_any_alias_refused_naming_its_line(text, line, name, tmp_path):
    """The issue's rule: aliases refused at once, not only beyond a count
    (a config is a page of data: each value written where it is used); an
    anchor with no alias is plain data."""
    path = tmp_path / "aliases.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=rf"aliases.yaml: line {line}: YAML alias \*{name}: "):
        mc.check_config_text(path)
    path.write_text(text.split("\n")[0] + "\n")
    mc.check_config_text(path)  # the anchor alone


def test_large_files_refused(tmp_path):
    path = tmp_path / "large.yaml"
    path.write_text("# " + "x" * mc.MAX_CONFIG_BYTES + "\n")
    with pytest.raises(ValueError, match="more than the 1000000 a config may have"):
        mc.check_config_text(path)


@pytest.mark.parametrize("raw, expected", [
    ("seeds: {count: 3}\n".encode("utf-16"), r"UTF-16 text .* save it as UTF-8"),
    (b"seeds:\x00\x01\x02", r"binary data \(a NUL byte at position 6\)"),
    ("title: Br\u00fccke\n".encode("latin-1"), r"not UTF-8 text \(byte 0xfc at position 9"),
])
def test_config_not_utf8_text_refused_naming_the_file(raw, expected, tmp_path):
    """Both readers (the text check and the strict loader) say what the file
    holds instead of UTF-8 YAML, naming it; a UTF-8 file with the same
    characters reads."""
    path = tmp_path / "c.yaml"
    path.write_bytes(raw)
    for read in (mc.check_config_text, mc.load_strict):
        with pytest.raises(ValueError, match=f"config file {path}: {expected}"):
            read(path)
    path.write_text("title: Br\u00fccke\n", encoding="utf-8")
    assert mc.load_strict(path) == {"title": "Br\u00fccke"}


def test_alias_bomb_refused_before_snakemake_loads_it(project):
    """Snakemake itself expands a mapping bomb while loading --configfile
    (it never returns): regenerate.sh's pre-check refuses it first."""
    (project / "bomb.yaml").write_text(_alias_bomb("mapping"))
    proc = subprocess.run([sys.executable, "workflow/check_configfiles.py", "--configfile", "bomb.yaml"],
                          cwd=project, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and "bomb.yaml: line 2: YAML alias *a0" in proc.stderr


def test_a_plan_beyond_the_job_limit_refused_with_its_size(monkeypatch):
    config = set_key(base_config(), "seeds", {"first": 0, "count": 10 ** 9, "chunk": 50})
    start = time.perf_counter()
    message = refusal(config, monkeypatch)
    assert "identification jobs" in message and "more than 10000" in message, message
    assert time.perf_counter() - start < 5


# --- 6. measured refs: the record's channel numbers, among the channels used -------------
def test_refs_are_record_channel_numbers(monkeypatch):
    config = base_config()
    config["measured"]["palisaden"].update(channels=[3, 4, 5], refs=[4, 5])
    monkeypatch.chdir(ROOT)
    mc.check_workflow_config(copy.deepcopy(config), [], SCHEMA)  # refs 4, 5 are channels used
    config["measured"]["palisaden"]["refs"] = [0]
    assert "measured.palisaden.refs [0] are not among the channels used [3, 4, 5]" in refusal(config, monkeypatch)


# --- 7. table titles as written: ζ and η ----------------------------------------------------
def test_title_printing_other_zeta_and_eta_refused(monkeypatch):
    config = set_key(base_config(), "tables.1.title", "Identified frequencies with ζ = .05, η = 3 %")
    message = refusal(config, monkeypatch)
    assert "tables.1.title says 'ζ = .05'" in message and "tables.1.title says 'η = 3 %'" in message, message


def test_default_titles_agree_with_their_cases(monkeypatch):
    config = base_config()
    mc.normalise_numbers(config)
    assert mc.case_problems(config) == []


# --- 8. interpretation names ---------------------------------------------------------------
def test_interpretation_name_with_underscore_refused(monkeypatch):
    config = base_config()
    config["interpretations"]["lower_x"] = config["interpretations"]["lower"]
    message = refusal(config, monkeypatch)
    assert "'lower_x' does not match" in message and "no '_'" in message, message


# --- 10. a parameter study never overwrites the committed results/tables ---------------------
@pytest.fixture()
def git_tree(tmp_path):
    """A git work tree whose results/tables is committed."""
    (tmp_path / "results/tables").mkdir(parents=True)
    (tmp_path / "results/tables/table_01.csv").write_text("mode\n1\n")
    for args in (["init", "-q"], ["add", "results"], ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "t"]):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)
    return tmp_path


def test_changed_config_without_run_name_refused_where_tables_are_committed(git_tree, monkeypatch):
    default = ROOT / "config/config.yaml"
    changed = set_key(base_config(), "seeds.count", 7)
    mc.normalise_numbers(changed)
    monkeypatch.chdir(git_tree)
    with pytest.raises(ValueError, match=r"seeds.count.*--config run=<name>"):
        mc.check_run_name(changed, default)
    mc.check_run_name({**changed, "run": "seven_seeds"}, default)  # named: results/runs/seven_seeds/
    unchanged = base_config()
    mc.normalise_numbers(unchanged)
    mc.check_run_name(unchanged, default)  # the default config regenerates the committed tables


def test_computing_the_searches_needs_no_run_name(git_tree, monkeypatch):
    """run_searches recomputes the default config's committed searches table."""
    default = ROOT / "config/config.yaml"
    config = {**base_config(), "run_searches": True}
    mc.normalise_numbers(config)
    monkeypatch.chdir(git_tree)
    mc.check_run_name(config, default)
    with pytest.raises(ValueError, match=r"\(seeds.count\)"):
        mc.check_run_name(set_key(config, "seeds.count", 7), default)


def test_searches_not_computed_cite_the_committed_table(tmp_path, monkeypatch):
    config = base_config()
    assert config["run_searches"] is False  # the default: a regeneration computes no search
    monkeypatch.chdir(tmp_path)
    missing = "run_searches = false cites the committed results/tables/searches.csv: no such file"
    assert any(missing in p for p in mc.path_problems(config))
    assert not any(missing in p for p in mc.path_problems({**config, "run_searches": True}))
    assert not any(missing in p for p in mc.path_problems({**config, "searches": {}}))


def test_changed_config_without_run_name_refused_by_snakemake(tmp_path):
    work = copy_project(tmp_path)
    (work / "results/tables").mkdir(parents=True)
    (work / "results/tables/table_01.csv").write_text("mode\n1\n")
    for args in (["init", "-q"], ["add", "results"], ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "t"]):
        subprocess.run(["git", *args], cwd=work, check=True, capture_output=True)
    proc = run_snakemake(work, "-n", "--configfile", SMALL_CONFIG_FILE, check=False)
    assert proc.returncode == 2
    assert "--config run=<name>" in proc.stdout + proc.stderr
    # plain snakemake too: the refusal and exit 2, no traceback
    assert 'File "' not in proc.stderr and "ValueError" not in proc.stderr, proc.stderr[-2000:]


# --- 8. roving tests: setups with their geometry, no channels or refs of their own ----------
@pytest.mark.parametrize("change, fragment", [
    ({"path": "tests/data/palisaden_20hz_30min.npy"}, "measured.roving_plate"),
    ({"refs": [0]}, "measured.roving_plate"),
    ({"geometry": None}, "measured.roving_plate"),
    ({"setups": ["tests/data/roving_plate/setup_1", "tests/data/roving_plate/nowhere"]},
     "measured.roving_plate.setups[1] = 'tests/data/roving_plate/nowhere': tests/data/roving_plate/nowhere: no such "
     "setup"),
    ({"geometry": "tests/data/palisaden_geometry"},
     "measured.roving_plate.setups[0] = 'tests/data/roving_plate/setup_1': tests/data/roving_plate/setup_1/channels.csv: "
     "node(s) 1-1, 2-1, 3-1, 4-1, 5-3 not in the geometry"),
])
def test_roving_test_refusals(change, fragment, monkeypatch):
    config = base_config()
    config["measured"]["roving_plate"].update(change)
    if change.get("geometry", "") is None:
        del config["measured"]["roving_plate"]["geometry"]
    assert fragment in refusal(config, monkeypatch)


# --- 11. searches of unstated settings: every setting must be a study that can run -----------
@pytest.mark.parametrize("change, fragment", [
    ({"study": "nosuch"}, "searches.probe.study = 'nosuch' is not one of studies"),
    ({"tables": [3, 7]}, "searches.probe.tables: [7] are not tables of studies.demo"),
    ({"vary": {"methods.cera.cols": [100]}}, "searches.probe.vary: 'methods.cera.cols' is not a setting"),
    ({"vary": {"beam.n_samples": [3594, 100]}},
     "searches.probe, setting s001 (beam.n_samples = 100): methods.era: rows + cols = 124"),
    ({"vary": {"beam.n_samples": ["long"]}}, "searches.probe, setting s000 (beam.n_samples = long): beam.n_samples"),
    ({"vary": {"noise_model.scale": ["peak"]}},
     "searches.probe, setting s000 (noise_model.scale = peak): noise_model.scale = 'peak': 'peak' is not one of"),
    ({"vary": {"methods.era.rows": []}}, "searches.probe.vary.methods.era.rows"),
    ({"vary": {"beam.samples_per_period": [float("nan")]}},
     "searches.probe.vary.beam.samples_per_period.0 = nan: not a finite number"),
])
def test_impossible_search_refused(change, fragment, monkeypatch):
    config = base_config()
    config["searches"] = {"probe": {"question": "q", "study": "demo", "tables": [3],
                                    "vary": {"methods.era.rows": [24]}, **change}}
    message = refusal(config, monkeypatch)
    assert fragment in message, message


def test_search_settings_count_in_the_plan(monkeypatch):
    config = base_config()
    config["searches"] = {f"probe{k}": {"question": "q", "study": "demo", "tables": [3],
                                        "vary": {"methods.era.cols": list(range(100, 500))}} for k in range(30)}
    config["run_searches"] = True
    message = refusal(config, monkeypatch)
    assert "12000 search settings" in message, message
