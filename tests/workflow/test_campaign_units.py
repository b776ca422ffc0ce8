"""The campaign's pure parts, each on small inputs (no Snakemake run): the
tests of the mutation run of ``benchmarks/mutation_campaign.py``."""

import hashlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
from modal._hashes import content_hashes, file_hash
from modal._locks import clear_stale_locks, descendants, live_snakemake_processes, stale_locks, stop_leftover_run
from modal.campaign import campaign_inputs, chunks, gather, identify_chunk, identify_one, read_campaign
from modal.campaign._jobs import MODE_COLUMNS, _reason, shape_matrix
from modal.measured import overlapping_input as _overlapping_input

# -- the campaign file --------------------------------------------------------

IDENTIFY = "identify: {excitation: ambient}\n"


@pytest.fixture
def folder(tmp_path):
    """Two 3-channel records at 20 Hz (a.npz, b.npz) and an index of them."""
    rng = np.random.default_rng(0)
    for name in ("a", "b"):
        modal.save_record_npz(tmp_path / f"{name}.npz", rng.standard_normal((400, 3)), 0.05)
    (tmp_path / "i.csv").write_text("path,time\nb.npz,2025-01-02\na.npz,2025-01-01\n")
    return tmp_path


def write(folder, text) -> Path:
    (folder / "c.yaml").write_text(text)
    return folder / "c.yaml"


def refused(folder, text, message):
    with pytest.raises(ValueError) as info:
        read_campaign(write(folder, text))
    assert message in str(info.value)
    return str(info.value)


def test_a_campaign_read_with_its_defaults_and_layout(folder):
    config, index = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY))
    assert config["tracking"] == {"reference_modes": None, "freq_rtol": 0.05, "mac_min": 0.8, "min_share": 0.3}
    assert config["chunk"] == 50
    assert config["layout"] == {"n_channels": 3, "fs": 20.0, "units": [None] * 3}  # values only, no record
    assert config["identify"] == modal.IdentifyOptions(excitation="ambient").to_dict()
    assert list(index.columns) == ["record", "path", "time"]
    assert list(index["record"]) == ["a.npz", "b.npz"]
    assert list(index["path"]) == [str(folder / "a.npz"), str(folder / "b.npz")]
    assert campaign_inputs(folder / "c.yaml", config, index) == [folder / "c.yaml", folder / "i.csv",
                                                                 folder / "a.npz", folder / "b.npz"]


def test_settings_at_their_bounds_are_taken_beyond_them_refused(folder):
    (folder / "refs.csv").write_text("freq_hz,phi_0,phi_1,phi_2\n1.0,1.0,0.5,0\n")
    text = ("records: {index: i.csv}\n" + IDENTIFY +
            "tracking: {reference_modes: refs.csv, freq_rtol: 0.5, mac_min: 0, min_share: 1}\nchunk: 1\n")
    config, index = read_campaign(write(folder, text))
    assert config["tracking"] == {"reference_modes": str(folder / "refs.csv"), "freq_rtol": 0.5, "mac_min": 0,
                                  "min_share": 1}
    assert config["chunk"] == 1
    assert campaign_inputs(folder / "c.yaml", config, index)[2] == folder / "refs.csv"
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY +
                                    "tracking: {reference_modes: null, freq_rtol: 0.01, mac_min: 1, "
                                    "min_share: 0.01}\n"))
    assert (config["tracking"]["freq_rtol"], config["tracking"]["mac_min"]) == (0.01, 1)
    assert config["tracking"]["reference_modes"] is None
    (folder / "sub").mkdir()
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY +
                                    "tracking: {reference_modes: sub/../refs.csv}\n"))
    assert config["tracking"]["reference_modes"] == str(folder / "refs.csv")
    base = "records: {index: i.csv}\n" + IDENTIFY
    refused(folder, base + "tracking: {freq_rtol: 0}\n", "c.yaml: tracking.freq_rtol: 0 is less than or equal to")
    refused(folder, base + "tracking: {freq_rtol: 0.6}\n", "tracking.freq_rtol: 0.6 is greater than the maximum")
    refused(folder, base + "tracking: {mac_min: -0.1}\n", "tracking.mac_min: -0.1 is less than the minimum of 0")
    refused(folder, base + "tracking: {mac_min: 1.1}\n", "tracking.mac_min: 1.1 is greater than the maximum of 1")
    refused(folder, base + "tracking: {min_share: 0}\n", "tracking.min_share: 0 is less than or equal to")
    refused(folder, base + "tracking: {min_share: 1.5}\n", "tracking.min_share: 1.5 is greater than the maximum")
    refused(folder, base + "tracking: {reference_modes: 3}\n", "tracking.reference_modes: 3 is not of type")
    refused(folder, base + "tracking: {mac_min: .nan}\n", "c.yaml: tracking.mac_min: nan is not a finite number")
    refused(folder, base + "tracking: {other: 1}\n", "tracking: Additional properties are not allowed ('other'")
    refused(folder, base + "chunk: 0\n", "chunk: 0 is less than the minimum of 1")
    refused(folder, base + "chunk: true\n", "chunk: True is not of type 'integer'")
    refused(folder, base + "chunk: 2.5\n", "chunk: 2.5 is not of type 'integer'")
    refused(folder, base + "tracking: {reference_modes: none.csv}\n",
            f"c.yaml: tracking.reference_modes: no file {folder / 'none.csv'}")
    refused(folder, base + "other: 1\n", "c.yaml: (top level): Additional properties are not allowed ('other'")
    refused(folder, IDENTIFY, "c.yaml: (top level): 'records' is a required property")
    refused(folder, "records: {index: i.csv}\n", "c.yaml: (top level): 'identify' is a required property")
    refused(folder, "records: {index: i.csv, other: 1}\n" + IDENTIFY, "records: Additional properties")
    refused(folder, "records: {index: 3}\n" + IDENTIFY, "c.yaml: records.index: 3 is not of type 'string'")
    refused(folder, "records: {glob: '*.npz'}\n" + IDENTIFY, "give either index (a CSV of path,time) or glob")
    refused(folder, "records: {index: i.csv, glob: '*.npz', time_format: '%Y'}\n" + IDENTIFY,
            "c.yaml: records: give either index (a CSV of path,time) or glob with time_format")
    refused(folder, "records: 3\n" + IDENTIFY, "c.yaml: records: 3 is not of type 'object'")
    refused(folder, "records: {}\n" + IDENTIFY, "c.yaml: records: give either index (a CSV of path,time) or glob")
    for key in ("freq_rtol", "mac_min", "min_share"):
        refused(folder, base + f"tracking: {{{key}: a}}\n", f"c.yaml: tracking.{key}: 'a' is not of type 'number'")
    refused(folder, "records: {index: i.csv}\nidentify: 3\n", "c.yaml: identify: 3 is not of type 'object'")
    refused(folder, "records: {index: i.csv}\nidentify: {fmax: 3}\n",
            "c.yaml: identify: 'excitation' is a required property")
    refused(folder, base + "tracking: 3\n", "c.yaml: tracking: 3 is not of type 'object'")
    for key in ("glob: 3, time_format: x", "glob: x, time_format: 3", "glob: x, time_format: y, time_regex: 3"):
        refused(folder, f"records: {{{key}}}\n" + IDENTIFY, "is not of type 'string'")


def test_a_campaign_named_by_a_relative_path_is_named_in_full(folder, monkeypatch):
    monkeypatch.chdir(folder)
    write(folder, "records: {index: i.csv}\n" + IDENTIFY + "chunk: 2.0\n")
    with pytest.raises(ValueError, match="chunk: 2.0 is not") as info:
        read_campaign("c.yaml")
    assert str(info.value).startswith(f"{folder / 'c.yaml'}: ")
    write(folder, "records: {index: i.csv}\n" + IDENTIFY)
    config, index = read_campaign("c.yaml")
    assert list(index["path"]) == [str(folder / "a.npz"), str(folder / "b.npz")]
    assert campaign_inputs("c.yaml", config, index)[:2] == [folder / "c.yaml", folder / "i.csv"]


def test_a_campaign_that_cannot_be_read_says_why(tmp_path):
    refused(tmp_path, "- records\n- identify\n", "c.yaml: a campaign is a mapping with records and identify")
    with pytest.raises(ValueError, match="none.yaml: cannot read the campaign: No such file or directory"):
        read_campaign(tmp_path / "none.yaml")
    write(tmp_path, "records: {index: none.csv}\n" + IDENTIFY)
    with pytest.raises(ValueError, match=r"none.csv: cannot read the index: .*No such file"):
        read_campaign(tmp_path / "c.yaml")


