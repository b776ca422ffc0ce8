"""Tracking a campaign's modes by shape (issue 34): references built from
frequency and shape together, so modes that cross in frequency stay apart;
a gate that follows each mode's drift; the one-to-one assignment of largest
MAC; shapes that match no reference untracked. Synthetic tables of modes
first (fast), then a simulated campaign whose modes cross, identified."""

import numpy as np
import pandas as pd
import pytest

from modal.campaign import identify_chunk, read_campaign, reference_modes, track_modes
from modal.campaign._report import _interval, campaign_report
from modal.campaign._simulated import simulate_campaign
from modal.campaign._tracking import TRACKED_COLUMNS, observed_ranges
from modal.identification import mac


def _modes(rows):
    """A modes table: rows of (record, frequency, shape)."""
    table = []
    for k, (record, freq, shape) in enumerate(rows):
        row = {"record": record, "time": pd.Timestamp("2025-01-01") + pd.Timedelta(hours=int(record[1:])),
               "mode": k, "freq_hz": freq, "freq_std_hz": 0.01, "damping": 0.01, "damping_std": 0.002}
        row.update({f"phi_{c}": v for c, v in enumerate(shape)})
        table.append(row)
    return pd.DataFrame(table)


def _unit(angle_deg):
    """A shape at ``angle_deg`` from x towards y: MAC cos^2 with x."""
    a = np.radians(angle_deg)
    return (np.cos(a), np.sin(a), 0.0)


X, Y = _unit(0), _unit(90)


def _crossing(n=40, blends=(), seed=0):
    """Two modes of orthogonal shapes, x drifting from 2.3 to 2.7 Hz over the
    records and y steady at 2.5 Hz (they cross at record n / 2), estimates
    scattered by 0.2 % and shapes by a few degrees; ``blends``: (record,
    angle) estimates at 2.5 Hz with shapes between x and y."""
    rng = np.random.default_rng(seed)
    rows = []
    for r in range(n):
        fx = 2.3 + 0.4 * r / (n - 1)
        rows.append((f"r{r:03d}", fx * (1 + 0.002 * rng.standard_normal()), _unit(3 * rng.standard_normal())))
        rows.append((f"r{r:03d}", 2.5 * (1 + 0.002 * rng.standard_normal()), _unit(90 + 3 * rng.standard_normal())))
    rows += [(f"r{record:03d}", 2.5, _unit(angle)) for record, angle in blends]
    return _modes(rows)


def test_the_assignment_takes_the_larger_mac():
    """Two estimates of one record may both match the reference: the one of
    larger MAC is tracked, though the other lies at the reference frequency
    exactly (a cost that preferred the nearer frequency, or an inverted
    comparison, would take MAC 0.85)."""
    reference = pd.DataFrame({"mode": [1], "freq_hz": [2.0], "phi_0": [1.0], "phi_1": [0.0], "phi_2": [0.0]})
    modes = _modes([("r1", 2.0, _unit(22.8)), ("r1", 2.08, _unit(5.7))])  # MAC 0.85 and 0.99
    similarity = mac(np.array([_unit(22.8), _unit(5.7)]).T, np.array([X]).T)[:, 0]
    assert similarity == pytest.approx([0.85, 0.99], abs=0.002)
    tracked, untracked = track_modes(modes, reference, freq_rtol=0.05, mac_min=0.8)
    assert tracked["freq_hz"].tolist() == [2.08] and tracked["mac"].tolist() == pytest.approx([0.99], abs=0.002)
    assert untracked["freq_hz"].tolist() == [2.0]
    # two references, two estimates: the pairing of largest summed MAC, not the nearest frequencies
    references = pd.DataFrame({"mode": [1, 2], "freq_hz": [2.0, 2.02], "phi_0": [1.0, 0.0], "phi_1": [0.0, 1.0],
                               "phi_2": [0.0, 0.0]})
    modes = _modes([("r1", 2.0, _unit(80)), ("r1", 2.02, _unit(10))])
    tracked, _ = track_modes(modes, references, freq_rtol=0.05, mac_min=0.8)
    assert sorted(zip(tracked["mode"], tracked["freq_hz"])) == [(1, 2.02), (2, 2.0)]


def test_of_two_estimates_of_one_shape_the_nearer_in_frequency_is_tracked():
    """A mode at 7.90 Hz (MAC 0.9994 with the reference) and a spurious row
    of its shape at 8.10 Hz (MAC 0.9997), as a simulated campaign gave: the
    MACs differ by noise, so the frequency decides (the MAC alone took 8.10
    Hz, 2.5 % from the truth). With the shapes further apart (MAC 0.985
    against 0.9997) the MAC decides again: 0.0147 of MAC outweighs the 2.3
    points of frequency (0.0023)."""
    reference = pd.DataFrame({"mode": [1], "freq_hz": [7.92], "phi_0": [1.0], "phi_1": [0.0], "phi_2": [0.0]})
    near, far = _unit(np.degrees(np.arccos(np.sqrt(0.9994)))), _unit(np.degrees(np.arccos(np.sqrt(0.9997))))
    tracked, untracked = track_modes(_modes([("r1", 7.90, near), ("r1", 8.10, far)]), reference, freq_rtol=0.05)
    assert tracked["freq_hz"].tolist() == [7.90] and untracked["freq_hz"].tolist() == [8.10]
    worse = _unit(np.degrees(np.arccos(np.sqrt(0.985))))
    tracked, _ = track_modes(_modes([("r1", 7.90, worse), ("r1", 8.10, far)]), reference, freq_rtol=0.05)
    assert tracked["freq_hz"].tolist() == [8.10]


