"""The beam studies of thesis Ch. 6 (modal.thesis.study)."""

import pytest

import modal

THESIS_SAMPLES = 3594


@pytest.mark.parametrize("method", ["tcm", "era", "cera"])
def test_study_frame_is_to_frame_with_labels(demo, method):
    """modal.thesis.study._frame builds in one call what renaming and inserting
    into ModalResult.to_frame() gives (the identified-modes files depend on it)."""
    import pandas as pd

    from modal.thesis.study import _frame

    rec = demo["make"](THESIS_SAMPLES, damping=0.01)
    if method == "tcm":
        res = modal.tcm(rec.acceleration[:, :4], demo["dt"], vel=rec.velocity[:, :4])
    elif method == "era":
        with pytest.warns(modal.ModalWarning, match=r"^era: short window \(1.001 s"):  # the thesis's 101 samples
            res = modal.era(rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    else:
        with pytest.warns(modal.ModalWarning, match=r"^cera: short window \(2.906 s"):  # one fundamental period
            res = modal.cera(rec.acceleration, demo["dt"], 6, cols=360)
    labels = dict(case="c1", damping=0.01, noise=0.0, method=method, n=6, cols=-1, seed=-1)
    expected = res.to_frame().rename(columns={"damping": "damping_id"}).drop(columns="method")
    for key, value in reversed(list(labels.items())):
        expected.insert(0, key, value)
    pd.testing.assert_frame_equal(_frame(res, **labels), expected, check_exact=True)


def test_integrated_velocities_reach_the_noise_free_cases():
    """``noise_model.velocity: integrated`` integrates the noise-free cases'
    accelerations too (the TCM sees them), and leaves the ERA, which reads
    accelerations, untouched."""
    import yaml

    from modal.thesis.study import run_study

    with open(modal_root() / "config/config.yaml", encoding="utf-8") as fh:
        config = yaml.safe_load(fh)
    spec = dict(config["studies"]["demo"], cases={"c1": {"damping": 0.0, "noise": 0.0}})
    beam, named, seeds = config["beams"]["beam5"], config["interpretations"]["named"], {"first": 0, "count": 1}
    exact = run_study(spec, beam, named, seeds)
    integrated = run_study({**spec, "noise_model": {"velocity": "integrated"}}, beam, named, seeds)
    tcm = [frame[frame["method"] == "tcm"]["omega"].to_numpy() for frame in (exact, integrated)]
    era = [frame[frame["method"] == "era"]["omega"].to_numpy() for frame in (exact, integrated)]
    assert era[0].tolist() == era[1].tolist()
    change = abs(tcm[1] / tcm[0] - 1)
    assert change.max() > 1e-4 and change.max() < 0.05  # trapezoid errors at dt = T6 / 10, not a broken record


def modal_root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]


# --------------------------------------------------------------------------- #
# Sec. 6.4 read through the thesis's guidelines (config interpretations.guideline)
# --------------------------------------------------------------------------- #

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from modal.thesis import study as thesis_study  # noqa: E402
from modal.thesis.report import assess_table  # noqa: E402
from modal.thesis.tables import compare, read_published  # noqa: E402

from pathlib import Path  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def _config():
    import yaml

    return yaml.safe_load((REPO / "config" / "config.yaml").read_text())


def test_interpreted_overrides_only_what_the_interpretation_names():
    study = {"beam": "b", "methods": {"cera": {"n_modes": 6, "cols": 1440}, "tcm": {}}, "cols_sweep": [300]}
    beam = {"samples_per_period": 10, "n_samples": 3594, "n_modes": 6}
    reading = {"studies": {"cera": {"beam": {"period_mode": 3, "n_samples": 899}, "cols_sweep": [],
                                    "methods": {"cera": {"n_modes": 3, "eigenproblem": "as_printed"}}}}}
    read, read_beam = thesis_study.interpreted(study, beam, reading, "cera")
    assert read["methods"] == {"cera": {"n_modes": 3, "cols": 1440, "eigenproblem": "as_printed"}, "tcm": {}}
    assert read["cols_sweep"] == [] and read_beam == {**beam, "period_mode": 3, "n_samples": 899}
    assert study["methods"]["cera"] == {"n_modes": 6, "cols": 1440} and "period_mode" not in beam  # copies
    assert thesis_study.interpreted(study, beam, reading, "demo") == (study, beam)


def test_period_mode_sets_the_sampling_guideline():
    beam = dict(_config()["beams"]["beam10"], n_samples=10)
    omega = modal.SimplySupportedBeam(10.0, 20.0, 1.0).natural_frequencies(6)
    assert thesis_study.beam_record(beam, 0.0).dt == pytest.approx(2 * np.pi / omega[5] / 10, rel=1e-14)
    guideline = thesis_study.beam_record({**beam, "period_mode": 3}, 0.0)
    assert guideline.dt == pytest.approx(np.pi / (5 * omega[2]), rel=1e-14)  # Sec. 3.4: T_s = pi / 5 omega_n


def test_table_7_reproduces_under_the_guideline_reading():
    # The CERA's choices reach modal.cera through the study: dropping eigenproblem or singular_values,
    # or the beam's period_mode, loses the printed digits.
    config = _config()
    published = read_published(REPO / "config" / "thesis_tables.csv")
    base, beam = config["studies"]["cera"], config["beams"]["beam10"]
    reading = config["interpretations"]["guideline"]
    study, read_beam = thesis_study.interpreted(base, beam, reading, "cera")
    study = {**study, "cases": {"c1": {"damping": 0.0, "noise": 0.0}}, "cols_sweep": []}
    identified = {"guideline": thesis_study.run_study(study, read_beam, reading, config["seeds"])}
    table = compare(published[published["table"] == 7], identified, config["tables"][7], study["methods"], 0)
    assert assess_table(table)["guideline"]["n_match"] == 9
    for slip in ("eigenproblem", "singular_values"):
        methods = {**study["methods"], "cera": {k: v for k, v in study["methods"]["cera"].items() if k != slip}}
        if slip == "singular_values":
            methods["cera"]["singular_values"] = 6
        frame = thesis_study.run_study({**study, "methods": methods}, read_beam, reading, config["seeds"])
        cera = frame[frame["method"] == "cera"].sort_values("mode")["omega"].to_numpy()
        assert not np.array_equal(np.round(cera[:3], 3), [0.434, 1.722, 3.972]), slip