def test_the_index_refusals_name_the_row(folder):
    base = "records: {index: i.csv}\n" + IDENTIFY
    (folder / "i.csv").write_text("path,when\na.npz,2025-01-01\n")
    refused(folder, base, "i.csv: the index needs columns path,time; it has path, when")
    (folder / "i.csv").write_text("path,time\na.npz,2025-01-01\nb.npz,\n")
    refused(folder, base, "i.csv: row 3: no time")
    (folder / "i.csv").write_text("path,time\na.npz,2025-01-01\n,2025-01-02\n")
    refused(folder, base, "i.csv: row 3: no path")
    (folder / "i.csv").write_text("path,time\na.npz,2025-01-01\nb.npz,2025-01-32\n")
    refused(folder, base, "i.csv: row 3: time '2025-01-32' does not follow ISO 8601 (e.g. 2025-02-01T13:00)")
    (folder / "i.csv").write_text("path,time\na.npz,01/02/2025\nb.npz,2025-01-02\n")
    refused(folder, "records: {index: i.csv, time_format: '%d/%m/%Y'}\n" + IDENTIFY,
            "i.csv: row 3: time '2025-01-02' does not follow records.time_format '%d/%m/%Y'")
    (folder / "i.csv").write_text("path,time\n")
    refused(folder, base, "c.yaml: records: no record found")
    os.rename(folder / "b.npz", folder / "0101")  # a name that looks like a number, a time without separators
    (folder / "i.csv").write_text("path,time\n0101,20250102\n")
    _, index = read_campaign(write(folder, "records: {index: i.csv, time_format: '%Y%m%d'}\n" + IDENTIFY))
    assert list(index["record"]) == ["0101"] and list(index["time"]) == [pd.Timestamp("2025-01-02")]
    os.rename(folder / "0101", folder / "b.npz")
    # one file by two names (a link): named as first listed, with its count
    os.symlink(folder / "a.npz", folder / "link.npz")
    (folder / "i.csv").write_text("path,time\na.npz,2025-01-01\nb.npz,2025-01-02\nlink.npz,2025-01-03\n")
    refused(folder, base, "c.yaml: records: a.npz is listed 2 times")
    (folder / "i.csv").write_text("path,time\nlink.npz,2025-01-01\na.npz,2025-01-02\nsub/../a.npz,2025-01-03\n")
    refused(folder, base, "c.yaml: records: link.npz is listed 3 times")


def test_records_at_one_time_are_in_name_order_and_the_layout_skips_what_does_not_read(folder):
    (folder / "broken.npz").write_text("not a record")
    (folder / "i.csv").write_text("path,time\nb.npz,2025-01-01\nbroken.npz,2025-01-01\na.npz,2025-01-01\n")
    config, index = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY))
    assert list(index["record"]) == ["a.npz", "b.npz", "broken.npz"]
    assert list(index.index) == [0, 1, 2]
    assert config["layout"] == {"n_channels": 3, "fs": 20.0, "units": [None] * 3}
    (folder / "i.csv").write_text("path,time\nbroken.npz,2025-01-01\n")
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY))
    assert config["layout"] is None


def test_glob_refusals_and_names(folder):
    (folder / "d_20250103.npz").mkdir()  # a folder the pattern matches: not a record
    (folder / "sub").mkdir()
    os.rename(folder / "a.npz", folder / "sub" / "a_20250102.npz")
    os.rename(folder / "b.npz", folder / "b_20250101.npz")
    config, index = read_campaign(write(folder, "records: {glob: '**/*_*.npz', time_format: '%Y%m%d', "
                                                "time_regex: '\\d{8}'}\n" + IDENTIFY))
    assert list(index["record"]) == ["b_20250101.npz", "sub/a_20250102.npz"]
    assert list(index["path"]) == [str(folder / "b_20250101.npz"), str(folder / "sub" / "a_20250102.npz")]
    assert list(index["time"]) == [pd.Timestamp("2025-01-01"), pd.Timestamp("2025-01-02")]
    assert str(index["time"].dtype) == "datetime64[ns]"
    assert campaign_inputs(folder / "c.yaml", config, index) == [folder / "c.yaml", folder / "b_20250101.npz",
                                                                 folder / "sub" / "a_20250102.npz"]
    _, index = read_campaign(write(folder, "records: {glob: 'b_*.npz', time_format: 'b_%Y%m%d'}\n" + IDENTIFY))
    assert list(index["time"]) == [pd.Timestamp("2025-01-01")]  # the stem, without a regex
    refused(folder, "records: {glob: '*.npz', time_format: '%Y%m%d', time_regex: 'x(\\d)'}\n" + IDENTIFY,
            "b_20250101.npz: records.time_regex 'x(\\\\d)' does not match the name")
    refused(folder, "records: {glob: '*.npz', time_format: '%Y-%m'}\n" + IDENTIFY,
            "b_20250101.npz: records.time_format '%Y-%m' does not parse 'b_20250101'")
    refused(folder, "records: {glob: '*.none', time_format: '%Y'}\n" + IDENTIFY, "c.yaml: records: no record found")
    refused(folder, "records: {glob: '*.npz', time_format: '%Y', time_regex: '('}\n" + IDENTIFY,
            "c.yaml: records.time_regex '(' is not a regular expression: missing ), unterminated subpattern")


def test_chunks_are_consecutive_and_named_by_number():
    index = pd.DataFrame({"record": list("abcde")})
    parts = chunks(index, 2)
    assert list(parts) == ["c00000", "c00001", "c00002"]
    assert [list(p["record"]) for p in parts.values()] == [["a", "b"], ["c", "d"], ["e"]]
    assert list(chunks(index, 5)) == ["c00000"] and chunks(index.iloc[:0], 3) == {}


# -- the geometry the tracked shapes are drawn on --------------------------------

def _geometry(folder, channels="channel,node,x,y,z,quantity,role\n0,1,1,0,0,acceleration,roving\n"):
    """A two-storey stick (nodes 0, 1, 2 up z, lines between) and its
    channel table in ``folder/geo``."""
    (folder / "geo").mkdir(exist_ok=True)
    (folder / "geo" / "nodes.csv").write_text("node,x,y,z\n0,0,0,0\n1,0,0,3\n2,0,0,6\n")
    (folder / "geo" / "lines.csv").write_text("node_1,node_2\n0,1\n1,2\n")
    (folder / "geo" / "channels.csv").write_text(channels)
    return folder / "geo"


def test_a_geometry_is_read_with_its_channel_table(folder):
    """The geometry's folder and channel table are resolved, the table kept
    as plain rows, each shape entry's record channel said; both are inputs
    (an --out over them is refused); paths are resolved."""
    _geometry(folder, "channel,node,x,y,z,quantity,unit,role\n2,1,1,0,0,acceleration,cm/s2,roving\n"
                      "0,2,0,1,0,acceleration,,roving\n")
    text = "records: {index: i.csv}\nidentify: {excitation: ambient, channels: [2, 0]}\n" \
           "geometry: {folder: ./geo/../geo, channels: geo/../geo/channels.csv}\n"
    config, index = read_campaign(write(folder, text))
    geometry = config["geometry"]
    assert geometry["folder"] == str(folder / "geo") and geometry["channels"] == str(folder / "geo" / "channels.csv")
    assert geometry["shape_channels"] == [2, 0]
    assert [(r["channel"], r["node"], r["x"], r["y"], r["unit"]) for r in geometry["table"]] == \
        [(2, "1", 1.0, 0.0, "cm/s2"), (0, "2", 0.0, 1.0, "")]
    assert all(type(r["channel"]) is int for r in geometry["table"])  # plain values, for the workflow's params
    assert campaign_inputs(folder / "c.yaml", config, index)[2:4] == [folder / "geo", folder / "geo" / "channels.csv"]
    # every channel by default
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY + "geometry: {folder: geo, "
                                    "channels: geo/channels.csv}\n"))
    assert config["geometry"]["shape_channels"] == [0, 1, 2]
    assert read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY))[0]["geometry"] is None
    # no record reads: the table is read all the same, the channels identified are not known
    for name in ("a", "b"):
        (folder / f"{name}.npz").write_text("not a record")
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY + "geometry: {folder: geo, "
                                    "channels: geo/channels.csv}\n"))
    assert len(config["geometry"]["table"]) == 2 and config["geometry"]["shape_channels"] is None


def test_a_geometry_that_names_the_sensors_needs_no_channel_table(folder):
    """pyOMA2's geometry 1 names the sensors: matched by name to the
    channels of the layout's record (ch1, ch2, ch3 of an .npz)."""
    (folder / "geo").mkdir()
    (folder / "geo" / "sens_coord.txt").write_text("sName x y z\nch3 0 0 3\nch1 0 0 6\n")
    (folder / "geo" / "sens_dir.txt").write_text("1 0 0\n0 1 0\n")
    (folder / "a.npz").write_text("not a record")  # the names of the first record that reads: b.npz
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY + "geometry: {folder: geo}\n"))
    assert config["layout"]["n_channels"] == 3
    table = config["geometry"]["table"]
    assert [(r["channel"], r["name"], r["x"], r["y"]) for r in table] == [(0, "ch1", 0.0, 1.0), (2, "ch3", 1.0, 0.0)]
    assert config["geometry"]["channels"] is None
    # no record reads: no names to match, no table (the records fail in their jobs)
    for name in ("b",):
        (folder / f"{name}.npz").write_text("not a record")
    config, _ = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY + "geometry: {folder: geo}\n"))
    assert config["geometry"]["table"] is None and config["geometry"]["shape_channels"] is None