def test_crossing_modes_give_two_references_with_their_own_shapes():
    """Without given references, two modes crossing in frequency are two
    references (a clustering by frequency alone merges them), each tracked in
    every record under its own number; the blended estimates at the crossing
    (a chain x -> 25 -> 50 -> 65 -> 90 degrees, each step MAC >= 0.8) merge
    nothing and are left untracked (MAC < 0.8 with either shape, or below
    the true mode's in their record)."""
    modes = _crossing(blends=[(3, 25), (8, 50), (12, 50), (30, 65)])
    references = reference_modes(modes, n_records=40, min_share=0.3, mac_min=0.8)
    assert len(references) == 2
    shapes = references[["phi_0", "phi_1", "phi_2"]].to_numpy().T
    truth = mac(shapes, np.array([X, Y]).T)
    assert (truth.max(axis=1) >= 0.99).all() and sorted(truth.argmax(axis=1)) == [0, 1]
    tracked, untracked = track_modes(modes, references, freq_rtol=0.05, mac_min=0.8)
    assert tracked.groupby("mode")["record"].nunique().tolist() == [40, 40]
    x_mode = int(references["mode"].iloc[int(np.argmax(truth[:, 0]))])
    x_rows = modes.merge(tracked[tracked["mode"] == x_mode], on=["record", "freq_hz"])
    assert (np.abs(np.arctan2(x_rows["phi_1"], x_rows["phi_0"])) < np.radians(20)).all()  # x shapes only
    assert sorted(untracked["record"]) == ["r003", "r008", "r012", "r030"]  # the blends
    # the x mode's references reach over its whole drift, 2.3-2.7 Hz
    assert references.loc[references["mode"] == x_mode, ["freq_low_hz", "freq_high_hz"]].to_numpy()[0] == \
        pytest.approx([2.3, 2.7], rel=0.01)


def test_a_mode_replaced_by_another_shape_at_its_frequency_is_another_reference():
    """A mode seen in the first half of the campaign and one of another shape
    at the same frequency in the second half (never in one record, so only
    their shapes tell them apart) are two references, not one."""
    modes = _modes([(f"r{r:03d}", 2.0 + 0.001 * r, X if r < 20 else Y) for r in range(40)])
    references = reference_modes(modes, n_records=40, min_share=0.3, mac_min=0.8)
    assert references["n_records"].tolist() == [20, 20]
    tracked, untracked = track_modes(modes, references)
    assert untracked.empty and tracked.groupby("mode")["record"].nunique().tolist() == [20, 20]


def test_close_modes_of_similar_shape_seen_together_stay_two():
    """Two modes 3 % apart whose shapes are alike (MAC 0.83, as with few
    channels) but which every record shows both of are two references; a
    record showing the lower one twice (two poles of it, one among the
    lower mode's estimates of the other records of the summer, 2.01 Hz)
    does not split it in two."""
    rows = [(f"r{r:03d}", (2.0 if r < 15 else 2.01) * (1 + 1e-4 * np.sin(r)), _unit(12)) for r in range(30)]
    rows += [(f"r{r:03d}", 2.06 * (1 + 0.001 * np.cos(r)), _unit(-12)) for r in range(30)]
    rows += [("r003", 2.01, _unit(12))]
    references = reference_modes(_modes(rows), n_records=30, min_share=0.3, mac_min=0.8)
    assert references["n_records"].tolist() == [30, 30]
    assert references["freq_hz"].tolist() == pytest.approx([2.005, 2.06], abs=0.006)


def test_the_observed_range_follows_the_reference_shape_only():
    """A given reference's range is the band of estimates of its shape: a
    mode of another shape chained in frequency above it does not widen it,
    so an estimate of the reference's shape among that other mode's
    frequencies (2.4 Hz) stays untracked."""
    references = pd.DataFrame({"mode": [1], "freq_hz": [2.0], "phi_0": [1.0], "phi_1": [0.0], "phi_2": [0.0]})
    rows = [(f"r{r:03d}", 1.96 + 0.002 * r, X) for r in range(40)]
    rows += [(f"r{r:03d}", 2.05 + 0.01 * r, Y) for r in range(40)] + [("r999", 2.4, X)]
    ranges = observed_ranges(_modes(rows), references, freq_rtol=0.05, mac_min=0.8)
    assert ranges.loc[0, ["freq_low_hz", "freq_high_hz"]].tolist() == pytest.approx([1.96, 2.038])
    tracked, untracked = track_modes(_modes(rows), references)
    assert "r999" in set(untracked["record"]) and len(tracked) == 40


def test_given_references_follow_a_drift_beyond_freq_rtol():
    """With the true shapes given at 2.5 Hz, the x mode is tracked over its
    whole drift (2.3-2.7 Hz, 8 % either way: beyond a fixed 5 % gate around
    the reference) and never confused with y where they cross."""
    modes = _crossing()
    references = pd.DataFrame({"mode": [1, 2], "freq_hz": [2.5, 2.5], "phi_0": [1.0, 0.0], "phi_1": [0.0, 1.0],
                               "phi_2": [0.0, 0.0]})
    ranges = observed_ranges(modes, references, freq_rtol=0.05, mac_min=0.8)
    assert ranges.loc[0, ["freq_low_hz", "freq_high_hz"]].tolist() == pytest.approx([2.3, 2.7], rel=0.01)
    tracked, untracked = track_modes(modes, references, freq_rtol=0.05, mac_min=0.8)
    assert untracked.empty and tracked.groupby("mode")["record"].nunique().tolist() == [40, 40]
    drifted = tracked[(tracked["mode"] == 1) & (np.abs(tracked["freq_hz"] / 2.5 - 1) > 0.05)]
    assert len(drifted) >= 10  # estimates beyond 5 % of the reference, tracked
    rows = modes.merge(tracked, on=["record", "freq_hz"])
    assert ((rows["mode_y"] == 1) == (rows["phi_0"].abs() > rows["phi_1"].abs())).all()


