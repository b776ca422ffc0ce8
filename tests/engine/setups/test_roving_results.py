"""What ``write_setups`` (``modal identify SETUPS``) writes, checked file by
file on two short setups of the simulated plate: the merged tables as the
merge made them, each setup's own folder with its settings, report and
warnings, the log, and the options passed on to each step (an option lost on
its way is a wrong answer that looks right)."""

import dataclasses
import inspect
import json
import re
from importlib.metadata import version
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

import modal
import modal.measured
import modal.setups._results as results_module
from modal.cli import blas_threads
from modal.setups import plate_roving_test, read_setup, save_setup, write_setups
from modal.setups._results import draw_modes

PLATE = modal.SimplySupportedPlate(1.2, 0.8, 20.0, 10.0)  # 5.01, 9.64, 15.43, 17.36, 20.05 Hz
COMMAND = "modal identify setup_1 setup_2 --out out"
#: The merge's settings, none of them its default.
MERGE = {"freq_rtol": 0.02, "mac_min": 0.85, "min_setups": 1}


def significant_digits(text: str) -> int:
    """The most significant digits of any number written in ``text``."""
    most = 0
    for number in re.findall(r"(?<![\w.])-?(\d+\.?\d*)(?:e[-+]?\d+)?", text):
        most = max(most, len(number.replace(".", "").lstrip("0").rstrip("0") or "0"))
    return most


class Spy:
    """Calls ``function`` and keeps the keywords of each call."""

    def __init__(self, function):
        self.function, self.calls = function, []

    def __call__(self, *args, **keywords):
        self.calls.append(keywords)
        return self.function(*args, **keywords)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """Two 60-s setups of the plate, saved and read back; setup_1's first
    channel clipped (a warning of setup_1 only), one of setup_2's roving
    channels slightly tilted; merged with MERGE and the geometry, every step
    spied on."""
    root = tmp_path_factory.mktemp("roving")
    setups, geometry, _ = plate_roving_test(PLATE, duration=60.0)
    setups = setups[:2]
    acc = setups[0].record.acc.copy()
    top = 0.6 * np.max(acc[:, 0])
    acc[:, 0] = np.minimum(acc[:, 0], top)  # a pile-up at its largest value: clipped
    setups[0] = dataclasses.replace(setups[0], record=dataclasses.replace(setups[0].record, acc=acc))
    tilted = setups[1].channels.copy()
    tilted.loc[2, "y"] = 1e-4  # a roving channel 0.1 mrad off the vertical: read back, a unit vector of 16 digits
    setups[1] = dataclasses.replace(setups[1], channels=tilted)
    for s in setups:
        save_setup(s, root / s.name)
    read = [read_setup(root / s.name, geometry=geometry) for s in setups]
    spies = {name: Spy(getattr(modal.measured, name))
             for name in ("write_results", "write_settings", "identification_report")}
    merge, identify = Spy(results_module.merge_setups), Spy(results_module.identify_setup)
    lines, progress = [], []
    with pytest.MonkeyPatch.context() as patch, blas_threads(), \
            pytest.warns(modal.ModalWarning, match="channel 0: clipped"):
        for name, spy in spies.items():
            patch.setattr(modal.measured, name, spy)
        patch.setattr(results_module, "merge_setups", merge)
        patch.setattr(results_module, "identify_setup", identify)
        merged, results = write_setups(read, root / "out", "ambient", geometry=geometry, fmax=25, max_order=20,
                                       animate=False, log=lines.append, progress=lambda *a: progress.append(a),
                                       command=COMMAND, **MERGE)
    return {"root": root, "out": root / "out", "setups": read, "geometry": geometry, "merged": merged,
            "results": results, "lines": lines, "progress": progress, "spies": spies, "merge": merge,
            "identify": identify}