def test_geometry_refusals_name_the_key_and_the_file(folder):
    records = "records: {index: i.csv}\n" + IDENTIFY
    refused(folder, records + "geometry: {folder: nowhere}\n", "geometry.folder: geometry")
    refused(folder, records + "geometry: {channels: c.csv}\n", "geometry: 'folder' is a required property")
    refused(folder, records + "geometry: {folder: geo, colour: red}\n", "geometry: Additional properties")
    _geometry(folder)
    (folder / "geo" / "nodes.csv").write_text("node,x,y,z\n0,0,0,zero\n")
    message = refused(folder, records + "geometry: {folder: geo, channels: geo/channels.csv}\n", "geometry.folder: ")
    assert "nodes.csv: row 1, column z: 'zero' is not a number" in message
    _geometry(folder)
    refused(folder, records + "geometry: {folder: geo}\n", "geometry.folder: ")
    assert "names no sensors: give geometry.channels" in refused(folder, records + "geometry: {folder: geo}\n", "")
    refused(folder, records + "geometry: {folder: geo, channels: none.csv}\n",
            f"geometry.channels: no file {folder / 'none.csv'}")
    _geometry(folder, "channel,node,x,y,z,quantity,role\n0,9,1,0,0,acceleration,roving\n")
    refused(folder, records + "geometry: {folder: geo, channels: geo/channels.csv}\n",
            "geometry.channels: " + str(folder / "geo" / "channels.csv") + ": node(s) 9 not in the geometry")
    _geometry(folder, "channel,node,x,y,z,quantity,role\n3,1,1,0,0,acceleration,roving\n")
    refused(folder, records + "geometry: {folder: geo, channels: geo/channels.csv}\n",
            "channel(s) [3] beyond the record's 3 columns")
    _geometry(folder, "channel,node,x,y,z,quantity,role\n1,1,1,0,0,acceleration,roving\n"
                      "2,2,1,0,0,acceleration,roving\n")
    refused(folder, "records: {index: i.csv}\nidentify: {excitation: ambient, channels: [0, 1]}\n"
            "geometry: {folder: geo, channels: geo/channels.csv}\n",
            "geometry: channel(s) [2] of the channel table are not identified (identify.channels: 0, 1)")


def test_tracked_shapes_are_each_modes_aligned_mean_drawn_in_si_on_its_nodes():
    """The mean shape of a mode: its estimates scaled to unit norm and turned
    to the reference's sign before averaging (a plain mean of 2 v and -w
    points elsewhere); drawn with each entry at its record channel's node and
    direction (``shape_channels`` [2, 0, 1]: phi_0 is channel 2), in SI (cm/s2
    x 0.01), the largest component 1; mode 2's picture holds mode 2's shape."""
    from modal.campaign._report import drawn_shapes, shapes_figure
    from modal.campaign._tracking import mean_shapes
    from modal.setups import Geometry

    references = pd.DataFrame({"mode": [1, 2], "freq_hz": [1.0, 3.0], "phi_0": [0.3, 0.9], "phi_1": [0.5, -0.6],
                               "phi_2": [0.8, 0.1]})
    v, w = np.array([0.3, 0.5, 0.8]), np.array([0.4, 0.5, 0.7])
    tracked = pd.DataFrame({"mode": [1, 1, 2], "freq_hz": [1.0, 1.1, 3.0], "phi_0": [2 * v[0], -w[0], 0.9],
                            "phi_1": [2 * v[1], -w[1], -0.6], "phi_2": [2 * v[2], -w[2], 0.1]})
    mean = mean_shapes(tracked, references)
    expected = v / np.linalg.norm(v) + w / np.linalg.norm(w)
    expected /= np.linalg.norm(expected)
    assert mean[["phi_0", "phi_1", "phi_2"]].to_numpy()[0] == pytest.approx(expected, abs=1e-12)
    assert mean[["phi_0", "phi_1", "phi_2"]].to_numpy()[0] == pytest.approx([0.3632, 0.5173, 0.7749], abs=1e-4)
    assert mean[["phi_0", "phi_1", "phi_2"]].to_numpy()[1] == pytest.approx(np.array([0.9, -0.6, 0.1]) / 1.0862780,
                                                                            abs=1e-6)
    assert mean["mode"].tolist() == [1, 2] and mean["n_estimates"].tolist() == [2, 1]
    assert mean["freq_hz"].tolist() == pytest.approx([1.05, 3.0])
    assert mean["mac_reference"].tolist() == pytest.approx([0.99513, 1.0], abs=1e-5)
    assert mean_shapes(tracked[tracked["mode"] == 2], references)["mode"].tolist() == [2]  # mode 1: none tracked
    assert list(mean_shapes(tracked.iloc[:0], references).columns) == ["mode", "freq_hz", "n_estimates",
                                                                       "mac_reference", "phi_0", "phi_1", "phi_2"]
    # twelve channels: phi_10 is the eleventh entry, not the third
    shape = np.arange(1.0, 13.0)
    twelve = pd.DataFrame([{"mode": 1, "freq_hz": 1.0, **{f"phi_{k}": v for k, v in enumerate(shape)}}])
    assert mean_shapes(twelve, twelve)[[f"phi_{k}" for k in range(12)]].to_numpy()[0] == \
        pytest.approx(shape / np.linalg.norm(shape))
    # an estimate orthogonal to the reference (tracked at mac_min 0) counts as it is; one of zero norm adds nothing
    along_x = pd.DataFrame({"mode": [1], "freq_hz": [1.0], "phi_0": [1.0], "phi_1": [0.0], "phi_2": [0.0]})
    odd = pd.DataFrame({"mode": 1, "freq_hz": 1.0, "phi_0": [0.6, 0.0, 0.0], "phi_1": [0.8, 0.0, 0.0],
                        "phi_2": [0.0, 1.0, 0.0]})
    assert mean_shapes(odd.iloc[[0, 2]], along_x)[["phi_0", "phi_1", "phi_2"]].to_numpy()[0] == \
        pytest.approx([0.6, 0.8, 0.0])
    assert mean_shapes(odd.iloc[[0, 1]], along_x)[["phi_0", "phi_1", "phi_2"]].to_numpy()[0] == \
        pytest.approx(np.array([0.6, 0.8, 1.0]) / np.sqrt(2))

    geometry = Geometry(pd.DataFrame({"x": 0.0, "y": 0.0, "z": [0.0, 3.0, 6.0]}, index=pd.Index(["0", "1", "2"],
                                     name="node")), lines=[("0", "1"), ("1", "2")])
    table = pd.DataFrame({"channel": [0, 1, 2], "node": ["1", "2", "2"], "x": [1.0, 1.0, 0.0],
                          "y": [0.0, 0.0, 1.0], "z": 0.0, "quantity": "acceleration", "unit": ["", "cm/s2", ""]})
    table.loc[1, "unit"] = ""
    drawn = drawn_shapes(mean, table, [2, 0, 1], geometry).set_index(["mode", "node"])
    phi = mean[["phi_0", "phi_1", "phi_2"]].to_numpy()[0]
    # node 1 along x: channel 0 = phi_1; node 2 along x: channel 1 = phi_2; along y: channel 2 = phi_0
    assert drawn.loc[(1, "2"), ["x", "y", "z"]].tolist() == pytest.approx([1.0, phi[0] / phi[2], np.nan],
                                                                         nan_ok=True)
    assert drawn.loc[(1, "1"), "x"] == pytest.approx(phi[1] / phi[2])
    assert drawn.loc[(1, "1"), "x"] == pytest.approx(0.6676, abs=1e-4)
    assert drawn.loc[(2, "2"), "y"] == 1.0 and drawn.loc[(2, "2"), "x"] == pytest.approx(0.1 / 0.9)
    assert drawn.loc[(2, "1"), "x"] == pytest.approx(-0.6 / 0.9)
    assert (drawn.loc[[(1, "2"), (2, "2")], ["x_im", "y_im"]] == 0).all().all() and (drawn["flag"] == "").all()
    assert (drawn.loc[[(1, "1"), (2, "1")], "x_im"] == 0).all()
    # a channel along z gives the z component (real, no imaginary part)
    up = drawn_shapes(mean.iloc[:1], table.iloc[:1].assign(x=0.0, z=1.0), [0, 2, 1], geometry)
    assert up["node"].tolist() == ["1"] and up["z"].tolist() == pytest.approx([1.0]) and up["z_im"].tolist() == [0.0]
    assert up[["x", "y"]].isna().all().all()  # not measured
    assert list(drawn_shapes(mean.iloc[:0], table, [2, 0, 1], geometry).columns) == \
        ["mode", "node", "x", "y", "z", "x_im", "y_im", "z_im", "flag"]
    # twelve channels, one per node along x: phi_10 is the eleventh channel's, not the third's
    twelve = pd.DataFrame([{"mode": 1, **{f"phi_{k}": k + 1.0 for k in range(12)}}])
    along = pd.DataFrame({"channel": range(12), "node": [f"n{k}" for k in range(12)], "x": 1.0, "y": 0.0,
                          "z": 0.0, "quantity": "acceleration", "unit": ""})
    assert drawn_shapes(twelve, along, list(range(12)))["x"].tolist() == pytest.approx(np.arange(1, 13) / 12)
    # a channel in cm/s2 is brought to SI before the nodes are solved
    table.loc[1, "unit"] = "cm/s2"
    scaled = drawn_shapes(mean, table, [2, 0, 1], geometry).set_index(["mode", "node"])
    # (node 1 then moves most: its x is the 1)
    assert scaled.loc[(1, "1"), "x"] == 1.0 and scaled.loc[(1, "2"), "x"] == pytest.approx(0.01 * phi[2] / phi[1])
    assert scaled.loc[(1, "2"), "y"] == pytest.approx(phi[0] / phi[1])
    # the figure draws those numbers: per mode, the deformed line from node 1 to node 2 (after the dashed ones)
    figure = shapes_figure(geometry, table.assign(unit=""), [2, 0, 1], mean)
    titles = [ax.get_title() for ax in figure.axes]
    assert titles == ["mode 1: 1.05 Hz (mean of 2)", "mode 2: 3 Hz (mean of 1)"]
    for ax, mode in zip(figure.axes, (1, 2)):
        deformed = ax.lines[3].get_data_3d()
        assert deformed[0][0] / deformed[0][1] == pytest.approx(drawn.loc[(mode, "1"), "x"] / drawn.loc[(mode, "2"),
                                                                                                          "x"])
        assert deformed[1][1] / deformed[0][1] == pytest.approx(drawn.loc[(mode, "2"), "y"] / drawn.loc[(mode, "2"),
                                                                                                          "x"])
    assert shapes_figure(geometry, table, [2, 0, 1], mean.iloc[:0]) is None
    # up to three pictures a row: two modes are two columns, four are two rows of three
    assert figure.get_size_inches().tolist() == [7.2, 3.6]
    four = pd.concat([mean, mean.assign(mode=mean["mode"] + 2)], ignore_index=True)
    assert shapes_figure(geometry, table, [2, 0, 1], four).get_size_inches().tolist() == pytest.approx([10.8, 7.2])