def test_a_shape_that_matches_no_reference_stays_untracked():
    """An estimate at a reference's frequency with another shape is not
    filed under that reference (nor under the reference of that shape, far
    away in frequency)."""
    references = pd.DataFrame({"mode": [1, 2], "freq_hz": [2.0, 6.0], "phi_0": [1.0, 0.0], "phi_1": [0.0, 1.0],
                               "phi_2": [0.0, 0.0]})
    modes = _modes([("r1", 2.0, _unit(0)), ("r2", 2.0, _unit(60)), ("r3", 2.0, _unit(90)), ("r4", 6.1, _unit(90))])
    tracked, untracked = track_modes(modes, references, freq_rtol=0.05, mac_min=0.8)
    assert sorted(zip(tracked["record"], tracked["mode"])) == [("r1", 1), ("r4", 2)]
    assert sorted(untracked["record"]) == ["r2", "r3"]


def test_report_bars_are_clipped_at_zero_and_damping_is_in_percent(tmp_path):
    """The lower bar of an estimate stops at zero; the report states one
    unit of damping and gives it in %, with the overview of every mode and
    frequency against the index's columns."""
    assert _interval(np.array([0.5, 2.0]), np.array([1.0, 0.1])).ravel() == \
        pytest.approx([0.5, 0.196, 1.96, 0.196])
    # no std: no bar; a negative value (never a frequency, a damping at most): no bar below it
    assert _interval(np.array([0.5, -0.2]), np.array([np.nan, 1.0])).ravel().tolist() == [0.0, 0.0, 0.0, 1.96]
    modes = _crossing(n=12)
    references = reference_modes(modes, n_records=12)
    tracked, untracked = track_modes(modes, references)
    covariates = pd.DataFrame({"record": [f"r{r:03d}" for r in range(12)], "temperature_c": np.linspace(-3, 20, 12)})
    failed = pd.DataFrame(columns=["record", "reason"])
    campaign_report(tmp_path / "report.html", tracked, untracked, failed, references, 12, "chunk: 5\n",
                    "modal campaign", covariates=covariates)
    text = (tmp_path / "report.html").read_text()
    assert "Damping in % of critical throughout" in text and "damping_mean_pct" in text
    assert "Every identified mode" in text and "Frequency against the index" in text
    assert text.count("<img") == 3


@pytest.fixture(scope="module")
def crossing(tmp_path_factory):
    """A year of 40 two-minute records of the frame whose x modes cross its
    y modes (x stiffness -2 %/K: x frequencies -14 % to +12 % around the
    y ones), identified as a campaign's chunk would be."""
    root = tmp_path_factory.mktemp("crossing")
    truth = simulate_campaign(root, n_records=40, every_hours=219.0, duration=120.0, structure="crossing",
                              damping=(0.01, 0.015, 0.01, 0.015))
    config, index = read_campaign(root / "campaign.yaml")
    identify_chunk(index, config["identify"], root / "modes.csv", root / "failed.csv", config["layout"])
    modes = pd.read_csv(root / "modes.csv")
    modes["time"] = pd.to_datetime(modes["time"])
    return modes, truth


def _truth_mode(tracked, modes, truth):
    """Each tracked estimate with the true mode its shape matches best (MAC
    with the truth's shapes at its record) and that MAC."""
    rows = tracked.merge(modes, on=["record", "freq_hz"], suffixes=("", "_identified"))
    best, best_mac = [], []
    columns = [c for c in truth.columns if c.startswith("phi_")]
    for _, row in rows.iterrows():
        at = truth[truth["record"] == row["record"]]
        similarity = mac(row[columns].to_numpy(dtype=float)[:, None], at[columns].to_numpy(dtype=float).T)[0]
        best.append(int(at["mode"].iloc[int(np.argmax(similarity))]))
        best_mac.append(float(similarity.max()))
    return rows.assign(truth=best, truth_mac=best_mac)


def _identified(modes, truth):
    """(record, true mode) -> the frequencies of the record's estimates of
    it: MAC >= 0.9 with its true shape, within 2 % of its true frequency."""
    columns = [c for c in truth.columns if c.startswith("phi_")]
    found = {}
    for record, at in truth.groupby("record"):
        estimates = modes[modes["record"] == record]
        if estimates.empty:
            continue
        similarity = mac(estimates[columns].to_numpy(dtype=float).T, at[columns].to_numpy(dtype=float).T)
        for k, mode in enumerate(at.itertuples()):
            near = np.abs(estimates["freq_hz"].to_numpy() / mode.freq_hz - 1) <= 0.02
            hits = estimates["freq_hz"].to_numpy()[near & (similarity[:, k] >= 0.9)]
            if len(hits):
                found[(record, int(mode.mode))] = set(hits.tolist())
    return found


