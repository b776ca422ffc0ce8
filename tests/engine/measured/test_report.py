"""What `modal identify` writes beside the modes: the spectral witness's
columns, the MAC matrix, settings.json (every setting, the provenance) and the
self-contained report.html; BLAS held to one thread."""

import hashlib
import json
import re

import numpy as np
import pandas as pd
import pytest

import modal
from modal.cli import blas_threads
from modal.cli import main as cli

from ...browser import assert_readable, rendered
from ..cases import ambient_beam


@pytest.fixture(scope="module")
def beam_folder(tmp_path_factory):
    """The ambient beam (three modes, five sensors) saved as .npz and identified
    into a folder, as modal identify does."""
    root = tmp_path_factory.mktemp("beam")
    acc, dt, f_exact = ambient_beam(duration_s=300.0)
    path = modal.save_record_npz(root / "beam.npz", acc, dt)
    record = modal.read_record(path)
    options = modal.IdentifyOptions(excitation="ambient", fmax=float(f_exact[2] * 1.3), max_order=40)
    out = root / "out"
    with blas_threads():  # as modal identify runs it
        result, dt_used = modal.write_identification(record, out, options,
                                                     command="modal identify beam.npz --ambient")
    return path, out, options, result, dt_used, f_exact


def test_modes_are_checked_against_the_singular_value_peaks(beam_folder):
    """Each of the three modes is selected and has a first singular value's
    peak within 1 % whose vector is its shape; a selected mode that is none
    of them (a spurious second estimate beside one) has no peak, and says so
    in its flag."""
    _, out, _, result, _, f_exact = beam_folder
    modes = pd.read_csv(out / "modes.csv", keep_default_na=False, na_values=[""])
    assert {"sv_peak_hz", "sv_number", "sv_mac", "spectral_support"} <= set(modes.columns)
    nearest = np.array([np.min(np.abs(f_exact - f) / f_exact) for f in modes["freq_hz"]])
    real = nearest < 0.01
    assert real.sum() == 3
    assert modes.loc[real, "spectral_support"].all() and (modes.loc[real, "sv_number"] == 1).all()
    np.testing.assert_allclose(modes.loc[real, "sv_peak_hz"], f_exact, rtol=0.01)
    assert (modes.loc[real, "sv_mac"] > 0.99).all()
    assert not modes.loc[~real, "spectral_support"].any()
    assert modes.loc[~real, "sv_peak_hz"].isna().all() and (modes.loc[~real, "sv_number"] == 0).all()
    if "flag" in modes:
        flags = modes["flag"].fillna("").astype(str)
        assert list(flags.str.contains("no spectral peak")) == list(~real)
    spectrum = pd.read_csv(out / "singular_values.csv")
    assert list(spectrum.columns) == ["freq_hz", "sv1", "sv2"] and (spectrum["sv1"] >= spectrum["sv2"]).all()


def test_mac_csv_is_the_auto_mac_of_the_complex_shapes(beam_folder):
    _, out, _, result, _, _ = beam_folder
    matrix = pd.read_csv(out / "mac.csv", index_col="mode")
    numbers = list(result.modes["mode"])
    assert list(matrix.index) == numbers and list(matrix.columns) == [str(n) for n in numbers]
    values = matrix.to_numpy()
    np.testing.assert_allclose(np.diag(values), 1.0, atol=1e-4)
    np.testing.assert_allclose(values, values.T, atol=1e-4)
    shapes = pd.read_csv(out / "complex_shapes.csv")
    complex_shapes = np.column_stack([(g["re"] + 1j * g["im"]).to_numpy() for _, g in shapes.groupby("mode")])
    np.testing.assert_allclose(values, modal.auto_mac(complex_shapes), atol=1e-4)
    assert values[0, 1] < 0.5  # the beam's first two modes are far from parallel at these sensors
    assert (out / "mac.png").stat().st_size > 5_000


