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