@pytest.mark.slow
def test_crossing_modes_tracked_by_shape_in_a_simulated_campaign(crossing):
    """Without given references, each of the four modes is one reference,
    and no estimate is filed under the wrong mode (its shape's best match in
    the truth is the reference's mode). The first x and y modes (they cross
    at 10 C) are tracked in >= 90 % of the records where the identification
    found them, >= 80 % of all (near the crossing it misses one of them in
    some two-minute records)."""
    modes, truth = crossing
    references = reference_modes(modes, n_records=40)
    tracked, _ = track_modes(modes, references)
    rows = _truth_mode(tracked, modes, truth)
    mapping = rows.groupby("mode")["truth"].agg(lambda t: t.mode().iloc[0])
    assert sorted(mapping) == [1, 2, 3, 4]  # one reference per physical mode
    assert (rows["truth"] == rows["mode"].map(mapping)).all()  # no wrong assignment
    found = _identified(modes, truth)
    for physical in (1, 2):  # x and y first modes
        records = set(rows[rows["truth"] == physical]["record"])
        identified = {record for record, mode in found if mode == physical}
        assert len(records & identified) >= 0.9 * len(identified) and len(records) >= 32
    assert truth[truth["mode"] == 1]["freq_hz"].agg(lambda f: f.max() / f.min() - 1) > 0.15  # they did cross


@pytest.mark.slow
def test_true_references_follow_a_drift_beyond_five_percent(crossing):
    """With the true shapes and mean frequencies given, every mode the
    identification found in a record (:func:`_identified`) is tracked under
    its number, with one of its estimates, those more than 5 % from the
    reference frequency included."""
    modes, truth = crossing
    first = truth[truth["record"] == truth["record"].iloc[0]]
    references = pd.DataFrame({"mode": first["mode"].to_numpy(),
                               "freq_hz": truth.groupby("mode")["freq_hz"].mean().to_numpy(),
                               **{c: first[c].to_numpy() for c in first.columns if c.startswith("phi_")}})
    tracked, _ = track_modes(modes, references)
    by_mode = {(r, m): f for r, m, f in zip(tracked["record"], tracked["mode"], tracked["freq_hz"])}
    found = _identified(modes, truth)
    assert all(by_mode.get(key) in hits for key, hits in found.items())
    reference = dict(zip(references["mode"], references["freq_hz"]))
    drifted = [key for key in found if abs(by_mode[key] / reference[key[1]] - 1) > 0.05]
    assert len(drifted) >= 5  # drifted beyond 5 %, still tracked


def test_reference_modes_are_read_renumbered_by_frequency(tmp_path):
    """A reference file's modes: numbered 1, 2, ... by frequency (equal
    frequencies keep the file's order), its shape columns phi_... renamed
    phi_0, phi_1, ... in file order, other columns left out; a file without
    freq_hz or without shape columns is refused."""
    from modal.campaign import read_reference_modes

    (tmp_path / "r.csv").write_text("mode,freq_hz,phi_top,phi_mid,other\n7,5.0,0.1,-1,x\n3,2.0,1,0.5,y\n")
    table = read_reference_modes(tmp_path / "r.csv")
    assert table.to_dict("list") == {"mode": [1, 2], "freq_hz": [2.0, 5.0], "phi_0": [1.0, 0.1],
                                     "phi_1": [0.5, -1.0]}
    assert table["phi_0"].dtype == float and table["freq_hz"].dtype == float
    many = pd.DataFrame({"freq_hz": np.r_[2 * np.ones(50), np.ones(50)], "phi_a": np.arange(100)})
    many.to_csv(tmp_path / "many.csv", index=False)
    table = read_reference_modes(tmp_path / "many.csv")
    assert table["phi_0"].tolist() == list(range(50, 100)) + list(range(50))
    assert table["mode"].tolist() == list(range(1, 101))
    for text in ("freq,phi_0\n1.0,1.0\n", "freq_hz,shape\n1.0,1.0\n"):
        (tmp_path / "bad.csv").write_text(text)
        with pytest.raises(ValueError, match="bad.csv: reference modes need a freq_hz column and shape columns"):
            read_reference_modes(tmp_path / "bad.csv")


def test_large_campaigns_are_clustered_on_a_sample_of_records():
    """Over 1000 records, the references are built from 1000 of them, evenly
    spread in time, and the records counted for min_share scale alike: a
    mode in each of 1001 records of a 2002-record campaign is in 1000 of the
    sample, half of its 2000 records' share (kept at min_share 0.5). Records
    are counted, not estimates: 600 records of two modes are all clustered."""
    from modal.campaign._tracking import REFERENCE_SAMPLE

    assert REFERENCE_SAMPLE == 1000
    n = 1001  # two modes drifting slowly from 1 to 100 Hz, x and y: two chains of neighbours
    rows = [(f"r{r:04d}", float(100 ** (r / (n - 1))) * (1 + 0.001 * k), shape) for r in range(n)
            for k, shape in enumerate((X, Y))]
    modes = _modes(rows)
    references = reference_modes(modes, n_records=2 * n, min_share=0.5)
    assert references["n_records"].tolist() == [1000, 1000]
    assert references[["freq_low_hz", "freq_high_hz"]].to_numpy() == pytest.approx(np.array([[1.0, 100.0],
                                                                                             [1.001, 100.1]]))
    # the records kept: round(linspace(0, 1000, 1000)), all but r0500 (the floor would leave out r0999)
    assert references["freq_hz"].tolist() == pytest.approx([10.000106038, 10.010106144])
    assert reference_modes(modes, n_records=2 * n + 4, min_share=0.5).empty  # 2006 x 1000 / 1001 > 2000
    few = modes.iloc[:1200]  # 600 records: all clustered
    assert reference_modes(few, n_records=600)["n_records"].tolist() == [600, 600]


