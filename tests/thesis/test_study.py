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