def test_the_merged_tables_are_the_merges_at_six_digits(written):
    out, merged = written["out"], written["merged"]
    for name in ("modes", "shapes", "matches"):
        frame, text = getattr(merged, name), (out / f"{name}.csv").read_text()
        read = pd.read_csv(out / f"{name}.csv", keep_default_na=False, na_values=[""])
        assert list(read.columns) == list(frame.columns), name  # no index column
        assert len(read) == len(frame) > 0, name
        numeric = frame.select_dtypes("number").columns
        assert np.allclose(read[numeric].to_numpy(float), frame[numeric].to_numpy(float), rtol=1e-5, atol=0,
                           equal_nan=True), name
        assert significant_digits(text) == 6, name  # %.6g: six, never the 16-17 of a float's repr
    channels = pd.read_csv(out / "channels.csv", keep_default_na=False)
    setups = written["setups"]
    assert list(channels.columns) == ["setup", *setups[0].channels.columns]
    assert list(channels["setup"]) == [s.name for s in setups for _ in range(len(s.channels))]
    table = pd.concat([s.channels for s in setups])
    assert np.allclose(channels[["x", "y", "z"]].to_numpy(float), table[["x", "y", "z"]].to_numpy(float), rtol=1e-5,
                       atol=0)
    assert setups[1].channels.loc[2, "z"] != 1.0  # the tilt: digits beyond six to round
    assert significant_digits((out / "channels.csv").read_text()) <= 6


def test_each_setup_folder_holds_its_own_identification(written):
    out, setups, results = written["out"], written["setups"], written["results"]
    for setup, result in zip(setups, results):
        folder = out / "setups" / setup.name
        modes = pd.read_csv(folder / "modes.csv")
        assert [c for c in modes.columns if c.startswith("phi_")] == [f"phi_{n}" for n in setup.channels["name"]]
        assert np.allclose(modes["freq_hz"], result.modes["freq_hz"], rtol=1e-5)
        assert (folder / "singular_values.csv").is_file()  # the spectrum reached write_results
        settings = json.loads((folder / "settings.json").read_text())
        assert settings["chosen"]["n_lags"] > 0 and settings["chosen"]["references"]
        assert settings["criteria"] == json.loads(json.dumps(dataclasses.asdict(result.criteria)))
        assert settings["provenance"]["command"] == COMMAND
        hashed = [f["path"] for f in settings["provenance"]["inputs"]]
        assert hashed == [str(p.resolve()) for p in (setup.record.path, setup.path / "channels.csv")]
        assert settings["options"]["channels"] == [int(c) for c in setup.channels["channel"]]
        assert settings["options"]["quantities"] == list(setup.channels["quantity"])


def test_each_setup_report_has_its_own_steps_and_warnings(written):
    out, (first, second) = written["out"], written["setups"]
    one, two = ((out / "setups" / s.name / "report.html").read_text() for s in (first, second))
    assert f"setup {first.name}" in one and f"setup {second.name}" in two
    assert "correlations:" in one and "correlations:" in two  # each setup's own log steps
    clipped = "channel 0"
    assert "clipped" in one and clipped in one
    assert "clipped" not in two  # setup_1's warning is not repeated in setup_2's report
    page = (out / "report.html").read_text()
    assert "clipped" in page and "2 setups merged into" in page
    # the top report's "What was done": the log's lines, each setup's first
    assert f"setup {first.name}: {first.record.acc.shape[0]} samples" in page
    assert f"setup {second.name}: {second.record.acc.shape[0]} samples" in page


def test_the_log_says_each_setup_its_steps_and_modes(written):
    lines, setups, results = written["lines"], written["setups"], written["results"]
    for setup, result in zip(setups, results):
        n_refs = int((setup.channels["role"] == "reference").sum())
        head = f"setup {setup.name}: {setup.record.acc.shape[0]} samples, {len(setup.channels)} channels " \
               f"({n_refs} references)"
        start = lines.index(head)
        modes = f"  {len(result.modes)} modes: " + ", ".join(f"{f:.4g}" for f in result.modes["freq_hz"]) + " Hz"
        end = lines.index(modes)
        inside = lines[start + 1:end]
        assert inside and all(line.startswith("  ") for line in inside)
        assert any(line.startswith("  correlations:") for line in inside)
    assert written["progress"] and all(len(call) == 2 for call in written["progress"])