def test_the_reference_shape_is_the_medoid_of_at_most_400_evenly_spread():
    """A reference's shape is the estimate of largest summed MAC with the
    others (the medoid); of a 401-estimate cluster, 400 evenly spread are
    compared: index 399 in frequency order is left out. Here it is the
    central shape (400 others at +-5 degrees about it): with all 401
    compared it would be the reference."""
    from modal.campaign._tracking import MEDOID_SAMPLE

    assert MEDOID_SAMPLE == 400
    rows = [(f"r{k:03d}", 2.0 * (1 + 1e-5 * k), _unit(0 if k == 399 else (5 if k % 2 else -5))) for k in range(401)]
    references = reference_modes(_modes(rows), n_records=401)
    assert abs(references["phi_1"].iloc[0]) == pytest.approx(np.sin(np.radians(5)))
    assert reference_modes(_modes(rows[:400]), n_records=400)[["phi_0", "phi_1"]].to_numpy().tolist() == [[1.0, 0.0]]


def test_neighbours_are_pairs_within_both_gates_with_their_distance():
    """Two estimates are neighbours when f_j / f_i - 1 <= gap_rtol and MAC >=
    mac_min, both bounds included; distance: the frequency term over
    gap_rtol plus 1 - MAC over 1 - mac_min."""
    from modal.campaign._tracking import _neighbours

    f = np.array([2.0, 2.5, 3.0])
    unit = np.array([[1.0, 0.6, 0.0], [0.0, 0.8, 1.0]])  # MAC 0.36 between the first two, 0.64 the last two
    first, second, distance = _neighbours(f, unit, 0.25, 0.36)
    assert first.tolist() == [0, 1] and second.tolist() == [1, 2]
    assert distance == pytest.approx([0.25 / 0.25 + 0.64 / 0.64, 0.2 / 0.25 + 0.36 / 0.64])
    first, second, distance = _neighbours(f, unit, 0.5, 0.36)  # 3.0 / 2.0 - 1 = 0.5, but MAC 0
    assert first.tolist() == [0, 1] and second.tolist() == [1, 2]
    assert _neighbours(f, unit, 0.2, 0.5)[0].tolist() == [1]
    assert [a.tolist() for a in _neighbours(f[:1], unit[:, :1], 0.25, 0.36)] == [[], [], []]


def test_the_medoid_is_the_shape_closest_to_the_others_even_the_last():
    """Three estimates of one mode at +5, -5 and 0 degrees: the central one
    (largest summed MAC), though it is the last in frequency; of two, the
    first."""
    rows = [("r1", 2.0, _unit(5)), ("r2", 2.01, _unit(-5)), ("r3", 2.02, _unit(0))]
    references = reference_modes(_modes(rows), n_records=3)
    assert references[["phi_0", "phi_1"]].to_numpy().tolist() == [[1.0, 0.0]]
    references = reference_modes(_modes(rows[:2]), n_records=2)
    assert references["phi_1"].tolist() == pytest.approx([np.sin(np.radians(5))])


def test_a_mode_in_min_share_of_the_records_is_a_reference_and_empty_results_have_the_columns():
    """A cluster in 3 of 10 records is in 30 %, the default min_share: a
    reference (0.3 x 10 is 3.0000000000000004 in floating point); in 2 of
    10, not. No reference: the columns all the same."""
    rows = [(f"r{r}", 2.0 + 0.001 * r, X) for r in range(3)]
    assert reference_modes(_modes(rows), n_records=10)["n_records"].tolist() == [3]
    assert reference_modes(_modes(rows[:2]), n_records=10).empty
    assert reference_modes(_modes(rows[:1]), n_records=1, min_share=0.6)["n_records"].tolist() == [1]
    columns = ["mode", "freq_hz", "n_records", "freq_low_hz", "freq_high_hz"]
    assert list(reference_modes(_modes(rows[:2]), n_records=10).columns) == columns
    assert list(reference_modes(_modes(rows).iloc[:0], n_records=10).columns) == columns


def _join(label, f, shapes, record, freq_rtol=0.05, mac_min=0.8, damping=None):
    from modal.campaign._tracking import _join_split_modes

    joined = _join_split_modes(np.array(label), np.array(f), np.array(shapes).T, np.array(record), freq_rtol,
                               mac_min, None if damping is None else np.array(damping))
    return [sorted(np.flatnonzero(joined == k).tolist()) for k in dict.fromkeys(joined)]


def test_split_clusters_join_within_the_frequency_margin_bounds_included():
    """Clusters of one shape join when their frequency ranges lie within
    freq_rtol of each other, the bound included, whichever is larger."""
    shapes = [X] * 5
    # the smaller (2.5 Hz) lies exactly 25 % above the larger (2.0 Hz): joined at 0.25, not at 0.24
    assert _join([0, 0, 0, 1, 1], [2.0] * 3 + [2.5] * 2, shapes, list("abcde"), freq_rtol=0.25) == [[0, 1, 2, 3, 4]]
    assert _join([0, 0, 0, 1, 1], [2.0] * 3 + [2.5] * 2, shapes, list("abcde"), freq_rtol=0.24) == [[0, 1, 2],
                                                                                                     [3, 4]]
    # the smaller (2.0 Hz) lies exactly 20 % below the larger (2.5 Hz)
    assert _join([0, 0, 1, 1, 1], [2.0] * 2 + [2.5] * 3, shapes, list("abcde"), freq_rtol=0.2) == [[0, 1, 2, 3, 4]]
    assert _join([0, 0, 1, 1, 1], [2.0] * 2 + [2.5] * 3, shapes, list("abcde"), freq_rtol=0.19) == [[0, 1], [2, 3, 4]]