# -- the track and report steps -------------------------------------------------

def _chunk_files(folder):
    """Two chunks' files: records r0 ... r3, each with a mode of shape (1, 0.1)
    near 2 Hz and one of shape (0.1, -1) near 5 Hz, r3's second mode with
    shape (0.7, 0.7), matching neither; r4 failed."""
    columns = ",".join(MODE_COLUMNS)
    rows = []
    # (1.98 and 5.02 Hz with digits beyond the 8 significant ones the tables keep)
    for r, (f1, f2) in enumerate([(2.00, 5.00), (2.02, 5.05), (1.98000000001, 4.95), (2.01, 5.02000000001)]):
        second = "0.7,0.7" if r == 3 else "-0.1,1.0"
        rows.append(f"r{r},2025-01-0{r + 1},1,{f1},0.01,0.01,0.002,0.9,5,1.0,0.1")
        rows.append(f"r{r},2025-01-0{r + 1},2,{f2},0.02,0.02,0.003,0.9,5,{second}")
    (folder / "m0.csv").write_text(f"{columns},phi_0,phi_1\n" + "\n".join(rows[:4]) + "\n")
    (folder / "m1.csv").write_text(f"{columns},phi_0,phi_1\n" + "\n".join(rows[4:]) + "\n")
    (folder / "f0.csv").write_text("record,reason\n")
    (folder / "f1.csv").write_text("record,reason\nr4,broken\n")
    return [folder / "m0.csv", folder / "m1.csv"], [folder / "f0.csv", folder / "f1.csv"]


TRACKING = {"reference_modes": None, "freq_rtol": 0.05, "mac_min": 0.8, "min_share": 0.3}


def test_the_track_step_writes_every_table(tmp_path):
    """track_campaign gathers the chunks and writes modes, failures,
    references built from the campaign (seen in >= min_share of the
    records), the tracked estimates (without their shapes), the untracked
    ones and each mode's mean shape."""
    from modal.campaign import track_campaign
    from modal.campaign._tracking import TRACKED_COLUMNS

    modes_files, failed_files = _chunk_files(tmp_path)
    track_campaign(modes_files, failed_files, 5, TRACKING, tmp_path)
    modes = pd.read_csv(tmp_path / "modes.csv")
    assert len(modes) == 8 and modes["freq_hz"].tolist()[:3] == [2.0, 5.0, 2.02]
    assert list(modes.columns) == MODE_COLUMNS + ["phi_0", "phi_1"]
    assert pd.read_csv(tmp_path / "failed.csv").to_dict("list") == {"record": ["r4"], "reason": ["broken"]}
    references = pd.read_csv(tmp_path / "references.csv")
    assert list(references.columns) == ["mode", "freq_hz", "n_records", "freq_low_hz", "freq_high_hz", "phi_0",
                                        "phi_1"]
    assert references["mode"].tolist() == [1, 2] and references["n_records"].tolist() == [4, 3]
    assert references["freq_hz"].tolist() == pytest.approx([2.005, 5.0])
    assert references[["freq_low_hz", "freq_high_hz"]].to_numpy().tolist() == [[1.98, 2.02], [4.95, 5.05]]
    tracked = pd.read_csv(tmp_path / "tracked.csv")
    assert list(tracked.columns) == TRACKED_COLUMNS
    assert list(zip(tracked["record"], tracked["mode"], tracked["freq_hz"])) == [
        ("r0", 1, 2.0), ("r0", 2, 5.0), ("r1", 1, 2.02), ("r1", 2, 5.05), ("r2", 1, 1.98), ("r2", 2, 4.95),
        ("r3", 1, 2.01)]
    untracked = pd.read_csv(tmp_path / "untracked.csv")
    assert untracked[["record", "freq_hz"]].values.tolist() == [["r3", 5.02]]
    assert list(untracked.columns) == list(modes.columns)
    shapes = pd.read_csv(tmp_path / "tracked_shapes.csv")
    assert list(shapes.columns) == ["mode", "freq_hz", "n_estimates", "mac_reference", "phi_0", "phi_1"]
    assert shapes["mode"].tolist() == [1, 2] and shapes["n_estimates"].tolist() == [4, 3]
    assert shapes[["phi_0", "phi_1"]].to_numpy() == pytest.approx(np.array([[1, 0.1], [-0.1, 1]]) / np.sqrt(1.01))
    for name in ("modes", "references", "tracked", "untracked", "tracked_shapes"):  # 8 significant digits
        text = (tmp_path / f"{name}.csv").read_text()
        assert "00000001" not in text and "0.9950371902" not in text, name
    assert "0.99503719," in (tmp_path / "tracked_shapes.csv").read_text()
    # the index itself counts its records: 20 of them, a mode in 4 is under min_share
    track_campaign(modes_files, failed_files, pd.DataFrame({"record": range(20)}), TRACKING, tmp_path)
    assert pd.read_csv(tmp_path / "references.csv").empty and pd.read_csv(tmp_path / "tracked.csv").empty
    assert len(pd.read_csv(tmp_path / "untracked.csv")) == 8
    # tight tolerances: r1's 2.02 Hz lies 0.75 % above the median; r3's first mode (MAC 0.99) matches at 0.8 only
    track_campaign(modes_files, failed_files, 5, {**TRACKING, "freq_rtol": 0.001, "mac_min": 0.999}, tmp_path)
    assert pd.read_csv(tmp_path / "references.csv").empty
    # min_share of the 4 records identified (r4 failed): mode 2, in 3 of them (0.75), is a reference at 0.7
    # (of all 5 it would be 0.6), not at 0.8
    track_campaign(modes_files, failed_files, 5, {**TRACKING, "min_share": 0.7}, tmp_path)
    assert pd.read_csv(tmp_path / "references.csv")["n_records"].tolist() == [4, 3]
    track_campaign(modes_files, failed_files, 5, {**TRACKING, "min_share": 0.8}, tmp_path)
    assert pd.read_csv(tmp_path / "references.csv")["mode"].tolist() == [1]


def test_the_track_step_takes_given_references_with_their_observed_range(tmp_path):
    """Given references (a file) get the range the campaign observed; the
    built ones are not made; freq_rtol and mac_min reach the tracking."""
    from modal.campaign import track_campaign

    modes_files, failed_files = _chunk_files(tmp_path)
    (tmp_path / "refs.csv").write_text("freq_hz,phi_a,phi_b\n2.1,1.0,0.0\n")
    tracking = {**TRACKING, "reference_modes": str(tmp_path / "refs.csv")}
    track_campaign(modes_files, failed_files, 5, tracking, tmp_path)
    references = pd.read_csv(tmp_path / "references.csv")
    assert references.to_dict("list") == {"mode": [1], "freq_hz": [2.1], "phi_0": [1.0], "phi_1": [0.0],
                                          "freq_low_hz": [1.98], "freq_high_hz": [2.1]}
    tracked = pd.read_csv(tmp_path / "tracked.csv")
    assert tracked["freq_hz"].tolist() == [2.0, 2.02, 1.98, 2.01] and (tracked["mode"] == 1).all()
    assert tracked["mac"].tolist() == pytest.approx([1 / 1.01] * 4)
    assert pd.read_csv(tmp_path / "tracked_shapes.csv")["n_estimates"].tolist() == [4]
    track_campaign(modes_files, failed_files, 5, {**tracking, "mac_min": 0.995}, tmp_path)
    assert pd.read_csv(tmp_path / "tracked.csv").empty  # MAC 0.990 < 0.995
    track_campaign(modes_files, failed_files, 5, {**tracking, "freq_rtol": 0.01}, tmp_path)
    assert pd.read_csv(tmp_path / "tracked.csv").empty  # 2.1 Hz: no estimate within 1 %, no range