def test_every_option_reaches_its_step(written):
    setups, geometry = written["setups"], written["geometry"]
    (merge,) = written["merge"].calls
    assert {k: merge[k] for k in MERGE} == MERGE and merge["geometry"] is geometry
    for call in written["identify"].calls:
        assert call["log"] is not None and call["progress"] is not None and isinstance(call["details"], dict)
    spies = written["spies"]
    assert [c["fmax"] for c in spies["write_results"].calls] == [25, 25]
    assert [c["title"] for c in spies["write_results"].calls] == [s.name for s in setups]
    assert all(c["spectrum"] is not None for c in spies["write_results"].calls)
    for call in spies["write_settings"].calls:
        assert call["chosen"] and call["inputs"] and call["command"] == COMMAND and call["criteria"] is not None
    for call, setup in zip(spies["identification_report"].calls, setups):
        assert call["title"] == f"setup {setup.name}" and call["steps"]


def test_a_setup_that_cannot_be_identified_is_named_and_nothing_is_written(written, tmp_path):
    second = written["setups"][1]  # not clipped: no warning
    short = dataclasses.replace(second, name="setup_3",
                                record=dataclasses.replace(second.record, acc=second.record.acc[:40]))
    with pytest.raises(ValueError, match="^setup setup_3: fmax = 25 Hz with 60 rows needs 121 lags, more than half "
                                         "the 40-sample record"):
        write_setups([second, short], tmp_path / "out", "ambient", fmax=25, max_order=20)
    assert not (tmp_path / "out").exists()


def test_two_channels_of_one_name_give_numbered_columns(written, tmp_path):
    first = written["setups"][1]  # not clipped: no warning
    channels = first.channels.assign(name="acc")
    write_setups([dataclasses.replace(first, channels=channels)], tmp_path / "out", "ambient", fmax=25,
                 max_order=20)
    modes = pd.read_csv(tmp_path / "out" / "setups" / first.name / "modes.csv")
    assert [c for c in modes.columns if c.startswith("phi_")] == [f"phi_{c}" for c in channels["channel"]]
    page = (tmp_path / "out" / "report.html").read_text()
    assert f"<h1>{first.name}</h1>" in page and "Shapes" not in page  # no geometry, no shapes drawn


def test_one_record_on_its_geometry_gets_one_page(written, tmp_path):
    """One setup with a geometry: one page holds the record's own (its modes
    with the witness's columns, why each is believed, the diagram, the MAC
    matrix, the candidates) and the shapes drawn, not a roving test's."""
    first, geometry = written["setups"][1], written["geometry"]
    write_setups([first], tmp_path / "out", "ambient", fmax=25, max_order=20, geometry=geometry, animate=False)
    out = tmp_path / "out"
    page = (out / "report.html").read_text()
    assert f"<h1>{first.name} on its geometry</h1>" in page and "merged" not in page.split("<h2>")[0]
    headings = re.findall(r"<h2>([^<]+)</h2>", page)
    expected = ["Modes", "Stabilisation diagram", "Shapes", "MAC of the selected modes"]
    assert [h for h in headings if h in expected] == expected and "Setups" not in headings
    own = (out / "setups" / first.name / "report.html").read_text()
    table = page.split("<h2>Modes</h2>")[1].split("<h2>")[0]
    assert table == own.split("<h2>Modes</h2>")[1].split("<h2>")[0]  # the record's table, evidence and notes
    assert "SV peak" in table and "Why each mode is believed" in table
    assert ("<h2>Candidates</h2>" in page) == ("<h2>Candidates</h2>" in own)
    nodes = pd.read_csv(out / "shapes.csv")["node"].nunique()
    assert f"Shapes drawn at {nodes} nodes of the geometry." in page


def png_size(path) -> tuple[int, int]:
    """A PNG's width and height in pixels (its header)."""
    header = path.read_bytes()[16:24]
    return int.from_bytes(header[:4], "big"), int.from_bytes(header[4:], "big")