def test_split_clusters_join_by_shape_and_shared_records_largest_first():
    """A cluster joins the kept one whose medoid matches its own best, MAC >=
    mac_min (bound included), sharing at most SPLIT_SHARE (20 %) of its
    records (bound included), the larger clusters taken first; a kept one
    that shares too many is passed over for the next; a joined cluster's
    records count for those that follow."""
    x3, x4 = (0.6, 0.8, 0.0), (1.0, 0.0, 0.0)  # MAC 0.36
    assert _join([0, 0, 1], [2.0, 2.0, 2.01], [x4, x4, x3], list("abc"), mac_min=0.36) == [[0, 1, 2]]
    assert _join([0, 0, 1], [2.0, 2.0, 2.01], [x4, x4, x3], list("abc"), mac_min=0.37) == [[0, 1], [2]]
    # a 5-record cluster sharing 1 record (20 %) with the larger joins; sharing 2 (40 %) it does not
    big = [f"r{k}" for k in range(10)]
    assert _join([0] * 10 + [1] * 5, [2.0] * 15, [X] * 15, big + ["r0", "s1", "s2", "s3", "s4"]) == [list(range(15))]
    assert _join([0] * 10 + [1] * 5, [2.0] * 15, [X] * 15, big + ["r0", "r1", "s2", "s3", "s4"]) == \
        [list(range(10)), list(range(10, 15))]
    # largest first: 3 records sharing one with 10 (a third of its own) stay apart, though that is a tenth of 10
    assert _join([1] * 3 + [0] * 10, [2.0] * 13, [X] * 13, ["r0", "s1", "s2"] + big) == [[0, 1, 2],
                                                                                        list(range(3, 13))]
    # the first kept shares too many records (the 6 share 2 with the 10 and stay apart); the next one takes it
    labels, f, shapes = [0] * 10 + [1] * 6 + [2] * 3, [2.0] * 19, [X] * 19
    record = big + ["r0", "r1", "t2", "t3", "t4", "t5"] + ["r2", "r3", "s"]
    assert _join(labels, f, shapes, record) == [list(range(10)), list(range(10, 19))]
    # the first kept lies elsewhere in frequency (5 Hz); the next one (2 Hz) takes the 2.01 Hz cluster
    f = [5.0] * 10 + [2.0] * 6 + [2.01] * 3
    assert _join(labels, f, shapes, big + [f"t{k}" for k in range(6)] + ["s0", "s1", "s2"]) == [list(range(10)),
                                                                                               list(range(10, 19))]
    f = [2.0] * 19
    record = big + [f"t{k}" for k in range(6)] + ["r0", "r1", "s"]  # the 6 join the 10; the 3 share 2 with them
    assert _join(labels, f, shapes, record) == [list(range(16)), [16, 17, 18]]
    record = big + ["u0", "u1", "u2", "u3", "u4", "u5"] + ["u0", "u1", "s"]  # shared with the 6 that joined
    assert _join(labels, f, shapes, record) == [list(range(16)), [16, 17, 18]]


def test_observed_ranges_bounds_defaults_and_each_reference():
    """The band: estimates whose MAC with the reference is >= mac_min (bound
    included), cut where neighbours lie more than freq_rtol apart (a step of
    exactly freq_rtol is not a cut); a reference without a matching estimate
    keeps its own frequency and the next is still looked at; the defaults
    are freq_rtol 0.05 and mac_min 0.8; the references given are left as
    they are; integer frequencies give float bounds."""
    x3 = (0.6, 0.8, 0.0)  # MAC 0.36 with x
    references = pd.DataFrame({"mode": [1, 2], "freq_hz": [7, 2], "phi_0": [0.0, 1.0], "phi_1": [0.0, 0.0],
                               "phi_2": [1.0, 0.0]})
    modes = _modes([("r1", 2.0, X), ("r2", 2.5, x3), ("r3", 1.98, X)])
    out = observed_ranges(modes, references, freq_rtol=0.25, mac_min=0.36)
    assert out[["freq_low_hz", "freq_high_hz"]].to_numpy().tolist() == [[7.0, 7.0], [1.98, 2.5]]
    assert out["freq_low_hz"].dtype == float and list(references.columns) == ["mode", "freq_hz", "phi_0", "phi_1",
                                                                              "phi_2"]
    assert observed_ranges(modes, references, freq_rtol=0.25, mac_min=0.37)["freq_high_hz"].tolist() == [7.0, 2.0]
    assert observed_ranges(modes, references, freq_rtol=0.24, mac_min=0.36)["freq_high_hz"].tolist() == [7.0, 2.0]
    # defaults: 2.05 lies 2.5 % above 2.0 (a step within 5 %), 2.2 Hz 7.3 % above it; MAC 0.81 matches, 0.79 not
    modes = _modes([("r1", 2.0, X), ("r2", 2.05, _unit(np.degrees(np.arccos(0.9)))),
                    ("r3", 2.2, X), ("r4", 1.9, _unit(np.degrees(np.arccos(np.sqrt(0.79)))))])
    assert observed_ranges(modes, references)[["freq_low_hz", "freq_high_hz"]].to_numpy().tolist() == \
        [[7.0, 7.0], [2.0, 2.05]]
    # the nearest matching estimate exactly freq_rtol from the reference: a band; beyond it none, and the next
    # reference is still looked at
    two = pd.DataFrame({"mode": [1, 2], "freq_hz": [1.5, 2.0], "phi_0": [1.0, 1.0], "phi_1": [0.0, 0.0],
                        "phi_2": [0.0, 0.0]})
    out = observed_ranges(_modes([("r1", 2.5, X)]), two, freq_rtol=0.25)
    assert out[["freq_low_hz", "freq_high_hz"]].to_numpy().tolist() == [[1.5, 1.5], [2.0, 2.5]]
    no_modes = pd.DataFrame(columns=["record", "time", "mode", "freq_hz"])  # as gathered from no chunk
    assert observed_ranges(no_modes, references)["freq_high_hz"].tolist() == [7.0, 2.0]