def test_the_report_step_reads_the_tables_and_draws_the_shapes_given_a_geometry(tmp_path, monkeypatch):
    """report_campaign hands campaign_report the track step's tables (times
    as times), the campaign file's text, the command and the covariates;
    with a geometry (and its channel table) the geometry read, the table and
    the mean shapes; without a table or geometry, none."""
    from modal.campaign import _report, report_campaign, track_campaign

    modes_files, failed_files = _chunk_files(tmp_path)
    track_campaign(modes_files, failed_files, 5, TRACKING, tmp_path)
    _geometry(tmp_path, "channel,node,x,y,z,quantity,role\n0,1,1,0,0,acceleration,roving\n"
                        "1,2,0,1,0,acceleration,roving\n")
    (tmp_path / "c.yaml").write_text("chunk: 3\n")
    geometry = {"folder": str(tmp_path / "geo"), "channels": None, "shape_channels": [0, 1],
                "table": [{"channel": 0, "node": "1", "x": 1.0, "y": 0.0, "z": 0.0, "quantity": "acceleration",
                           "unit": ""}, {"channel": 1, "node": "2", "x": 0.0, "y": 1.0, "z": 0.0,
                                         "quantity": "acceleration", "unit": ""}]}
    report_campaign(tmp_path, 5, tmp_path / "c.yaml", "modal campaign c.yaml", geometry=geometry,
                    covariates={"record": ["r0", "r1", "r2", "r3"], "temperature_c": [1.0, 2.0, 3.0, 4.0]})
    text = (tmp_path / "report.html").read_text()
    assert text.count("<img") == 4 and "<h2>Tracked shapes</h2>" in text and "Frequency against" in text
    assert "<b>5</b> records: <b>4</b> identified, <b>1</b> failed" in text and "r4" in text
    assert "modal campaign c.yaml" in text and "chunk: 3" in text
    received = {}
    monkeypatch.setattr(_report, "campaign_report", lambda *args, **keywords: received.update(args=args, **keywords))
    report_campaign(tmp_path, 5, tmp_path / "c.yaml", "cmd", geometry=geometry)
    path, tracked, untracked, failed, references, n_records, config_text, command = received["args"]
    assert path == tmp_path / "report.html" and n_records == 5 and config_text == "chunk: 3\n" and command == "cmd"
    assert str(tracked["time"].dtype).startswith("datetime64") and len(tracked) == 7 and len(untracked) == 1
    assert failed["record"].tolist() == ["r4"] and references["mode"].tolist() == [1, 2]
    assert received["covariates"] is None
    drawing, table, channels = received["geometry"]
    assert list(drawing.nodes.index) == ["0", "1", "2"] and table["node"].tolist() == ["1", "2"] and channels == [0, 1]
    assert received["shapes"]["n_estimates"].tolist() == [4, 3]
    report_campaign(tmp_path, 5, tmp_path / "c.yaml", "cmd", covariates={"record": ["r0"], "t": [1.0]})
    assert received["geometry"] is None and received["shapes"] is None
    assert received["covariates"].to_dict("list") == {"record": ["r0"], "t": [1.0]}
    report_campaign(tmp_path, 5, tmp_path / "c.yaml", "cmd", geometry={**geometry, "table": None})
    assert received["geometry"] is None and received["shapes"] is None


# -- a chunk's job --------------------------------------------------------------

class Result:
    """What ``identify_record`` returns, made up from the record: two modes
    whose numbers tell the record, its channel count and ``dt`` apart."""

    def __init__(self, acc, dt):
        n = acc.shape[1]
        level = float(np.round(np.abs(acc[0]).sum(), 6))
        self.modes = pd.DataFrame({"mode": [1, 2], "freq_hz": [level, 1 / dt], "freq_std_hz": [1 / 3, 0.2],
                                   "damping": [0.01, 0.02], "damping_std": [0.001, 0.002], "mpc": [0.9, 0.8],
                                   "n_poles": [5, 6], "other": [7, 8]})
        self.shapes = np.arange(2 * n, dtype=float).reshape(n, 2) + level


@pytest.fixture
def stand_in(monkeypatch):
    """identify_record replaced by :class:`Result` (it warns, as the real
    one may); the options it received are kept."""
    received = []

    def identify_record(acc, dt, options):
        import warnings
        warnings.warn("no mode selected")  # the tests turn warnings into errors
        received.append(options)
        return Result(acc, dt), None

    monkeypatch.setattr(modal.measured, "identify_record", identify_record)
    return received


def test_a_chunk_writes_each_mode_and_each_failure(folder, stand_in, tmp_path):
    config, index = read_campaign(write(folder, "records: {index: i.csv}\nidentify: {excitation: ambient, fmax: 5}\n"))
    good = modal.read_record(folder / "a.npz")
    modal.save_record_npz(folder / "short.npz", good.acc[:, :2], good.dt)
    modal.save_record_npz(folder / "slow.npz", good.acc[::2], 2 * good.dt)
    (folder / "broken.npz").write_text("not a record")
    extra = pd.DataFrame({"record": ["short", "slow", "broken"], "time": pd.Timestamp("2025-06-01"),
                          "path": [str(folder / n) for n in ("short.npz", "slow.npz", "broken.npz")]})
    records = pd.concat([index, extra], ignore_index=True)
    modes_csv, failed_csv = tmp_path / "new" / "a" / "modes.csv", tmp_path / "other" / "b" / "failed.csv"
    identify_chunk(records, config["identify"], modes_csv, failed_csv, config["layout"])
    assert stand_in == [modal.IdentifyOptions(excitation="ambient", fmax=5)] * 2
    modes, failed = pd.read_csv(modes_csv), pd.read_csv(failed_csv)
    assert list(modes.columns) == MODE_COLUMNS + ["phi_0", "phi_1", "phi_2"]
    b = modal.read_record(folder / "b.npz").acc
    level = float(np.round(np.abs(b[0]).sum(), 6))
    assert modes.iloc[3].tolist() == ["b.npz", "2025-01-02T00:00:00", 2, 20, 0.2, 0.02, 0.002, 0.8, 6, level + 1,
                                      level + 3, level + 5]
    assert modes.iloc[2][["mode", "freq_hz", "phi_0"]].tolist() == [1, pytest.approx(level), level]
    assert list(modes["record"]) == ["a.npz", "a.npz", "b.npz", "b.npz"]
    assert modes_csv.read_text().count(",0.33333333,") == 2  # to 8 significant digits
    assert list(failed.columns) == ["record", "reason"] and list(failed["record"]) == ["short", "slow", "broken"]
    assert failed["reason"][0] == "2 channels, the campaign's records 3"
    assert failed["reason"][1] == "sampled at 10 Hz, the campaign's records at 20 Hz"
    np.testing.assert_array_equal(shape_matrix(modes[modes["record"] == "b.npz"]), Result(b, 0.05).shapes)
    # no layout: the odd records are identified
    assert identify_one(folder / "short.npz", config["identify"]).shapes.shape == (2, 2)
    identify_chunk(records.iloc[4:5], config["identify"], modes_csv, failed_csv)
    assert modes_csv.read_text().strip() == ",".join(MODE_COLUMNS)  # no mode: a header still
    assert list(pd.read_csv(failed_csv)["record"]) == ["broken"]
    identify_chunk(records.iloc[:2], config["identify"], modes_csv, failed_csv)
    assert failed_csv.read_text() == "record,reason\n"  # none failed: a header still


def test_each_warning_of_a_record_is_one_line_in_the_jobs_log(folder, monkeypatch, tmp_path, capsys):
    """A record's warnings (a clipped channel, ...) are not lost: each is a
    line of the job's log (standard error) naming the record, every time
    it is given (one line of code warning twice gives two), also for a
    record whose identification then fails; identify_one hands them over."""
    import warnings

    from modal.identification import ModalWarning

    def identify_record(acc, dt, options):
        for channel in (0, 2):
            warnings.warn(f"channel {channel} clipped:\n 5 samples at its extreme", ModalWarning)
        if acc.shape[0] < 400:
            raise ValueError("too short")
        return Result(acc, dt), None

    monkeypatch.setattr(modal.measured, "identify_record", identify_record)
    config, index = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY))
    modal.save_record_npz(folder / "cut.npz", modal.read_record(folder / "a.npz").acc[:300], 0.05)
    records = pd.concat([index.iloc[:1], pd.DataFrame({"record": ["cut"], "path": [str(folder / "cut.npz")],
                                                       "time": pd.Timestamp("2025-06-01")})], ignore_index=True)
    capsys.readouterr()
    identify_chunk(records, config["identify"], tmp_path / "m.csv", tmp_path / "f.csv", config["layout"])
    assert capsys.readouterr().err.splitlines() == [
        "a.npz: ModalWarning: channel 0 clipped: 5 samples at its extreme",
        "a.npz: ModalWarning: channel 2 clipped: 5 samples at its extreme",
        "cut: ModalWarning: channel 0 clipped: 5 samples at its extreme",
        "cut: ModalWarning: channel 2 clipped: 5 samples at its extreme"]
    assert pd.read_csv(tmp_path / "f.csv")["reason"].tolist() == ["too short"]
    warned = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # none escapes identify_one
        identify_one(folder / "a.npz", config["identify"], warned=warned)
    assert warned == ["ModalWarning: channel 0 clipped: 5 samples at its extreme",
                      "ModalWarning: channel 2 clipped: 5 samples at its extreme"]
    assert identify_one(folder / "a.npz", config["identify"]).modes["mode"].tolist() == [1, 2]


def test_a_chunk_keeps_the_trusted_modes_only(folder, monkeypatch, tmp_path):
    """A mode the selection flags as doubtful (its flag says why) is not
    written, so never tracked; an empty or missing flag is trusted."""
    def identify_record(acc, dt, options):
        result = Result(acc, dt)
        result.modes = pd.concat([result.modes, result.modes.iloc[:1].assign(mode=3)], ignore_index=True)
        result.modes["flag"] = ["", "low MPC 0.41", np.nan]
        result.shapes = np.hstack([result.shapes, result.shapes[:, :1] + 100])
        return result, None

    monkeypatch.setattr(modal.measured, "identify_record", identify_record)
    config, index = read_campaign(write(folder, "records: {index: i.csv}\n" + IDENTIFY))
    identify_chunk(index.iloc[:1], config["identify"], tmp_path / "m.csv", tmp_path / "f.csv", config["layout"])
    modes = pd.read_csv(tmp_path / "m.csv")
    assert modes["mode"].tolist() == [1, 3]
    assert modes["phi_0"].iloc[1] == pytest.approx(modes["phi_0"].iloc[0] + 100)


