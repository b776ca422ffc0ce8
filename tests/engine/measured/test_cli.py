"""`modal identify` and `python -m modal`: files in, results out, exit codes."""

import subprocess
import sys

import numpy as np
import pytest

from ..cases import PALISADEN, PALISADEN_MODES_HZ

@pytest.mark.slow
def test_cli_identify_palisaden(tmp_path):
    from modal.cli import main

    out = tmp_path / "pal"
    code = main(["identify", str(PALISADEN), "--fs", "20", "--ambient", "--fmax", "5", "--highpass", "0.5",
                 "--channels", "0,1,2,3,4,5", "--refs", "0,1,2,3", "--out", str(out), "--quiet"])
    assert code == 0
    import pandas as pd

    modes = pd.read_csv(out / "modes.csv")
    for column in ("freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std", "damping_spread", "n_poles",
                   "mpc", "mamc"):
        assert column in modes
    for published in PALISADEN_MODES_HZ:
        assert np.min(np.abs(modes["freq_hz"] - published)) / published < 0.005
    assert (out / "stabilisation.png").stat().st_size > 10_000


def test_cli_errors_and_exit_codes(tmp_path, capsys):
    from modal.cli import EXIT_BAD_FILE, EXIT_CANNOT_IDENTIFY, main

    out = str(tmp_path / "o")
    bad = tmp_path / "bad.csv"
    bad.write_text("t,a\n0,1\n0.1,x\n0.2,3\n")
    assert main(["identify", str(bad), "--ambient", "--out", out]) == EXIT_BAD_FILE
    assert "bad.csv: row 3, column 2" in capsys.readouterr().err
    short = tmp_path / "short.npy"
    np.save(short, np.random.default_rng(0).standard_normal((100, 2)))
    assert main(["identify", str(short), "--fs", "10", "--ambient", "--out", out]) == EXIT_CANNOT_IDENTIFY
    assert "longer record" in capsys.readouterr().err
    # options the record cannot take are bad options (2), found before any work
    assert main(["identify", str(short), "--fs", "10", "--ambient", "--channels", "0,5", "--out", out]) == 2
    assert "channels [5]: the record has channels 0 ... 1" in capsys.readouterr().err
    assert main(["identify", str(short), "--fs", "10", "--ambient", "--fmax", "5", "--out", out]) == 2
    assert "fmax = 5 Hz must be below the Nyquist frequency 5 Hz" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["identify", str(short), "--ambient", "--free-decay", "--out", out])
    assert exc.value.code == 2
    with pytest.raises(SystemExit):
        main(["identify", str(short), "--ambient", "--channels", "a,b", "--out", out])


def test_python_m_modal_and_import_without_matplotlib():
    code = "import sys, modal; assert 'matplotlib' not in sys.modules and 'lvm_read' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)
    run = subprocess.run([sys.executable, "-m", "modal", "identify", "--help"], capture_output=True, text=True)
    assert run.returncode == 0 and "--free-decay" in run.stdout
