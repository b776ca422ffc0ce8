"""Record input/output (modal.io): round trips and bad files."""

import numpy as np
import pytest

from modal.io import load_record, save_record_npz, write_uff58

DT = 1 / 200


@pytest.fixture
def acc():
    rng = np.random.default_rng(3)
    return rng.standard_normal((64, 3))


def test_npz_round_trip(tmp_path, acc):
    path = save_record_npz(tmp_path / "rec.npz", acc, DT)
    got, dt = load_record(path)
    np.testing.assert_array_equal(got, acc)
    assert dt == DT


def test_npz_alternative_keys(tmp_path, acc):
    np.savez(tmp_path / "y.npz", y=acc[:, 0], fs=200.0)
    got, dt = load_record(tmp_path / "y.npz")
    assert got.shape == (64, 1)
    assert dt == pytest.approx(DT, rel=1e-15)
    np.savez(tmp_path / "nofs.npz", acc=acc)
    got, dt = load_record(tmp_path / "nofs.npz", fs=200)
    assert dt == pytest.approx(DT)


def test_csv_with_time_column_and_header(tmp_path, acc):
    t = DT * np.arange(acc.shape[0])
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack([t, acc]), delimiter=",", header="t,a1,a2,a3", comments="", fmt="%.17g")
    got, dt = load_record(path)
    np.testing.assert_array_equal(got, acc)
    assert dt == pytest.approx(DT, rel=1e-12)


def test_csv_with_given_fs(tmp_path, acc):
    path = tmp_path / "rec.csv"
    np.savetxt(path, acc, delimiter=",", fmt="%.17g")
    got, dt = load_record(path, fs=200)
    np.testing.assert_array_equal(got, acc)
    assert dt == pytest.approx(DT)


@pytest.mark.parametrize("binary", [False, True])
def test_uff58_round_trip(tmp_path, acc, binary):
    path = write_uff58(tmp_path / "rec.uff", acc, DT, binary=binary)
    got, dt = load_record(path)
    assert got.shape == acc.shape
    np.testing.assert_allclose(got, acc, rtol=0 if binary else 1e-10, atol=0 if binary else 1e-11)
    assert dt == pytest.approx(DT, rel=1e-12)


def test_bad_files(tmp_path, acc):
    bad = acc.copy()
    bad[5, 1] = np.nan
    np.savez(tmp_path / "nan.npz", acc=bad, dt=DT)
    with pytest.raises(ValueError, match="NaN"):
        load_record(tmp_path / "nan.npz")
    np.savez(tmp_path / "nofs.npz", acc=acc)
    with pytest.raises(ValueError, match="sampling rate"):
        load_record(tmp_path / "nofs.npz")
    np.savez(tmp_path / "both.npz", acc=acc, dt=DT)
    with pytest.raises(ValueError, match="contradicts"):
        load_record(tmp_path / "both.npz", fs=100)
    (tmp_path / "rec.xls").write_text("1,2\n3,4\n")
    with pytest.raises(ValueError, match="unknown record format"):
        load_record(tmp_path / "rec.xls")
    (tmp_path / "ragged.csv").write_text("0,1,2\n0.005,3\n0.01,5,6\n")
    with pytest.raises(ValueError, match="unequal"):
        load_record(tmp_path / "ragged.csv")
    (tmp_path / "hole.csv").write_text("0,1,2\n0.005,,4\n0.01,5,6\n")
    with pytest.raises(ValueError, match=r"hole.csv: row 2, column 2 is empty"):
        load_record(tmp_path / "hole.csv")
    (tmp_path / "jitter.csv").write_text("0,1\n0.005,2\n0.013,3\n")
    with pytest.raises(ValueError, match="uniformly"):
        load_record(tmp_path / "jitter.csv")
    with pytest.raises(ValueError, match="does not exist"):
        load_record(tmp_path / "missing.npz")


def test_uff_unequal_lengths(tmp_path, acc):
    import pyuff

    path = write_uff58(tmp_path / "a.uff", acc, DT)
    short = write_uff58(tmp_path / "b.uff", acc[:10, :1], DT)
    sets = pyuff.UFF(str(path)).read_sets() + [pyuff.UFF(str(short)).read_sets()]
    for s in sets:
        s.setdefault("orddenom_spec_data_type", 0)
    mixed = tmp_path / "mixed.uff"
    pyuff.UFF(str(mixed)).write_sets(sets, mode="overwrite")
    with pytest.raises(ValueError, match="unequal length"):
        load_record(mixed)


def test_writers_reject_bad_input(tmp_path, acc):
    with pytest.raises(ValueError, match="dt"):
        save_record_npz(tmp_path / "x.npz", acc, 0.0)
    with pytest.raises(ValueError, match="NaN"):
        write_uff58(tmp_path / "x.uff", np.full((4, 1), np.nan), DT)
    with pytest.raises(ValueError, match="nodes"):
        write_uff58(tmp_path / "x.uff", acc, DT, nodes=[1])