def test_settings_json_round_trips_and_names_the_records_hash(beam_folder):
    path, out, options, result, dt_used, _ = beam_folder
    settings = json.loads((out / "settings.json").read_text())
    assert modal.IdentifyOptions.from_mapping(settings["options"]) == options
    inputs = settings["provenance"]["inputs"]
    assert len(inputs) == 1 and inputs[0]["path"] == str(path.resolve())
    assert inputs[0]["sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()
    assert inputs[0]["bytes"] == path.stat().st_size
    assert settings["provenance"]["command"] == "modal identify beam.npz --ambient"
    assert settings["version"] == settings["provenance"]["version"]
    assert settings["fs_record_hz"] == pytest.approx(100.0)
    assert settings["fs_identified_hz"] == pytest.approx(1 / dt_used)
    assert settings["decimation"] == 1  # fmax = 26 Hz: 100 Hz is below 2 x 2.5 fmax
    chosen = settings["chosen"]
    assert chosen["orders"] == {"first": 2, "last": 40, "step": 2}
    assert chosen["rows"] >= 60 and chosen["n_lags"] == 2 * chosen["rows"] + 1
    assert chosen["references"] == [0, 1, 2, 3, 4] and chosen["uncertainty_segments"] >= 4
    assert chosen["welch_nperseg"] == modal.signals.welch_segment(chosen["n_samples"])
    assert settings["criteria"] == {k: getattr(result.criteria, k) for k in settings["criteria"]}


def test_report_is_one_self_contained_page(beam_folder):
    path, out, _, result, _, _ = beam_folder
    page = (out / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 2  # the diagram, the MAC matrix
    assert not re.search(r"(src|href)=['\"]?(https?:|//|file:)", page)  # nothing loaded from elsewhere
    for f in result.modes["freq_hz"]:
        assert f"{f:.4g}" in page
    assert hashlib.sha256(path.read_bytes()).hexdigest() in page
    assert "modal identify beam.npz --ambient" in page
    assert "Why each mode is believed" in page and "singular-value peak" in page
    assert "Chosen from the record" in page and "welch_nperseg" in page
    if "flag" in result.modes:
        assert ">flag</th>" in page


@pytest.mark.slow
def test_report_reads_in_a_browser(beam_folder):
    """Opened in Chromium in a laptop's window: both pictures decode and show,
    nothing is fetched from elsewhere, no sideways scrolling; the modes
    table shows one row per row of modes.csv, the headings come in the
    order a reader follows."""
    _, out, _, _, _, _ = beam_folder
    seen = rendered(out / "report.html")
    assert_readable(seen, images=2)
    modes = pd.read_csv(out / "modes.csv")
    table = seen["tables"][0]
    assert table["header"][:2] == ["mode", "frequency (Hz)"] and table["rows"] == len(modes) + 1
    assert seen["headings"][1:5] == ["Modes", "Stabilisation diagram", "MAC of the selected modes", "Candidates"]


def test_command_line_records_its_command_and_the_decimation(tmp_path):
    acc, dt, _ = ambient_beam(duration_s=120.0)
    path = modal.save_record_npz(tmp_path / "short.npz", acc[:, :3], dt)
    out = tmp_path / "out"
    argv = ["identify", str(path), "--ambient", "--fmax", "12", "--max-order", "20", "--out", str(out), "--quiet"]
    assert cli(argv) == 0
    settings = json.loads((out / "settings.json").read_text())
    assert settings["provenance"]["command"] == "modal " + " ".join(argv)
    assert settings["decimation"] == 3 and settings["fs_identified_hz"] == pytest.approx(100 / 3)
    assert settings["options"]["fmax"] == 12 and settings["options"]["max_order"] == 20
    assert (out / "report.html").is_file()


def _blas_threads() -> set:
    from threadpoolctl import threadpool_info

    return {pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"}


def test_blas_is_held_to_one_thread_unless_the_environment_says(monkeypatch):
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    import scipy.linalg  # noqa: F401  its BLAS loaded too

    before = _blas_threads()
    with blas_threads():
        assert _blas_threads() == {1}
    assert _blas_threads() == before
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")
    with blas_threads():
        assert _blas_threads() == before


def test_the_evidence_names_the_peak_and_says_when_its_shape_is_another():
    """Each mode's sentence names the singular value that peaks (first,
    second), and a supporting peak whose singular vector is not the mode's
    shape is said to be so, not cited as a reason to believe it; the EFDD
    damping is the peak's cross-check, not the mode's."""
    from modal.measured._report import SHAPE_AGREES, evidence

    modes = pd.DataFrame({"mode": [1, 2, 3], "freq_hz": [2.5, 2.576, 6.0], "n_poles": [28, 12, 20],
                          "spectral_support": [True, True, False], "sv_number": [1, 2, 0],
                          "sv_peak_hz": [2.515, 2.515, np.nan], "sv_mac": [0.999, 0.02, np.nan],
                          "efdd_freq_hz": [2.509, np.nan, np.nan], "efdd_damping": [0.0033, np.nan, np.nan],
                          "flag": ["", "", "no spectral peak"]})
    first, second, third = evidence(modes, 30)
    assert "a peak of the first singular value at 2.515 Hz (shape MAC 1.00 with its singular vector)" in first
    assert "that peak's EFDD cross-check 2.509 Hz and damping 0.33 %" in first
    assert ("a peak of the second singular value at 2.515 Hz whose singular vector is not this shape (MAC 0.02)"
            in second) and "shape MAC" not in second
    assert "no singular-value peak near it" in third and third.endswith("Doubtful: no spectral peak.")
    modes.loc[1, "sv_mac"] = SHAPE_AGREES  # at the bound the shape agrees
    assert "(shape MAC 0.80 with its singular vector)" in evidence(modes, 30)[1]
    # one channel: MPC and MAC are 1 by construction, no evidence: not cited; two channels: cited
    one = modes.assign(mpc=1.0, sv_mac=1.0)
    first, second, _ = evidence(one, 30, n_channels=1)
    assert first.startswith("Mode 1 at 2.5 Hz, stable poles at 28 of 30 model orders, a peak of the first singular "
                            "value at 2.515 Hz, that peak's EFDD") and "MPC" not in first and "MAC" not in first
    assert "MAC" not in second and "second singular value at 2.515 Hz." in second
    assert "MPC 1.00" in evidence(one, 30, n_channels=2)[0] and "shape MAC 1.00" in evidence(one, 30, n_channels=2)[0]


def test_a_one_channel_record_s_page_says_its_shapes_tell_nothing(tmp_path):
    """The page of a one-channel record says MPC, MAC and 'same shape' are 1
    by construction; a two-channel record's page does not."""
    acc, dt, f_exact = ambient_beam(duration_s=120.0)
    for channels, said in ((1, True), (2, False)):
        record = modal.read_record(modal.save_record_npz(tmp_path / f"r{channels}.npz", acc[:, 1:1 + channels], dt))
        modal.write_identification(record, tmp_path / str(channels), "ambient", fmax=float(f_exact[2] * 1.3),
                                   max_order=20)
        page = (tmp_path / str(channels) / "report.html").read_text()
        assert ("One channel: every shape is the same number" in page) == said
