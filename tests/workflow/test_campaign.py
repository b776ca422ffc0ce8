"""Monitoring campaigns: the workflow of ``modal campaign`` on a simulated
shear frame whose frequencies follow the temperature (known at every
record), failures listed and the campaign going on, resuming, growing with
the index, tracking and the configuration's refusals."""

import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
import modal.campaign
from modal.campaign import read_campaign, reference_modes, simulate_campaign, track_modes
from modal.cli import main as cli
from modal.measured import OutputError
from tests.browser import assert_readable, rendered


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """30 two-minute records every 12 h, plus three that fail or hold no
    response: a file that is not a record, a listed file that does not
    exist, and pure noise (no mode, not a failure)."""
    root = tmp_path_factory.mktemp("campaign")
    truth = simulate_campaign(root, n_records=30, every_hours=12, duration=120.0)
    (root / "records" / "broken.csv").write_text("time,a\nyesterday,abc\n")
    noise = np.random.default_rng(5).standard_normal((6000, 4))
    np.savez(root / "records" / "noise.npz", acc=noise, fs=50.0)
    index = pd.read_csv(root / "index.csv")
    extra = pd.DataFrame({"path": ["records/broken.csv", "records/missing.npz", "records/noise.npz"],
                          "time": ["2025-03-01T00:00:00", "2025-03-02T00:00:00", "2025-03-03T00:00:00"]})
    pd.concat([index, extra]).to_csv(root / "index.csv", index=False)
    out = root / "out"
    assert cli(["campaign", str(root / "campaign.yaml"), "--out", str(out), "--cores", "2"]) == 0
    return root, out, truth


def test_tracked_modes_follow_the_temperature(campaign):
    """Every record's modes are tracked under the number of the frame's
    mode they are: within 2.5 % of its frequency at that record's
    temperature, 0.6 % on average (two-minute records: the estimates
    scatter by some 0.4 %)."""
    root, out, truth = campaign
    tracked = pd.read_csv(out / "tracked.csv")
    assert list(tracked.columns) == ["record", "time", "mode", "freq_hz", "freq_std_hz", "damping", "damping_std",
                                     "mac"]
    joined = tracked.merge(truth, on=["record", "mode"], suffixes=("", "_true"))
    assert len(joined) == len(tracked)  # no tracked mode outside the truth's numbering
    error = np.abs(joined["freq_hz"] / joined["freq_hz_true"] - 1)
    assert error.max() < 0.025 and error.mean() < 0.006
    per_mode = tracked.groupby("mode")["record"].nunique()
    assert per_mode[1] == 30 and per_mode[2] == 30 and per_mode.min() >= 15
    assert (tracked["mac"] >= 0.8).all()
    modes = pd.read_csv(out / "modes.csv")
    assert modes.groupby("record")["mode"].apply(lambda m: m.is_unique).all()  # each record identified once
    span = truth.groupby("mode")["freq_hz"].agg(lambda f: f.max() / f.min() - 1)
    assert span[1] > 0.003  # the frequencies did move with the temperature


def test_each_tracked_modes_mean_shape_is_its_true_shape_drawn_on_the_frame(campaign):
    """tracked_shapes.csv holds each tracked mode's mean shape: the frame's
    shape of that mode (MAC >= 0.99 with the truth, below 0.2 with the other
    modes'), and the report draws them on the campaign's geometry."""
    from modal.identification import mac

    root, out, truth = campaign
    shapes = pd.read_csv(out / "tracked_shapes.csv")
    tracked = pd.read_csv(out / "tracked.csv")
    assert shapes["mode"].tolist() == sorted(tracked["mode"].unique())
    assert shapes["n_estimates"].tolist() == tracked.groupby("mode").size().tolist()
    phi = [f"phi_{k}" for k in range(4)]
    true = truth.groupby("mode")[phi].first()
    similarity = mac(shapes[phi].to_numpy().T, true.loc[shapes["mode"]].to_numpy().T)
    assert np.diag(similarity).min() >= 0.99
    assert (similarity - np.diag(np.diag(similarity))).max() < 0.2
    assert np.allclose(np.linalg.norm(shapes[phi].to_numpy(), axis=1), 1.0)
    report = (out / "report.html").read_text()
    section = report.split("<h2>Tracked shapes</h2>")[1].split("<h2>")[0]
    assert "alt='tracked shapes on the structure'" in section and "data:image/png;base64," in section