def test_tracking_gates_include_their_bounds_and_mac_decides_before_frequency():
    """An estimate exactly at the gate's lower or upper frequency, or at MAC
    = mac_min, is tracked; of two estimates of equal MAC the one nearer the
    reference frequency is taken, whichever comes first, and the frequency
    never outweighs MAC (0.99 at 25 % off beats 0.85 at the reference
    frequency); beyond 100 % off, frequency no longer tells them apart."""
    x3 = (0.6, 0.8, 0.0)  # MAC 0.36 with x
    references = pd.DataFrame({"mode": [4], "freq_hz": [2.0], "freq_low_hz": [2.0], "freq_high_hz": [2.0],
                               "phi_0": [1.0], "phi_1": [0.0], "phi_2": [0.0]})
    modes = _modes([("r1", 1.5, X), ("r2", 2.5, X), ("r3", 2.0, x3), ("r4", 1.49, X), ("r5", 2.51, X)])
    tracked, untracked = track_modes(modes, references, freq_rtol=0.25, mac_min=0.36)
    assert tracked["record"].tolist() == ["r1", "r2", "r3"] and (tracked["mode"] == 4).all()
    assert tracked["mac"].tolist() == pytest.approx([1.0, 1.0, 0.36])
    assert untracked["record"].tolist() == ["r4", "r5"]
    assert list(untracked.columns) == list(modes.columns) and untracked.index.tolist() == [0, 1]
    # equal MAC: the nearer frequency, listed second
    modes = _modes([("r1", 2.3, X), ("r1", 2.1, X)])
    assert track_modes(modes, references, freq_rtol=0.25)[0]["freq_hz"].tolist() == [2.1]
    modes = _modes([("r1", 1.8, X), ("r1", 1.9, X)])
    assert track_modes(modes, references, freq_rtol=0.25)[0]["freq_hz"].tolist() == [1.9]
    modes = _modes([("r1", 2.0, _unit(22.8)), ("r1", 2.5, _unit(5.7))])  # MAC 0.85 and 0.99
    assert track_modes(modes, references, freq_rtol=0.25)[0]["freq_hz"].tolist() == [2.5]
    wide = references.assign(freq_high_hz=4.0)  # 5.2 and 7.0 Hz: 160 % and 250 % off: alike, the first taken
    assert track_modes(_modes([("r1", 7.0, X), ("r1", 5.2, X)]), wide, freq_rtol=0.8)[0]["freq_hz"].tolist() == [7.0]


def test_tracking_refuses_other_channels_and_returns_its_own_tables():
    """Shapes over other channels than the references' are refused; the
    untracked table is a table of its own, never the caller's."""
    references = pd.DataFrame({"mode": [1], "freq_hz": [2.0], "phi_0": [1.0], "phi_1": [0.0]})
    modes = _modes([("r1", 2.0, X)])
    with pytest.raises(ValueError, match="the records' shapes have 3 channels, the reference modes 2"):
        track_modes(modes, references)
    tracked, untracked = track_modes(modes, references.iloc[:0])  # no reference: every mode untracked
    assert tracked.empty and list(tracked.columns) == TRACKED_COLUMNS
    untracked["freq_hz"] = 0.0
    assert modes["freq_hz"].tolist() == [2.0]


def test_a_rarer_first_cluster_does_not_hide_the_next():
    """Each cluster is judged on its own records: the first (10 estimates of
    x at 2 Hz in 10 of 21 records) is under min_share 0.5, the next (y at 3
    Hz, split in two by record s0 showing it twice, 3.00 and 3.01 Hz, then
    joined: 12 estimates in 11 records) is a reference."""
    rows = [(f"r{k}", 2.0 + 1e-4 * k, X) for k in range(10)]
    rows += [(f"s{k}", 3.0 + 1e-5 * k, Y) for k in range(6)]
    rows += [("s0", 3.01, Y)] + [(f"t{k}", 3.01 + 1e-5 * k, Y) for k in range(1, 6)]
    references = reference_modes(_modes(rows), n_records=21, min_share=0.5)
    assert references["n_records"].tolist() == [11] and references["freq_low_hz"].tolist() == [3.0]