def _lvm(path, unit, n=400):
    """A one-channel LabVIEW record at 20 Hz whose header names its unit."""
    header = ("LabVIEW Measurement\t\nWriter_Version\t2\nReader_Version\t2\nSeparator\tTab\nDecimal_Separator\t.\n"
              "Multi_Headings\tNo\nX_Columns\tOne\nTime_Pref\tRelative\nOperator\tx\n***End_of_Header***\t\n\t\n"
              f"Channels\t1\t\nSamples\t{n}\t\nY_Unit_Label\t{unit}\t\nX_Dimension\tTime\t\n"
              "X0\t0.0000000000000000E+0\t\nDelta_X\t0.05\t\n***End_of_Header***\t\t\nX_Value\tAcceleration\tComment\n")
    rng = np.random.default_rng(len(str(path)))
    path.write_text(header + "".join(f"{0.05 * i:.2f}\t{v:.6E}\n" for i, v in enumerate(rng.standard_normal(n))))
    return path


def test_a_record_in_other_units_fails_naming_them(tmp_path, stand_in):
    """A logger switched from g to m/s^2: the record fails with both units
    (its shapes would mix units); the same unit in other case does not."""
    for name, unit in (("a", "g"), ("b", "m/s^2"), ("c", "G"), ("d", "m/s²")):
        _lvm(tmp_path / f"{name}.lvm", unit)
    (tmp_path / "i.csv").write_text("path,time\na.lvm,2025-01-01\nb.lvm,2025-01-02\nc.lvm,2025-01-03\n")
    config, _ = read_campaign(write(tmp_path, "records: {index: i.csv}\n" + IDENTIFY))
    assert config["layout"]["units"] == ["g"]
    with pytest.raises(ValueError, match=r"^channel 0 in m/s2, the campaign's records in g: the "
                                         r"shapes would mix units$"):
        identify_one(tmp_path / "b.lvm", config["identify"], config["layout"])
    spelt = dict(config["layout"], units=["m/s2"])  # the same unit spelt otherwise is one unit
    assert identify_one(tmp_path / "d.lvm", config["identify"], spelt) is not None
    assert identify_one(tmp_path / "c.lvm", config["identify"], config["layout"]) is not None
    npz = dict(config["layout"], units=[None])  # a record that names no unit is not compared
    assert identify_one(tmp_path / "b.lvm", config["identify"], npz) is not None


def test_the_rate_is_compared_to_one_part_in_a_billion(folder, stand_in):
    layout = {"n_channels": 3, "fs": 20.0 * (1 + 1e-6)}
    with pytest.raises(ValueError, match=r"^sampled at 20 Hz, the campaign's records at 20 Hz$"):
        identify_one(folder / "a.npz", {"excitation": "ambient"}, layout)
    layout["fs"] = 20.0 * (1 + 1e-11)
    assert identify_one(folder / "a.npz", {"excitation": "ambient"}, layout).modes["freq_hz"][1] == 20


def test_a_failure_reason_is_one_line():
    assert _reason(ValueError("fmax above\n   Nyquist")) == "fmax above Nyquist"
    assert _reason(OSError(2, "No such file")) == "[Errno 2] No such file"
    assert _reason(ValueError()) == "ValueError"
    assert _reason(MemoryError()) == "out of memory"
    assert _reason(MemoryError("12 GB")) == "out of memory (12 GB)"
    assert _reason(Exception("bad UFF")) == "Exception: bad UFF"
    assert _reason(KeyError()) == "KeyError"


def test_gather_reads_every_chunk_in_order(tmp_path):
    columns = ",".join(MODE_COLUMNS)
    (tmp_path / "m0.csv").write_text(f"{columns},phi_0\na,2025-01-01,1,2.5,0.1,0.01,0.001,0.9,5,1.0\n")
    (tmp_path / "m1.csv").write_text(f"{columns}\n")
    (tmp_path / "m2.csv").write_text(f"{columns},phi_0\nb,2025-01-02,1,2.6,0.1,0.01,0.001,0.9,5,-1.0\n")
    (tmp_path / "f0.csv").write_text("record,reason\nx,broken\n")
    (tmp_path / "f1.csv").write_text("record,reason\ny,short\n")
    modes, failed = gather([tmp_path / f"m{k}.csv" for k in range(3)], [tmp_path / "f0.csv", tmp_path / "f1.csv"])
    assert list(modes["record"]) == ["a", "b"] and list(modes["freq_hz"]) == [2.5, 2.6]
    assert list(modes.index) == [0, 1]
    assert modes["time"].tolist() == [pd.Timestamp("2025-01-01"), pd.Timestamp("2025-01-02")]
    assert list(failed["record"]) == ["x", "y"] and list(failed.index) == [0, 1]
    modes, failed = gather([tmp_path / "m1.csv"], [])
    assert modes.empty and list(modes.columns) == MODE_COLUMNS and list(failed.columns) == ["record", "reason"]
    assert str(modes["time"].dtype).startswith("datetime64")


def test_shapes_are_channels_by_modes_in_channel_order():
    modes = pd.DataFrame({"phi_10": [10, 11], "phi_2": [2, 3], "phi_0": [0, 1], "freq_hz": [1.0, 2.0]})
    shapes = shape_matrix(modes)
    assert shapes.tolist() == [[0, 1], [2, 3], [10, 11]] and shapes.dtype == float


# -- content hashes ---------------------------------------------------------------

def test_a_file_hash_is_the_sha256_of_all_its_bytes(tmp_path):
    data = bytes(range(256)) * (5 * 4096 + 3)  # 5 MiB and a bit: several blocks
    (tmp_path / "big").write_bytes(data)
    assert file_hash(tmp_path / "big") == hashlib.sha256(data).hexdigest()


def test_the_cache_is_trusted_while_the_status_is_unchanged(tmp_path):
    path, cache = tmp_path / "r.bin", tmp_path / "deep" / "er" / "cache.json"
    path.write_bytes(b"abc")
    (tmp_path / "folder").mkdir()
    hashes = content_hashes([tmp_path / "none", tmp_path / "folder", path], cache=cache)
    assert hashes == {str(path): hashlib.sha256(b"abc").hexdigest(), str(tmp_path / "folder"): None,
                      str(tmp_path / "none"): None}
    st = path.stat()
    written = json.loads(cache.read_text())
    assert written == {str(path): [[st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns], hashes[str(path)]]}
    assert not list(cache.parent.glob("*.tmp"))
    written[str(path)][1] = "from the cache"
    cache.write_text(json.dumps(written))
    stamp = cache.stat().st_mtime_ns
    time.sleep(0.01)
    assert content_hashes([path], cache=cache) == {str(path): "from the cache"}  # not read again
    assert cache.stat().st_mtime_ns == stamp  # nothing new: not rewritten
    assert content_hashes([path]) == {str(path): hashes[str(path)]}
    written[str(path)][0][1] += 1  # another size: hashed again
    cache.write_text(json.dumps(written))
    assert content_hashes([path], cache=cache) == {str(path): hashes[str(path)]}
    assert json.loads(cache.read_text())[str(path)][1] == hashes[str(path)]
    cache.write_text("{not json")
    assert content_hashes([path], cache=cache) == {str(path): hashes[str(path)]}
    assert json.loads(cache.read_text())[str(path)][1] == hashes[str(path)]
    assert content_hashes([path], cache=tmp_path / "none" / "x" / "c.json")[str(path)] == hashes[str(path)]


# -- Snakemake's locks ------------------------------------------------------------

def sleeper(cwd, *words):
    return subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)", *words], cwd=cwd)


def fake_snakemake(folder, cwd, *args):
    """A process whose command line is Snakemake's (``python .../snakemake
    ARGS``), working in ``cwd``."""
    script = Path(folder) / "snakemake"
    script.write_text(f"#!{sys.executable}\nimport time\ntime.sleep(60)\n")
    script.chmod(0o755)
    return subprocess.Popen([os.fsencode(script), *args], cwd=cwd)


def test_live_snakemake_processes_are_those_working_here(tmp_path):
    here, elsewhere = tmp_path / "here", tmp_path / "elsewhere"
    here.mkdir()
    elsewhere.mkdir()
    ours, other, away = fake_snakemake(tmp_path, here), sleeper(here, "snakemake"), fake_snakemake(tmp_path, elsewhere)
    try:
        time.sleep(0.3)
        found = live_snakemake_processes(here)
        assert found == {ours.pid: f"{sys.executable} {tmp_path / 'snakemake'}"}
        assert live_snakemake_processes(here / ".." / "here") == found
        assert live_snakemake_processes(here, exclude={ours.pid}) == {}
        (here / ".snakemake" / "locks").mkdir(parents=True)
        (here / ".snakemake" / "locks" / "1.input.lock").write_text("")
        assert clear_stale_locks(here) == (0, found)
        assert (here / ".snakemake" / "locks" / "1.input.lock").exists()
    finally:
        for p in (ours, other, away):
            p.kill()
            p.wait()