def test_failed_records_are_listed_and_the_campaign_goes_on(campaign):
    root, out, _ = campaign
    failed = pd.read_csv(out / "failed.csv").set_index("record")
    assert set(failed.index) == {"records/broken.csv", "records/missing.npz"}
    assert "missing.npz" in failed.loc["records/missing.npz", "reason"]
    modes = pd.read_csv(out / "modes.csv")
    assert "records/noise.npz" not in set(modes["record"])  # no structural response: no mode, no failure
    report = (out / "report.html").read_text()
    assert "33</b> records" in report and "broken.csv" in report
    assert "campaign.yaml" not in report.split("Provenance")[0]  # not a record; named only as the command run
    assert "data:image/png;base64," in report and "Provenance" in report


def test_report_reads_in_a_browser(campaign):
    """Opened in Chromium in a laptop's window: the four pictures (every
    mode over time, the tracked modes, frequency against the temperature,
    the tracked shapes) decode and show, nothing is fetched from elsewhere,
    no sideways scrolling; one row per tracked mode and per failed record."""
    _, out, _ = campaign
    seen = rendered(out / "report.html")
    assert_readable(seen, images=4)
    rows = sorted(t["rows"] for t in seen["tables"])
    assert rows == sorted([1 + pd.read_csv(out / "tracked.csv")["mode"].nunique(),
                           1 + len(pd.read_csv(out / "failed.csv"))])


def test_a_rerun_resumes_and_new_records_add_only_their_jobs(campaign, tmp_path):
    """Run again: nothing to do. Records appended to the index (later in
    time) add their chunk; the chunks before it are not rerun."""
    root, out, _ = campaign
    stamps = {p: p.stat().st_mtime_ns for p in (out / "chunks").glob("*/modes.csv")}
    assert cli(["campaign", str(root / "campaign.yaml"), "--out", str(out)]) == 0
    assert {p: p.stat().st_mtime_ns for p in (out / "chunks").glob("*/modes.csv")} == stamps
    more = tmp_path / "more"
    simulate_campaign(more, n_records=3, every_hours=12, duration=120.0, start="2025-06-01 00:00", seed=99)
    for p in (more / "records").iterdir():
        shutil.copy(p, root / "records" / p.name)
    index = pd.concat([pd.read_csv(root / "index.csv"), pd.read_csv(more / "index.csv")])
    index.to_csv(root / "index.csv", index=False)
    assert cli(["campaign", str(root / "campaign.yaml"), "--out", str(out)]) == 0
    after = {p: p.stat().st_mtime_ns for p in (out / "chunks").glob("*/modes.csv")}
    assert len(after) == len(stamps) == 2  # 36 records in chunks of 25
    changed = sorted(p.parent.name for p in after if after[p] != stamps.get(p))
    assert changed == ["c00001"]  # the last chunk grew; c00000 was not rerun
    assert pd.read_csv(out / "tracked.csv")["record"].nunique() == 33