def test_the_report_summary_per_reference_mode():
    """One row per reference: its frequency as reference_hz and its range
    (no shape, no n_records), the records it was tracked in and their share
    of the identified ones in %, the median std of a frequency, mean damping
    and median damping std in %, the median MAC; a reference never tracked
    has 0 and no statistics."""
    from modal.campaign._report import mode_summary

    references = pd.DataFrame({"mode": [1, 2], "freq_hz": [2.0, 5.0], "n_records": [3, 1],
                               "freq_low_hz": [1.9, 5.0], "freq_high_hz": [2.1, 5.0], "phi_0": [1.0, 0.0],
                               "phi_1": [0.0, 1.0]})
    tracked = pd.DataFrame({"record": ["a", "b", "c", "c"], "mode": [1, 1, 1, 1], "freq_hz": 2.0,
                            "freq_std_hz": [0.01, 0.02, 0.04, 0.03], "damping": [0.01, 0.02, 0.03, 0.02],
                            "damping_std": [0.001, 0.002, 0.004, 0.003], "mac": [0.9, 0.95, 0.99, 0.97]})
    summary = mode_summary(tracked, references, n_identified=8)
    assert list(summary.columns) == ["mode", "reference_hz", "freq_low_hz", "freq_high_hz", "tracked_in",
                                     "tracked_share_pct", "median_freq_std_hz", "damping_mean_pct",
                                     "median_damping_std_pct", "median_mac"]
    first = summary.iloc[0]
    assert first["reference_hz"] == 2.0 and first["tracked_in"] == 3 and first["tracked_share_pct"] == 37.5
    assert first["median_freq_std_hz"] == pytest.approx(0.025) and first["damping_mean_pct"] == pytest.approx(2.0)
    assert first["median_damping_std_pct"] == pytest.approx(0.25) and first["median_mac"] == pytest.approx(0.96)
    assert summary["tracked_in"].tolist() == [3, 0] and summary["tracked_in"].dtype == int
    assert summary.iloc[1][["median_freq_std_hz", "damping_mean_pct", "median_mac"]].isna().all()
    assert mode_summary(tracked, references, n_identified=0)["tracked_share_pct"].tolist() == [300.0, 0.0]
    assert list(mode_summary(tracked.iloc[:0], references, 8).columns) == ["mode", "reference_hz", "freq_low_hz",
                                                                           "freq_high_hz"]


def test_a_mode_some_records_show_twice_within_its_peak_is_one_reference():
    """A mode at 6.2 Hz (damping 1.7 %) in 12 records, 4 of which show it a
    second time 2 % higher (damping 1.2 %), with the same shape: one
    reference, not two, though the second cluster shares every record with
    the first (the second estimate lies within the resonance peak: 0.124 Hz
    apart, half-power half-widths 0.105 + 0.076 Hz). The bound: clusters
    whose median frequencies lie exactly the sum of their half-widths apart
    join, a little more and (sharing their records) they stay two; without
    damping the rule is not applied."""
    rng = np.random.default_rng(2)
    rows = [(f"r{r:03d}", 6.2 * (1 + 0.002 * rng.standard_normal()), _unit(2 * rng.standard_normal()))
            for r in range(12)]
    rows += [(f"r{r:03d}", 6.324 * (1 + 0.002 * rng.standard_normal()), _unit(2 * rng.standard_normal()))
             for r in (1, 4, 7, 10)]
    modes = _modes(rows)
    modes["damping"] = [0.017] * 12 + [0.012] * 4
    references = reference_modes(modes, n_records=12)
    assert references["n_records"].tolist() == [12]
    tracked, untracked = track_modes(modes, references)
    assert len(tracked) == 12 and len(untracked) == 4
    # the bound: 2.0 Hz at 1 % and 2.06 Hz at 2 %: 0.02 + 0.0412 = 0.0612 Hz of half-widths
    shapes, record = [X] * 6, ["a", "b", "c", "a", "b", "c"]
    for gap, together in ((0.0612 / 1.0106, True), (0.062, False)):
        f = [2.0] * 3 + [2.0 + gap] * 3
        damping = [0.01] * 3 + [0.0412 / f[3]] * 3
        assert _join([0] * 3 + [1] * 3, f, shapes, record, damping=damping) == \
            ([list(range(6))] if together else [[0, 1, 2], [3, 4, 5]]), gap
    assert _join([0] * 3 + [1] * 3, [2.0] * 3 + [2.03] * 3, shapes, record) == [[0, 1, 2], [3, 4, 5]]


def test_a_simulated_twelve_record_campaign_has_one_reference_per_mode(tmp_path):
    """Twelve two-minute records of the four-storey frame in June: some
    records show the 6.2 Hz mode twice (two trusted estimates a few % apart,
    both of its shape, MAC 0.998 with each other), which split it into two
    references (6.20 Hz in 11 records, 6.32 Hz in 4) before clusters within
    one resonance peak were joined: four references, one per mode."""
    simulate_campaign(tmp_path, n_records=12, every_hours=12.0, duration=120.0, start="2025-06-01 00:00")
    config, index = read_campaign(tmp_path / "campaign.yaml")
    identify_chunk(index, config["identify"], tmp_path / "modes.csv", tmp_path / "failed.csv", config["layout"])
    modes = pd.read_csv(tmp_path / "modes.csv")
    references = reference_modes(modes, n_records=12)
    assert references["freq_hz"].tolist() == pytest.approx([1.574, 4.173, 6.2, 7.805], rel=0.01)
    assert references["n_records"].min() >= 11