def test_each_mode_is_drawn_titled_animated_and_announced(written, tmp_path):
    """Two modes: both pictures at their resolution (90 and 110 dpi), each
    titled with its frequency and damping, each animated, each announced
    before it is drawn, the paths returned in order."""
    import modal.setups._drawing as drawing

    merged, geometry = written["merged"], written["geometry"]
    two = dataclasses.replace(merged, modes=merged.modes.iloc[:2])
    spies = {name: Spy(getattr(drawing, name)) for name in ("modes_figure", "mode_shape_figure",
                                                             "mode_shape_animation")}
    lines = []
    with pytest.MonkeyPatch.context() as patch:
        for name, spy in spies.items():
            patch.setattr(drawing, name, spy)
        paths = draw_modes(geometry, two, tmp_path, animate=True, log=lines.append)
    modes = [int(m) for m in two.modes["mode"]]
    titles = [f"mode {m.mode}: {m.freq_hz:.4g} Hz, damping {100 * m.damping:.2g} %" for m in two.modes.itertuples()]
    assert paths == [tmp_path / "modes.png", *(tmp_path / f"mode_{m}.png" for m in modes)]
    assert [c["title"] for c in spies["mode_shape_figure"].calls] == titles
    assert [c["title"] for c in spies["mode_shape_animation"].calls] == titles
    assert all((tmp_path / f"mode_{m}.gif").stat().st_size > 0 for m in modes)
    assert lines == ["drawing 2 modes on the geometry (modes.png)"] + [
        f"  mode {m} ({k}/2): mode_{m}.png, animating mode_{m}.gif" for k, m in enumerate(modes, start=1)]
    width, height = drawing.modes_figure(geometry, two.shapes, dict(zip(modes, titles))).get_size_inches()
    assert png_size(paths[0]) == (round(90 * width), round(90 * height))
    width, height = drawing.mode_shape_figure(geometry, two.shapes, modes[0], title=titles[0]).get_size_inches()
    assert png_size(paths[1]) == (round(110 * width), round(110 * height))


def test_the_top_settings_say_the_options_the_merge_and_the_inputs(written):
    out, setups = written["out"], written["setups"]
    settings = json.loads((out / "settings.json").read_text())
    assert settings["options"]["excitation"] == "ambient"
    assert (settings["options"]["fmax"], settings["options"]["max_order"]) == (25, 20)
    assert settings["merge"] == {**MERGE, "setups": [s.name for s in setups]}
    assert settings["geometry"] == str(written["geometry"].source)
    assert settings["version"] == settings["provenance"]["version"] == version("modal-identification")
    assert settings["provenance"]["command"] == COMMAND
    assert len(settings["provenance"]["inputs"]) == 4  # two records, two channel tables
    assert list(settings) == ["options", "merge", "geometry", "version", "provenance"]
    text = (out / "settings.json").read_text()
    assert text == json.dumps(settings, indent=2) + "\n"  # for a reader: two spaces a level


def test_the_inputs_a_setup_was_read_from(tmp_path):
    """A record read from a file: it, and the channel table and pyOMA's two
    files beside it where they exist; an array in memory: none. The geometry's
    folder only where it exists."""
    record = tmp_path / "record.npy"
    for name in ("record.npy", "channel_dofs.txt", "setup_info.txt"):
        (tmp_path / name).write_text("")
    setup = SimpleNamespace(record=SimpleNamespace(path=record), path=tmp_path)
    assert results_module._setup_inputs(setup) == [record, tmp_path / "channel_dofs.txt", tmp_path / "setup_info.txt"]
    (tmp_path / "channels.csv").write_text("")
    assert results_module._setup_inputs(setup)[:2] == [record, tmp_path / "channels.csv"]
    in_memory = SimpleNamespace(record=SimpleNamespace(path=None), path=None)
    assert results_module._setup_inputs(in_memory) == []
    assert results_module._inputs([in_memory], SimpleNamespace(source=str(tmp_path / "no such folder"))) == []
    assert results_module._inputs([in_memory], SimpleNamespace(source=str(tmp_path))) == [tmp_path]


def test_animations_by_default():
    """``modal identify`` animates unless told not to (``--no-animation``); so do the functions."""
    assert inspect.signature(write_setups).parameters["animate"].default is True
    assert inspect.signature(draw_modes).parameters["animate"].default is True


def test_the_shapes_are_drawn_without_animations_when_asked(written):
    out, modes = written["out"], written["merged"].modes
    assert (out / "modes.png").is_file()
    assert sorted(p.name for p in out.glob("mode_*")) == sorted(f"mode_{m}.png" for m in modes["mode"])
    n = len(modes)
    drawn = [line for line in written["lines"] if line.startswith("  mode ")]
    assert drawn == [f"  mode {m} ({k}/{n}): mode_{m}.png" for k, m in enumerate(modes["mode"], start=1)]