def test_campaign_file_refusals(tmp_path, capsys):
    def refused(text, message):
        path = tmp_path / "c.yaml"
        path.write_text(text)
        assert cli(["campaign", str(path), "--out", str(tmp_path / "out")]) == 2
        assert message in capsys.readouterr().err
    refused("records: {index: i.csv}\nidentify: {excitation: ambient, fmx: 3}\n", "Additional properties")
    refused("records: {index: i.csv, glob: '*.npy'}\nidentify: {excitation: ambient}\n",
            "give either index (a CSV of path,time) or glob with time_format")
    refused("records: {glob: '*.npy', time_format: '%Y'}\nidentify: {excitation: ambient, max_order: 7}\n",
            "identify.max_order")
    refused("records: {index: i.csv}\nidentify: {excitation: ambient, fmax: .nan}\n",
            "identify.fmax: nan is not a finite number")
    refused("records: {index: i.csv}\nidentify: {excitation: ambient}\ntracking: {freq_rtol: .inf}\n",
            "tracking.freq_rtol")
    (tmp_path / "i.csv").write_text("path,time\na.npy,noon\n")
    refused("records: {index: i.csv}\nidentify: {excitation: ambient}\n",
            "row 2: time 'noon' does not follow ISO 8601")
    # Settings every record would fail alike: refused before any job (the layout
    # the records that read agree on is checked; one that does not read is left to its job).
    modal.save_record_npz(tmp_path / "b.npz", np.random.default_rng(0).standard_normal((2000, 3)), 0.05)
    (tmp_path / "i.csv").write_text("path,time\nbroken.npz,2025-01-01\nb.npz,2025-01-02\n")
    (tmp_path / "broken.npz").write_text("not a record")
    base = "records: {index: i.csv}\nidentify: {excitation: ambient, "
    refused(base + "fmax: 10}\n", "identify.fmax = 10 Hz must be below the Nyquist frequency 10 Hz (fs = 20 Hz) "
                                  "(the campaign's records: 3 channels at 20 Hz, as b.npz of the 1 read)")
    refused(base + "channels: [0, 3]}\n", "identify.channels [3]: the record has channels 0 ... 2")
    refused(base + "fmax: 5, highpass_hz: 5}\n", "identify.highpass_hz = 5 Hz must be below fmax = 5 Hz")
    refused(base + "rows: 30.0}\n", "identify.rows must be an integer, got 30.0")
    # an identify.fs that the records' own rate contradicts: no record reads with it
    refused(base + "fs: 50}\n", "identify.fs = 50 Hz contradicts the rate the records hold (as b.npz, and no record "
                               "read with it): leave identify.fs out")
    (tmp_path / "c.yaml").write_text(base + "fs: 20}\n")
    assert read_campaign(tmp_path / "c.yaml")[0]["identify"]["fs"] == 20  # the records' own rate: taken
    # rows whose lags the records cannot hold (the longest read decides: a shorter one fails alone in its job)
    refused(base + "rows: 600}\n", "identify.rows = 600 needs 1201 lags, more than half the 2000-sample record: "
                                 "give rows = 499 at the most or a longer record (the campaign's records: 3 channels")
    refused(base + "fmax: 0.5}\n", "identify.fmax = 0.5 Hz decimates the 2000-sample record by 16 to 125 samples, "
                                 "fewer than the 242 the identification needs (60 rows: 121 lags): fmax must be above "
                                 "0.8889 Hz for this record (or give rows = 30 at the most or a longer record)")
    modal.save_record_npz(tmp_path / "c.npz", np.random.default_rng(1).standard_normal((4000, 3)), 0.05)
    (tmp_path / "i.csv").write_text("path,time\nbroken.npz,2025-01-01\nb.npz,2025-01-02\nc.npz,2025-01-03\n")
    refused(base + "rows: 1000}\n", "identify.rows = 1000 needs 2001 lags, more than half the 4000-sample record: "
                                  "give rows = 999 at the most or a longer record (the longest record read: c.npz)")
    (tmp_path / "c.yaml").write_text(base + "rows: 600}\n")
    assert read_campaign(tmp_path / "c.yaml")[0]["identify"]["rows"] == 600
    (tmp_path / "i.csv").write_text("path,time\nbroken.npz,2025-01-01\nb.npz,2025-01-02\n")
    assert read_campaign_ok(tmp_path, base + "fmax: 9.9}\n")
    assert not (tmp_path / "out").exists()


def read_campaign_ok(folder, text) -> bool:
    (folder / "c.yaml").write_text(text)
    config, index = read_campaign(folder / "c.yaml")
    return config["identify"]["fmax"] == 9.9 and len(index) == 2


def test_glob_with_times_in_the_names(tmp_path):
    """Records are ordered by the time in their names, not by name."""
    for name in ("a_20250102-0600.npy", "b_20250101-1800.npy"):
        np.save(tmp_path / name, np.zeros((10, 2)))
    (tmp_path / "c.yaml").write_text("records: {glob: '*_*.npy', time_format: '%Y%m%d-%H%M', "
                                     "time_regex: '_(\\d{8}-\\d{4})'}\nidentify: {excitation: ambient, fs: 10}\n")
    config, index = read_campaign(tmp_path / "c.yaml")
    assert list(index["record"]) == ["b_20250101-1800.npy", "a_20250102-0600.npy"]
    assert index["time"].iloc[0] == pd.Timestamp("2025-01-01 18:00")
    assert config["tracking"]["freq_rtol"] == 0.05 and config["chunk"] == 50


def _modes(rows):
    return pd.DataFrame([{"record": r, "time": pd.Timestamp("2025-01-01"), "mode": k, "freq_hz": f,
                          "freq_std_hz": 0.01, "damping": 0.01, "damping_std": 0.001, "phi_0": s[0], "phi_1": s[1]}
                         for r, k, f, s in rows])


