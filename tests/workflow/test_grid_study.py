"""The grid chapter's pipeline: virtual test -> choice -> filtering -> TCM/ERA -> tables."""

import copy
import inspect

import numpy as np
import pandas as pd
import pytest
import yaml

import modal
import modal.thesis.grid_study as gs
from modal.structures._shake_test import shake_test
from modal.structures._grid import Grid
from modal.records._io import save_record_npz, write_uff58
from workflow_run import ROOT

CONFIG = yaml.safe_load((ROOT / "config/config.yaml").read_text())


@pytest.fixture(scope="module")
def spec():
    s = copy.deepcopy(CONFIG["grid"])
    s["seeds"] = {"first": 0, "count": 2}
    return s


@pytest.fixture(scope="module")
def grid(spec):
    return gs.grid_model(spec)


def test_noise_free_virtual_test_era_exact(grid, spec):
    # Four participating modes, no noise, no filtering: ERA recovers the true
    # frequencies of the participating modes to 1e-6 relative.
    test = {**spec["test"], "noise": 0.0, "n_modes": 4}
    shaken = shake_test(grid, **test)
    with pytest.warns(modal.ModalWarning, match="short window"):  # 420 samples: the lowest mode's periods are few
        res = modal.era(shaken.acceleration, shaken.dt, 4, rows=20, cols=400)
    np.testing.assert_allclose(res.freq_hz, shaken.freq_hz, rtol=1e-6)
    assert not res.real_pole.any()


@pytest.mark.slow
def test_pipeline_tables(spec):
    records = gs.grid_records(spec)
    identified, selection = gs.run_grid_study(records, spec)
    assert set(identified["case"]) == set(spec["cases"])
    assert set(selection["seed"]) == {0, 1}
    assert (selection.groupby("seed").size() == spec["n_selected"]).all()
    published = modal.thesis.tables.read_published(ROOT / "config/thesis_tables.csv")
    for number in (10, 11, 12, 13, 14, 15):
        table = gs.grid_table(number, published[published["table"] == number], identified, selection, spec, 0)
        assert len(table) == (published["table"] == number).sum()
        ident = table[table["method"].isin(["tcm", "era"]) & table["published"].notna()
                      & (table["column"] != "pct_change_from_10hz")]
        assert ident["reproduced"].notna().all(), table
        np.testing.assert_allclose(ident["rel_dev"], ident["reproduced"] / ident["published"] - 1)
        # the true frequencies beside: those of the grid model
        true = table.groupby("mode")["actual"].first().to_numpy()
        np.testing.assert_allclose(true, gs.grid_model(spec).frequencies_hz(4), rtol=1e-12)


@pytest.mark.slow
def test_measured_record_path_gives_the_virtual_results(spec, tmp_path):
    records = gs.grid_records({**spec, "seeds": {"first": 0, "count": 1}})
    rec = records[0]
    ident_virtual, _ = gs.run_grid_study(records, spec)
    for path in (save_record_npz(tmp_path / "r.npz", rec.acceleration, rec.dt),
                 write_uff58(tmp_path / "r.uff", rec.acceleration, rec.dt)):
        measured = {**spec, "source": "measured", "measured": {"path": str(path), "fs": None, "channels": None}}
        ident, _ = gs.run_grid_study(gs.grid_records(measured), measured)
        np.testing.assert_allclose(ident["freq_hz"], ident_virtual["freq_hz"], rtol=1e-4)
        assert ident["actual"].isna().all()


def test_bad_input(spec):
    rec = gs.grid_records({**spec, "seeds": {"first": 0, "count": 1}})[0]
    nan = rec.acceleration.copy()
    nan[100, 2] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        gs.run_grid_study({0: gs.GridRecord(nan, rec.dt, rec.true_hz, rec.labels)}, spec)
    with pytest.raises(ValueError, match="Nyquist"):
        gs.run_grid_study({0: rec}, {**spec, "cases": {"lp150": 150.0}})
    runs = {"era_m": {**spec["runs"]["era_m3"], "sets": 40}}
    with pytest.raises(ValueError, match="reduce rows or cols"):
        gs.run_grid_study({0: rec}, {**spec, "runs": runs})
    with pytest.raises(ValueError, match="exceeds the 2 channels"):
        gs.run_grid_study({0: rec}, {**spec, "accelerometers": [0, 1],
                                      "runs": {"tcm": {"method": "tcm", "cases": ["raw"], "n_identified": [3]}}})
    with pytest.raises(ValueError, match="grid.accelerometers"):
        gs.choose_accelerometers(rec, {**spec, "accelerometers": [0, 11]})


def test_thesis_grid_is_stated_only_in_config():
    # config.yaml is the one source of the tuned grid and of its shaking
    # test: the engine repeats none of their values as a default.
    block = CONFIG["grid"]
    for function, settings in ((Grid, block["model"]), (shake_test, block["test"])):
        parameters = inspect.signature(function).parameters
        for key, value in settings.items():
            default = parameters[key].default
            assert default is inspect.Parameter.empty or default != value, f"{function.__name__}({key}=...)"


def test_model_note_compares_with_the_published_estimates(spec):
    published = pd.read_csv(ROOT / "config/thesis_tables.csv")
    published = published[published["table"] == 10]
    model_hz, estimates = gs.model_against_estimates(10, published, spec)
    np.testing.assert_array_equal(estimates, [0.83, 1.76, 4.35, 6.49])  # thesis Table 10, "est."
    np.testing.assert_allclose(model_hz, [0.825, 1.778, 4.410, 6.467], atol=6e-4)  # README, modal/grid.py
    assert gs.model_against_estimates(11, published, spec) == (None, None)
    with pytest.raises(ValueError, match="no 'est' rows"):
        gs.model_against_estimates(10, published[published["method"] != "est"], spec)


def test_measured_record_that_cannot_fill_the_tables_is_refused(spec, tmp_path):
    """A one-channel record and a long record at another rate are refused
    with the reasons, instead of printing Table 10 beside the thesis."""
    rng = np.random.default_rng(0)
    n, fs = spec["test"]["n_samples"], spec["test"]["fs"]
    for name, acc, rate, reason in [
        ("one.npz", rng.standard_normal((n, 1)), fs, "1 channel"),
        ("long.npz", rng.standard_normal((20 * n, 6)), 100.0, "samples at 100 Hz, but grid.test describes"),
    ]:
        path = tmp_path / name
        np.savez(path, acc=acc, fs=rate)
        measured = {**spec, "source": "measured", "measured": {"path": str(path), "fs": None, "channels": None}}
        with pytest.raises(ValueError, match=f"{name}: this record cannot fill.*\\n.*{reason}"):
            gs.grid_records(measured)