def leftover_snakemake(folder, cwd, ignore_sigint=False) -> subprocess.Popen:
    """A Snakemake left running by a caller killed alone (``python
    .../snakemake``, working in ``cwd``), with a job of its own that works
    elsewhere; ``ignore_sigint``: one that Ctrl-C does not stop."""
    script = Path(folder) / "left" / "snakemake"
    script.parent.mkdir(exist_ok=True)
    script.write_text(f"#!{sys.executable}\nimport signal, subprocess, sys, time\n"
                      "job = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(60)'], cwd='/')\n"
                      + ("signal.signal(signal.SIGINT, signal.SIG_IGN)\n" if ignore_sigint else "")
                      + "time.sleep(60)\n")
    script.chmod(0o755)
    return subprocess.Popen([str(script), "--cores", "1"], cwd=cwd)


def started_job(pid) -> int:
    """The one job of the left Snakemake ``pid``, once it runs its own
    program: a child seen between fork and exec still holds its parent's
    signal handlers, and a SIGINT that reaches it then is lost with them."""
    expected = f"{sys.executable} -c import time; time.sleep(60)"
    wait_until(lambda: len(descendants(pid)) == 1 and " ".join(modal._locks._argv(descendants(pid)[0])) == expected)
    return descendants(pid)[0]


def test_a_run_left_working_in_the_folder_is_stopped_with_its_jobs_and_nothing_else(tmp_path):
    here, elsewhere = tmp_path / "here", tmp_path / "elsewhere"
    here.mkdir()
    elsewhere.mkdir()
    left = leftover_snakemake(tmp_path, here)
    others = [sleeper(here, "snakemake"), fake_snakemake(tmp_path, elsewhere)]  # no run here
    try:
        job = started_job(left.pid)
        # no lock held: no run is interrupted (a dry run takes none)
        assert stop_leftover_run(here, grace=5.0) == ({}, {})
        assert left.poll() is None
        (here / ".snakemake" / "locks").mkdir(parents=True)
        (here / ".snakemake" / "locks" / "0.input.lock").write_text("")
        stopped, alive = stop_leftover_run(here, grace=20.0)
        assert set(stopped) == {left.pid, job} and alive == {}
        assert stopped[job] == f"{sys.executable} -c import time; time.sleep(60)"
        assert left.wait(timeout=5) == -signal.SIGINT and not modal._locks._alive(job)
        assert [p.poll() for p in others] == [None, None]  # not signalled
    finally:
        for p in (left, *others):
            p.kill()
            p.wait()


def test_a_left_run_that_does_not_stop_on_sigint_is_returned_alive(tmp_path):
    (tmp_path / "here" / ".snakemake" / "locks").mkdir(parents=True)
    (tmp_path / "here" / ".snakemake" / "locks" / "0.input.lock").write_text("")
    stubborn = leftover_snakemake(tmp_path, tmp_path / "here", ignore_sigint=True)
    try:
        job = started_job(stubborn.pid)
        stopped, alive = stop_leftover_run(tmp_path / "here", grace=0.5)
        assert set(stopped) == {job} and set(alive) == {stubborn.pid} and stubborn.poll() is None
    finally:
        stubborn.kill()
        stubborn.wait()


def test_without_proc_a_left_run_cannot_be_seen_and_nothing_is_signalled(tmp_path, monkeypatch):
    (tmp_path / ".snakemake" / "locks").mkdir(parents=True)
    (tmp_path / ".snakemake" / "locks" / "0.input.lock").write_text("")
    real = Path.exists
    monkeypatch.setattr(Path, "exists", lambda p: False if str(p) == "/proc/self" else real(p))
    signalled = []
    monkeypatch.setattr(os, "kill", lambda pid, signum: signalled.append(pid))  # pid 0 would be this group
    assert stop_leftover_run(tmp_path, grace=1.0) == ({}, {}) and signalled == []


def test_a_process_is_alive_until_it_ends_a_zombie_or_reaped():
    assert modal._locks._alive(os.getpid())
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    wait_until(lambda: not modal._locks._alive(child.pid))  # ended, not yet reaped: a zombie
    assert Path(f"/proc/{child.pid}").exists()
    child.wait()
    assert not modal._locks._alive(child.pid)  # reaped: no /proc entry


def wait_until(condition, seconds=20.0):
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


def test_a_command_line_that_is_not_utf8_is_read(tmp_path):
    odd = fake_snakemake(tmp_path, tmp_path, b"\xff", b"--cores")
    try:
        time.sleep(0.3)
        assert live_snakemake_processes(tmp_path) == {odd.pid: f"{sys.executable} {tmp_path / 'snakemake'} "
                                                               "\ufffd --cores"}
    finally:
        odd.kill()
        odd.wait()


def test_stale_locks_are_listed_and_cleared(tmp_path, monkeypatch):
    assert stale_locks(tmp_path) == ([], {}) and clear_stale_locks(tmp_path) == (0, {})
    locks = tmp_path / ".snakemake" / "locks"
    locks.mkdir(parents=True)
    assert stale_locks(tmp_path) == ([], {})
    for name in ("1.output.lock", "0.input.lock", "notes.txt"):
        (locks / name).write_text("")
    assert stale_locks(tmp_path) == ([locks / "0.input.lock", locks / "1.output.lock"], {})
    # this process and its parent are not a run, whatever their command line
    code = ("import sys; from modal._locks import stale_locks; held, live = stale_locks(sys.argv[1]); "
            "print(len(held), live)")
    shown = subprocess.run([sys.executable, "-c", code, str(tmp_path), "snakemake"], cwd=tmp_path,
                           capture_output=True, text=True, check=True).stdout
    assert shown == "2 {}\n"
    assert clear_stale_locks(tmp_path) == (2, {})
    assert sorted(p.name for p in locks.iterdir()) == ["notes.txt"]
    # without /proc no process can be seen: the locks are left alone
    (locks / "0.input.lock").write_text("")
    real = Path.exists
    monkeypatch.setattr(Path, "exists", lambda p: False if str(p) == "/proc/self" else real(p))
    held, live = stale_locks(tmp_path)
    assert (held, live) == ([locks / "0.input.lock"],
                            {0: "unknown (no /proc): if no run is active, run `snakemake --unlock` once"})
    assert clear_stale_locks(tmp_path)[0] == 0 and (locks / "0.input.lock").exists()
    # a lock gone meanwhile (its run ended between listing and removing) is no error
    monkeypatch.setattr(modal._locks, "stale_locks", lambda root: ([locks / "gone.lock", locks / "0.input.lock"], {}))
    assert clear_stale_locks(tmp_path) == (2, {}) and not (locks / "0.input.lock").exists()


def test_the_caller_and_its_parent_are_not_a_run(tmp_path):
    """Started by a process whose command line names snakemake (a job
    Snakemake runs), working in the same folder: neither is a live run."""
    locks = tmp_path / ".snakemake" / "locks"
    locks.mkdir(parents=True)
    (locks / "0.input.lock").write_text("")
    inner = ("import sys; from modal._locks import stale_locks; held, live = stale_locks(sys.argv[1]); "
             "print(len(held), live)")
    outer = "import subprocess, sys; subprocess.run([sys.executable, '-c', sys.argv[1], sys.argv[2]], check=True)"
    shown = subprocess.run([sys.executable, "-c", outer, inner, str(tmp_path), "snakemake"], cwd=tmp_path,
                           capture_output=True, text=True, check=True).stdout
    assert shown == "1 {}\n"


# -- --out over the inputs ------------------------------------------------------

def test_an_output_folder_overlapping_an_input_says_how(tmp_path):
    inputs = [tmp_path / "c" / "campaign.yaml", tmp_path / "c" / "records" / "a.npz"]
    assert _overlapping_input(tmp_path / "out", inputs) is None
    assert _overlapping_input(tmp_path / "c", inputs) == f"holds the input {inputs[0]}"
    assert _overlapping_input(tmp_path / "c" / "records" / "a.npz", inputs) == f"is the input {inputs[1]}"
    assert _overlapping_input(tmp_path / "c" / "campaign.yaml" / "x", inputs) == f"lies inside the input {inputs[0]}"
    assert _overlapping_input(Path("."), [Path("x")]) == f"holds the input {Path('x').resolve()}"


# -- what the records agree on, the index's times and columns, the references --


@pytest.fixture
def simulated(tmp_path):
    """Five 10-second records of the simulated frame (4 channels at 50 Hz),
    one a day, and their campaign file (no geometry)."""
    from modal.campaign import simulate_campaign

    simulate_campaign(tmp_path, n_records=5, every_hours=24, duration=10.0)
    (tmp_path / "campaign.yaml").write_text("records: {index: index.csv}\nidentify: {excitation: ambient}\n")
    return tmp_path, pd.read_csv(tmp_path / "index.csv")