def test_tracking_is_one_to_one_and_gated():
    """References from the campaign: clusters of estimates close in frequency
    and shape found in enough records. A record's modes match them one to
    one by shape within their frequency range; a mode outside both gates
    stays untracked."""
    up, apart = (1.0, 1.0), (1.0, -1.0)
    modes = _modes([("a", 1, 2.00, up), ("a", 2, 5.00, apart), ("b", 1, 2.01, up), ("b", 2, 5.04, apart),
                    ("c", 1, 1.995, up), ("c", 2, 2.015, apart), ("c", 3, 9.0, up), ("d", 1, 2.01, apart),
                    ("e", 1, 7.0, up)])
    references = reference_modes(modes, n_records=5, min_share=0.4)
    # 1.995-2.01 Hz "up" (3 records), 2.01-2.015 Hz "apart" (2: a mode of its own, by its shape), 5.00-5.04 Hz
    # "apart" (2); 7 and 9 Hz "up", 29 % apart, one record each: not references
    assert list(references["n_records"]) == [3, 2, 2]
    assert references["freq_hz"].tolist() == pytest.approx([2.0, 2.0125, 5.02])  # the medians
    assert references[["freq_low_hz", "freq_high_hz"]].to_numpy().tolist() == [[1.995, 2.01], [2.01, 2.015],
                                                                               [5.0, 5.04]]
    assert references[["phi_0", "phi_1"]].to_numpy().tolist() == [list(up), list(apart), list(apart)]  # medoids
    tracked, untracked = track_modes(modes, references, freq_rtol=0.05, mac_min=0.8)
    assert sorted(zip(tracked["record"], tracked["mode"])) == [("a", 1), ("a", 3), ("b", 1), ("b", 3), ("c", 1),
                                                               ("c", 2), ("d", 2)]
    # 7 and 9 Hz have mode 1's shape, but lie far beyond the frequencies observed for it
    assert sorted(zip(untracked["record"], untracked["freq_hz"])) == [("c", 9.0), ("e", 7.0)]


@pytest.mark.slow
def test_run_is_the_entry_point_resumes_and_raises_when_a_job_fails(tmp_path):
    """``modal.campaign.run`` (what ``modal campaign`` calls) writes every
    job's log and names its call in the report; run again, with other
    cores, it reruns nothing and says what it did. A reference file that is
    not a table of modes is refused before any job. A job that fails (here
    the tracking, on a chunk's file whose time is not one) raises
    ``WorkflowStopped`` with Snakemake's exit code and where its log is; the
    identification jobs are kept."""
    simulate_campaign(tmp_path, n_records=3, every_hours=12, duration=120.0)
    out = tmp_path / "out"
    assert modal.campaign.run(tmp_path / "campaign.yaml", out, cores=2) == out
    assert "modal.campaign.run(" in (out / "report.html").read_text()
    assert [p.name for p in (out / "logs" / "identify_chunk").iterdir()] == ["c00000.log"]
    assert (out / "logs" / "track.log").is_file() and (out / "logs" / "report.log").is_file()
    stamps = {p: p.stat().st_mtime_ns for p in [*out.glob("**/*.csv"), out / "report.html"]}
    messages = []
    modal.campaign.run(tmp_path / "campaign.yaml", out, log=messages.append)
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps
    assert messages == ["3 records in 1 chunks of up to 25",
                        f"nothing to do: {out / 'tracked.csv'} and {out / 'report.html'} were up to date"]
    # a reference file that is not a table of modes: refused before any job (nothing rerun)
    (tmp_path / "bad.csv").write_text("not,modes\n1,2\n")
    (tmp_path / "bad.yaml").write_text((tmp_path / "campaign.yaml").read_text() +
                                       "tracking: {reference_modes: bad.csv}\n")
    with pytest.raises(ValueError, match="bad.yaml: tracking.reference_modes: .*bad.csv: reference modes need"):
        modal.campaign.run(tmp_path / "bad.yaml", out)
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps
    # a chunk's file overwritten with a time that is not one: the tracking fails
    chunk = out / "chunks" / "c00000" / "modes.csv"
    chunk.write_text("record,time,freq_hz\nx,yesterday,1.0\n")
    stamp = chunk.stat().st_mtime_ns
    with pytest.raises(modal.campaign.WorkflowStopped) as stopped:
        modal.campaign.run(tmp_path / "campaign.yaml", out)
    assert stopped.value.returncode != 0 and stopped.value.log == out / ".snakemake" / "log"
    assert chunk.stat().st_mtime_ns == stamp  # the identification was not rerun
    assert "Error" in (out / "logs" / "track.log").read_text()


def test_run_plans_and_refuses_before_any_job(tmp_path):
    """A dry run plans into a new folder and writes no result; bad options
    are refused before the output folder is made."""
    simulate_campaign(tmp_path / "c", n_records=2, duration=60.0)
    config = tmp_path / "c" / "campaign.yaml"
    plan = tmp_path / "plan"
    assert modal.campaign.run(config, plan, dry_run=True) == plan
    assert not list(plan.glob("*.csv")) and not (plan / "chunks").exists()
    with pytest.raises(OutputError, match="is the input"):
        modal.campaign.run(config, config)
    (tmp_path / "file").write_text("mine")
    with pytest.raises(OutputError, match="exists and is a file, not a folder"):
        modal.campaign.run(config, tmp_path / "file")
    with pytest.raises(ValueError, match="profile"):
        modal.campaign.run(config, tmp_path / "out", profile=tmp_path / "no-profile")
    with pytest.raises(ValueError, match="cores"):
        modal.campaign.run(config, tmp_path / "out", cores=0)
    (tmp_path / "c.yaml").write_text("records: {index: i.csv}\nidentify: {excitation: sideways}\n")
    with pytest.raises(ValueError, match="identify"):
        modal.campaign.run(tmp_path / "c.yaml", tmp_path / "out")
    assert not (tmp_path / "out").exists()


def _csv_records(folder, n=3, seconds=120.0, fs=50.0):
    """``n`` records of the simulated frame as CSV files named by their time (one a day)."""
    simulate_campaign(folder / "sim", n_records=n, every_hours=24, duration=seconds, fs=fs)
    for k, path in enumerate(sorted((folder / "sim" / "records").glob("*.npz"))):
        acc = modal.read_record(path).acc
        target = folder / "data" / f"day{k}" / f"r_202501{k + 1:02d}-0000.csv"
        target.parent.mkdir(parents=True, exist_ok=True)
        pd.DataFrame(acc, columns=[f"a{c}" for c in range(acc.shape[1])]).to_csv(target, index=False)
    (folder / "c.yaml").write_text("records: {glob: 'data/**/*.csv', time_format: '%Y%m%d-%H%M', "
                                   "time_regex: '_(\\d{8}-\\d{4})'}\n"
                                   f"identify: {{excitation: ambient, fs: {fs:g}, fmax: 10, max_order: 20}}\n")


def test_a_glob_never_takes_the_campaigns_own_files_for_records(tmp_path):
    """With ``glob: data/**/*.csv`` and the output folder inside data/, the
    campaign's own CSV files (a chunk's failed.csv) are not records: read
    with its output folder the index holds the three records; without it,
    the stray file is refused as a record whose name holds no time. (The
    second run of such a campaign refused it before, exit 2.)"""
    _csv_records(tmp_path)
    own = tmp_path / "data" / "results" / "chunks" / "c00000" / "failed.csv"
    own.parent.mkdir(parents=True)
    own.write_text("record,reason\n")
    _, index = read_campaign(tmp_path / "c.yaml", out=tmp_path / "data" / "results")
    assert [Path(p).name for p in index["path"]] == [f"r_202501{k:02d}-0000.csv" for k in (1, 2, 3)]
    with pytest.raises(ValueError, match="failed.csv: records.time_regex .* does not match the name"):
        read_campaign(tmp_path / "c.yaml")


@pytest.mark.slow  # runs a campaign twice
def test_a_campaign_whose_output_lies_in_its_glob_runs_again(tmp_path):
    """The output folder inside the globbed tree: the second run (whose
    workflow reads the campaign again, in the output folder) finds nothing
    to do, where it refused its own failed.csv as a record (exit 2)."""
    _csv_records(tmp_path)
    out = tmp_path / "data" / "results"
    messages = []
    modal.campaign.run(tmp_path / "c.yaml", out, log=messages.append)
    tracked = pd.read_csv(out / "tracked.csv")
    assert tracked["record"].nunique() == 3
    modal.campaign.run(tmp_path / "c.yaml", out, log=messages.append)
    assert messages[-1].startswith("nothing to do"), messages