def test_the_layout_is_the_one_the_records_agree_on_whatever_the_first(simulated):
    """The first record with a channel fewer, or at twice the rate: the
    layout is the others' (4 channels, 50 Hz), with no record's name in it;
    a record of another layout is refused in its job."""
    folder, index = simulated
    first = folder / index["path"][0]
    good = modal.read_record(first)
    modal.save_record_npz(first, good.acc[:, :3], good.dt)
    config, _ = read_campaign(folder / "campaign.yaml")
    assert config["layout"] == {"n_channels": 4, "fs": 50.0, "units": [None] * 4}
    with pytest.raises(ValueError, match="^3 channels, the campaign's records 4$"):
        identify_one(first, config["identify"], config["layout"])
    modal.save_record_npz(first, np.repeat(good.acc, 2, axis=0), good.dt / 2)
    config, _ = read_campaign(folder / "campaign.yaml")
    assert config["layout"] == {"n_channels": 4, "fs": 50.0, "units": [None] * 4}
    with pytest.raises(ValueError, match="^sampled at 100 Hz, the campaign's records at 50 Hz$"):
        identify_one(first, config["identify"], config["layout"])
    # settings no record of the layout takes are refused, naming the layout and how many records agree
    (folder / "c.yaml").write_text("records: {index: index.csv}\nidentify: {excitation: ambient, fmax: 30}\n")
    with pytest.raises(ValueError, match=r"identify.fmax = 30 Hz must be below the Nyquist frequency 25 Hz .*"
                                         r"\(the campaign's records: 4 channels at 50 Hz, as \S+0102_0000.npz and "
                                         r"3 other\(s\) of the 5 read\)"):
        read_campaign(folder / "c.yaml")


def test_times_with_utc_offsets_are_converted_to_utc_a_mix_with_none_is_refused(simulated):
    """Daylight saving: +01:00 in winter, +02:00 in summer, converted to UTC
    (pandas alone refuses the mix); times with an offset and times without
    are refused naming a row of each."""
    folder, index = simulated
    index["time"] = ["2025-01-01T01:00:00+01:00", "2025-03-30T03:00:00+02:00", "2025-03-30T01:30:00+01:00",
                     "2025-07-01T00:00:00Z", "2025-10-26T02:30:00+01:00"]
    index.to_csv(folder / "index.csv", index=False)
    _, read = read_campaign(folder / "campaign.yaml")
    assert [str(t) for t in read["time"]] == ["2025-01-01 00:00:00+00:00", "2025-03-30 00:30:00+00:00",
                                              "2025-03-30 01:00:00+00:00", "2025-07-01 00:00:00+00:00",
                                              "2025-10-26 01:30:00+00:00"]
    index.loc[3, "time"] = "2025-07-01T00:00:00"
    index.to_csv(folder / "index.csv", index=False)
    with pytest.raises(ValueError, match=r"index.csv: row 5: time '2025-07-01T00:00:00' has no UTC offset, row 2's "
                                         r"'2025-01-01T01:00:00\+01:00' has one"):
        read_campaign(folder / "campaign.yaml")


def test_index_columns_named_as_the_campaigns_own_are_kept_under_a_prefix(simulated):
    folder, index = simulated
    index["record"], index["mode"], index["freq_hz"], index["index_mode"] = "r", 1, 2.5, 3
    index.to_csv(folder / "index.csv", index=False)
    _, read = read_campaign(folder / "campaign.yaml")
    assert list(read.columns) == ["record", "path", "time", "temperature_c", "index_record", "index_index_mode",
                                  "index_freq_hz", "index_mode"]
    assert list(read["record"]) == list(index["path"]) and list(read["index_freq_hz"]) == [2.5] * 5
    assert list(read["index_index_mode"]) == [1] * 5 and list(read["index_mode"]) == [3] * 5


def test_reference_modes_are_checked_before_any_job(simulated, tmp_path):
    folder, _ = simulated
    text = "records: {index: index.csv}\nidentify: {excitation: ambient}\ntracking: {reference_modes: r.csv}\n"
    good = "freq_hz,phi_0,phi_1,phi_2,phi_3\n1.6,0.2,0.4,0.6,0.7\n4.2,-0.5,-0.5,0,0.7\n"
    for given, tail in [
            ("freq_hz,phi_0,phi_1,phi_2\n1.6,0.2,0.4,0.6\n", " has shapes over 3 channels, the records have 4"),
            ("freq_hz,phi_0,phi_1,phi_2,phi_3\n", ": no reference mode (a header and no row)"),
            ("freq_hz\n1.6\n", ": reference modes need a freq_hz column and shape columns phi_...; it has freq_hz"),
            ("freq_hz,phi_0,phi_1,phi_2,phi_3\n1.6,0.2,,0.6,0.7\n", ": row 2: phi_1 (empty) is not a finite number"),
            ("freq_hz,phi_0,phi_1,phi_2,phi_3\n-1,0.2,0.4,0.6,0.7\n",
             ": row 2: freq_hz '-1' is not a positive frequency"),
            (good + "1.6,0.2,0.4,0.6,0.7\n", ": row 4 repeats row 2: give each mode once")]:
        (folder / "r.csv").write_text(given)
        refused(folder, text, f"c.yaml: tracking.reference_modes: {folder / 'r.csv'}{tail}")
    (folder / "r.csv").write_text(good)
    assert read_campaign(write(folder, text))[0]["tracking"]["reference_modes"] == str(folder / "r.csv")
    # with identify.channels, as many shape entries as channels named
    refused(folder, text.replace("ambient}", "ambient, channels: [0, 1]}"),
            "has shapes over 4 channels, identify.channels names 2")
    # refused before any job: exit 2, no output folder
    (folder / "r.csv").write_text("freq_hz,phi_0\n1.6,1\n")
    assert modal.cli.main(["campaign", str(write(folder, text)), "--out", str(tmp_path / "out")]) == 2
    assert not (tmp_path / "out").exists()


def test_npy_records_without_identify_fs_are_refused_naming_it(simulated, tmp_path):
    folder, index = simulated
    for p in index["path"]:
        np.save(folder / p.replace(".npz", ".npy"), modal.read_record(folder / p).acc)
    index["path"] = index["path"].str.replace(".npz", ".npy")
    index.to_csv(folder / "index.csv", index=False)
    refused(folder, "records: {index: index.csv}\nidentify: {excitation: ambient}\n",
            "c.yaml: identify.fs: 5 record(s) are .npy arrays, which hold no sampling rate (e.g. "
            f"{index['path'][0]}): give their rate as identify.fs (Hz) in the campaign file")
    config, _ = read_campaign(write(folder, "records: {index: index.csv}\nidentify: {excitation: ambient, fs: 50}\n"))
    assert config["layout"] == {"n_channels": 4, "fs": 50.0, "units": [None] * 4}
    # an .npz without its rate, in the sample: refused the same way; in a job, its reason names identify.fs,
    # not the command line's --fs
    np.savez(folder / "t.npz", acc=modal.read_record(folder / index["path"][0], fs=50).acc)
    (folder / "i.csv").write_text("path,time\nt.npz,2025-01-01\n")
    refused(folder, "records: {index: i.csv}\nidentify: {excitation: ambient}\n",
            "c.yaml: identify.fs: record t.npz holds no sampling rate: give the rate of the campaign's records as "
            "identify.fs (Hz) in the campaign file")
    identify_chunk(pd.DataFrame({"record": ["t.npz"], "path": [str(folder / "t.npz")], "time": ["2025-01-01"]}),
                   {"excitation": "ambient"}, tmp_path / "m.csv", tmp_path / "f.csv")
    reason = pd.read_csv(tmp_path / "f.csv")["reason"][0]
    assert "identify.fs (Hz) in the campaign file" in reason and "--fs" not in reason


def test_chunks_write_iso_times_and_gather_reads_any_mix(simulated, tmp_path):
    """A chunk of whole days and one with a fractional second: each writes
    ISO 8601 (2025-01-01T00:00:00); gather reads them together, and chunks
    written before (2025-01-01 beside 2025-05-01 00:00:00) too."""
    folder, index = simulated
    config, read = read_campaign(folder / "campaign.yaml")
    records = read[["record", "path", "time"]].astype(str)
    records.loc[3:, "time"] = ["2025-05-01 00:00:00.250000", "2025-05-02 10:00:00"]
    identify_chunk(records.iloc[:3], config["identify"], tmp_path / "m0.csv", tmp_path / "f0.csv", config["layout"])
    identify_chunk(records.iloc[3:], config["identify"], tmp_path / "m1.csv", tmp_path / "f1.csv", config["layout"])
    assert set(pd.read_csv(tmp_path / "m0.csv")["time"]) == {"2025-01-01T00:00:00", "2025-01-02T00:00:00",
                                                             "2025-01-03T00:00:00"}
    assert set(pd.read_csv(tmp_path / "m1.csv")["time"]) == {"2025-05-01T00:00:00.250000", "2025-05-02T10:00:00"}
    modes, _ = gather([tmp_path / "m0.csv", tmp_path / "m1.csv"], [tmp_path / "f0.csv", tmp_path / "f1.csv"])
    assert sorted(set(modes["time"])) == [pd.Timestamp(t) for t in ("2025-01-01", "2025-01-02", "2025-01-03",
                                                                    "2025-05-01 00:00:00.25", "2025-05-02 10:00")]
    columns = ",".join(MODE_COLUMNS)
    (tmp_path / "old0.csv").write_text(f"{columns},phi_0\na,2025-01-01,1,2.5,0.1,0.01,0.001,0.9,5,1.0\n")
    (tmp_path / "old1.csv").write_text(f"{columns},phi_0\nb,2025-05-01 00:00:00,1,2.6,0.1,0.01,0.001,0.9,5,1.0\n")
    modes, _ = gather([tmp_path / "old0.csv", tmp_path / "old1.csv"], [])
    assert modes["time"].tolist() == [pd.Timestamp("2025-01-01"), pd.Timestamp("2025-05-01")]
