"""IdentifyOptions: one home for every option of an identification.

Every field is enumerated from the class (never a hand list), so a new option
without its description, schema and example, or one dropped on the way from a
campaign file, a workflow config, the command line or a roving setup to
:func:`modal.identify_record`, turns these tests red.
"""

import dataclasses
import math
import runpy
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

import modal
import modal.measured._pipeline as pipeline
import modal.thesis.config
from modal.measured import MAX_ORDER, IdentifyOptions

ROOT = Path(__file__).resolve().parents[3]
FIELDS = dataclasses.fields(IdentifyOptions)
EXAMPLES = {f.name: f.metadata["example"] for f in FIELDS}


class Captured(Exception):
    """Raised by the stand-in of identify_record once it has seen the options."""


@pytest.fixture
def capture(monkeypatch):
    """Replace identify_record where every route calls it; the options it
    receives are kept in the returned list (the call then stops)."""
    seen = []

    def stand_in(acc, dt, options=None, **keywords):
        seen.append(modal.measured.identify_options(options, **{k: v for k, v in keywords.items()
                                                                if k in IdentifyOptions.names()}))
        raise Captured

    monkeypatch.setattr(modal.measured, "identify_record", stand_in)
    monkeypatch.setattr(pipeline, "identify_record", stand_in)
    return seen


@pytest.fixture
def record(tmp_path):
    """A 2-channel ``.npy`` record (as many as the examples use): its rate is what ``fs`` says."""
    np.save(tmp_path / "rec.npy", np.random.default_rng(1).standard_normal((3000, 2)))
    return tmp_path / "rec.npy"


def test_every_field_is_documented_bounded_and_has_a_non_default_example():
    for f in FIELDS:
        assert f.metadata["help"] and f.metadata["schema"], f.name
        if f.metadata["flag"] is None:  # one flag per value: each value has its help
            assert sorted(f.metadata["choices"]) == sorted(f.metadata["schema"]["enum"]), f.name
        default = None if f.default is dataclasses.MISSING else f.default
        assert EXAMPLES[f.name] != default, f"{f.name}: the example must differ from the default"
    options = IdentifyOptions(**EXAMPLES)  # the examples hold together
    assert options.to_dict() == {k: list(v) if isinstance(v, tuple) else v for k, v in EXAMPLES.items()}
    assert IdentifyOptions(excitation="ambient").max_order == MAX_ORDER == 60


def test_the_workflow_schema_holds_the_options_schema():
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    measured = schema["properties"]["measured"]["additionalProperties"]
    assert {k: measured["properties"][k] for k in IdentifyOptions.names()} == \
        IdentifyOptions.json_schema()["properties"]
    assert "excitation" in measured["required"]


def test_the_campaign_schema_is_the_options_schema():
    from modal.campaign._config import SCHEMA

    identify = SCHEMA["properties"]["identify"]
    assert identify["properties"] == IdentifyOptions.json_schema()["properties"]
    assert identify["required"] == ["excitation"] and identify["additionalProperties"] is False


def test_the_docs_option_table_lists_every_option_with_its_key():
    records = (ROOT / "docs/records.md").read_text()
    for f in FIELDS:
        if f.metadata["flag"]:
            flag = f"`{f.metadata['flag']} {f.metadata['metavar']}`"
        else:
            flag = " / ".join(f"`--{v.replace('_', '-')}`" for v in f.metadata["schema"]["enum"])
        assert f"| {flag} | `{f.name}` |" in records, f"docs/records.md: no row for {f.name}"


@pytest.mark.parametrize("name", IdentifyOptions.names())
def test_each_option_in_a_campaign_file_reaches_identify_record(name, tmp_path, record, capture):
    given = {"excitation": "ambient", "fs": 100.0, name: EXAMPLES[name]}
    identify = {k: list(v) if isinstance(v, tuple) else v for k, v in given.items()}
    (tmp_path / "index.csv").write_text("path,time\nrec.npy,2025-01-01 00:00\n")
    (tmp_path / "c.yaml").write_text(yaml.safe_dump({"records": {"index": "index.csv"}, "identify": identify}))
    config, index = modal.campaign.read_campaign(tmp_path / "c.yaml")
    with pytest.raises(Captured):
        modal.campaign.identify_one(index["path"][0], config["identify"])
    received = capture[0]
    assert getattr(received, name) == EXAMPLES[name]
    assert received == IdentifyOptions(**given)  # and nothing else changed


def test_every_option_in_a_workflow_config_reaches_identify_record(tmp_path, record, capture, monkeypatch):
    spec = {"path": str(record), **{k: list(v) if isinstance(v, tuple) else v for k, v in EXAMPLES.items()}}
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    import jsonschema

    jsonschema.validate({"x": spec}, schema["properties"]["measured"])
    assert modal.thesis.config.measured_problems("measured.x", spec) == []
    job = SimpleNamespace(params=SimpleNamespace(spec=spec), input=SimpleNamespace(record=str(record)),
                          output=SimpleNamespace(modes=str(tmp_path / "out" / "modes.csv")), threads=1,
                          log=[str(tmp_path / "job.log")])
    monkeypatch.setattr(sys, "stderr", sys.stderr)  # the job sends it to its log
    monkeypatch.syspath_prepend(str(ROOT / "workflow/scripts"))
    try:
        with pytest.raises(Captured):
            runpy.run_path(str(ROOT / "workflow/scripts/measured.py"), init_globals={"snakemake": job})
    finally:
        if sys.stderr is not sys.__stderr__ and getattr(sys.stderr, "name", "") == job.log[0]:
            sys.stderr.close()
    assert capture[0] == IdentifyOptions(**EXAMPLES)


def test_every_option_on_the_command_line_reaches_identify_record(tmp_path, record, capture):
    from modal.cli import main

    argv = ["identify", str(record), "--out", str(tmp_path / "o"), "--quiet"]
    for f in FIELDS:
        value = EXAMPLES[f.name]
        if f.metadata["flag"] is None:
            argv.append(f"--{value.replace('_', '-')}")
        else:
            argv += [f.metadata["flag"], ",".join(map(str, value)) if isinstance(value, tuple) else str(value)]
    assert main(argv) == 1, "the stand-in stops the identification (an internal error)"
    assert capture[0] == IdentifyOptions(**EXAMPLES)


def test_a_roving_setup_is_identified_with_the_options_and_its_own_channels(capture):
    plate = modal.SimplySupportedPlate(1.2, 0.8, 20.0, 10.0)
    setup = modal.plate_roving_test(plate, duration=20.0)[0][1]
    given = {k: v for k, v in EXAMPLES.items() if k not in ("channels", "refs", "quantities")}
    with pytest.raises(Captured):
        modal.identify_setup(setup, IdentifyOptions(**given))
    received = capture[0]  # every channel a reference of the correlations, as modal identify alone (issue 33)
    assert received == IdentifyOptions(**given).replace(quantities=list(setup.channels["quantity"]))
    with pytest.raises(ValueError, match="channels: a setup's channel table says"):
        modal.identify_setup(setup, IdentifyOptions(excitation="ambient", channels=[0]))


@pytest.mark.parametrize("changes, message", [
    ({"excitation": "forced"}, "excitation must be one of ambient, free_decay"),
    ({"max_order": 41}, "max_order must be even"),
    ({"max_order": 0}, "max_order must be at least 2"),
    ({"max_order": True}, "max_order must be an integer"),
    ({"rows": 30.0}, "rows must be an integer"),
    ({"fmax": math.nan}, "fmax must be a positive finite number"),
    ({"fmax": -1.0}, "fmax must be a positive finite number"),
    ({"highpass_hz": 5.0, "fmax": 5.0}, "highpass_hz = 5 Hz must be below fmax = 5 Hz"),
    ({"highpass_hz": 6.0, "fmax": 5.0}, "highpass_hz = 6 Hz must be below fmax"),
    ({"channels": [0, 1], "refs": [2]}, r"refs \[2\] are not among the channels used \[0, 1\]"),
    ({"channels": [0, 0]}, "names a channel twice"),
    ({"channels": [0, 1], "quantities": ["velocity"]}, "one quantity per channel used"),
    ({"quantities": ["speed"]}, "quantities must name one of"),
    ({"fs": 10.0, "fmax": 5.0}, "fmax = 5 Hz must be below the Nyquist frequency 5 Hz"),
])
def test_contradictions_are_refused_with_the_option_named(changes, message):
    with pytest.raises(ValueError, match=message):
        IdentifyOptions(**{"excitation": "ambient", **changes})


def test_what_holds_just_inside_the_bounds():
    options = IdentifyOptions(excitation="ambient", fs=10.0, fmax=4.999, highpass_hz=4.99, max_order=2, rows=1,
                              channels=[3, 1], refs=[3], quantities=["velocity", "acceleration"])
    assert options.channel_choice(4) == ([3, 1], [0])  # refs as positions among the channels used
    assert options.record_problems(4, 10.0) == []
    assert options.record_problems(3, 10.0) == ["channels [3]: the record has channels 0 ... 2",
                                                 "refs [3]: the record has channels 0 ... 2"]
    assert options.record_problems(4, 9.99) == [
        "fmax = 4.999 Hz must be below the Nyquist frequency 4.995 Hz (fs = 9.99 Hz)"]
    assert options.record_problems(4, 9.98) == [
        "fmax = 4.999 Hz must be below the Nyquist frequency 4.99 Hz (fs = 9.98 Hz)",
        "highpass_hz = 4.99 Hz must be below the Nyquist frequency 4.99 Hz (fs = 9.98 Hz)"]
    assert IdentifyOptions(excitation="ambient", quantities=["velocity"]).record_problems(2, 10.0) == [
        "quantities names 1 channels, the identification uses 2"]


def test_length_problems_need_twice_the_lags_in_the_record_as_identified():
    """An ambient record holds ``2 rows + 1`` lags in half its samples after
    the decimation ``floor(fs / (2.5 fmax))``: 121 lags for the 60 rows fmax
    brings on 2 channels (max_order 60), so 242 samples; rows given decide
    alone; 2 max_order / channels rows where more; a free decay, and rows the
    record chooses (neither fmax nor rows), are not judged here. Each
    message names the option, the samples and the bound the record allows."""
    ambient = IdentifyOptions(excitation="ambient", fmax=10.0)  # at 100 Hz: decimated by 4
    assert ambient.decimation(0.01) == 4 and ambient.fixed_rows(2) == 60
    assert ambient.length_problems(968, 0.01, 2) == []  # 242 samples after decimation: just enough
    assert ambient.length_problems(967, 0.01, 2) == [
        "fmax = 10 Hz decimates the 967-sample record by 4 to 241 samples, fewer than the 242 the identification "
        "needs (60 rows: 121 lags): fmax must be above 10 Hz for this record (or give rows = 59 at the most or a longer "
        "record)"]
    assert ambient.replace(fmax=10.01).length_problems(967, 0.01, 2) == []  # decimated by 3: 322 samples
    # 2 max_order / channels rows where more than 60: 100 for max_order 100 on 2 channels (used, not recorded)
    wide = ambient.replace(max_order=100)
    assert wide.fixed_rows(2) == 100 and wide.fixed_rows(4) == 60
    assert wide.length_problems(1608, 0.01, 2) == [] and wide.length_problems(1607, 0.01, 4) == []
    assert wide.length_problems(1607, 0.01, 2)[0].startswith("fmax = 10 Hz decimates the 1607-sample record by 4 "
                                                             "to 401 samples, fewer than the 402")
    # rows given, no fmax: no decimation; the most rows that fit are named where they still hold max_order
    rows = IdentifyOptions(excitation="ambient", rows=100, max_order=20)
    assert rows.decimation(0.01) == 1 and rows.length_problems(402, 0.01, 2) == []
    assert rows.length_problems(401, 0.01, 2) == [
        "rows = 100 needs 201 lags, more than half the 401-sample record: give rows = 99 at the most or a longer "
        "record"]
    assert rows.replace(max_order=200).length_problems(401, 0.01, 2) == [
        "rows = 100 needs 201 lags, more than half the 401-sample record: give a longer record"]
    # no fmax helps a record too short even undecimated
    assert IdentifyOptions(excitation="ambient", fmax=10.0, rows=100).length_problems(350, 0.01, 4) == [
        "fmax = 10 Hz decimates the 350-sample record by 4 to 87 samples, fewer than the 402 the identification "
        "needs (100 rows: 201 lags): no fmax is enough: give rows = 21 at the most or a "
        "longer record"]
    # fmax that does not decimate (below 2 x 2.5 fmax): the record as it is
    assert IdentifyOptions(excitation="ambient", fmax=30.0).decimation(0.01) == 1
    assert IdentifyOptions(excitation="ambient", fmax=30.0).length_problems(241, 0.01, 2)[0].startswith(
        "fmax = 30 Hz with 60 rows needs 121 lags, more than half the 241-sample record")
    assert IdentifyOptions(excitation="ambient").length_problems(10, 0.01, 2) == []
    # record_problems with the record's length: the same, after the problems of channels and rates only
    assert ambient.record_problems(2, 100.0, 967) == ambient.length_problems(967, 0.01, 2)
    assert ambient.record_problems(2, 100.0) == [] and ambient.record_problems(2, 100.0, 968) == []
    assert ambient.replace(channels=[0]).record_problems(2, 100.0, 967) == ambient.length_problems(967, 0.01, 1)
    assert ambient.replace(channels=[2]).record_problems(2, 100.0, 967) == ["channels [2]: the record has channels "
                                                                            "0 ... 1"]
    assert IdentifyOptions(excitation="free_decay", rows=100, fmax=10.0).length_problems(10, 0.01, 2) == []


def test_from_mapping_names_the_key():
    with pytest.raises(ValueError, match=r"c.yaml: identify.maxorder: not an option"):
        IdentifyOptions.from_mapping({"excitation": "ambient", "maxorder": 4}, where="c.yaml: identify")
    with pytest.raises(ValueError, match=r"here.excitation: required"):
        IdentifyOptions.from_mapping({"fmax": 4}, where="here")
    with pytest.raises(ValueError, match=r"here.max_order must be even"):
        IdentifyOptions.from_mapping({"excitation": "ambient", "max_order": 3}, where="here")
    kept = IdentifyOptions.from_mapping({"excitation": "ambient", "path": "x", "fmax": None}, other=["path"])
    assert kept == IdentifyOptions(excitation="ambient")


def test_channels_and_refs_are_the_records_numbers():
    """identify_record on the whole record with channels [2, 0, 1] and refs [0]
    is identify_record on those columns with the reference at position 1."""
    from ..cases import ambient_beam

    acc, dt, f_exact = ambient_beam()
    acc = acc[:, :3]
    chosen = IdentifyOptions(excitation="ambient", channels=[2, 0, 1], refs=[0], max_order=12,
                             fmax=f_exact[1] * 1.3)
    result, _ = modal.identify_record(acc, dt, chosen)
    by_hand, _ = modal.identify_record(acc[:, [2, 0, 1]], dt, "ambient", refs=[1], max_order=12,
                                       fmax=f_exact[1] * 1.3)
    assert result.shapes.shape[0] == 3 and len(result.modes) >= 1
    np.testing.assert_array_equal(result.modes["freq_hz"], by_hand.modes["freq_hz"])
    np.testing.assert_array_equal(result.shapes, by_hand.shapes)
    other_ref, _ = modal.identify_record(acc[:, [2, 0, 1]], dt, "ambient", refs=[0], max_order=12,
                                         fmax=f_exact[1] * 1.3)
    assert not np.array_equal(other_ref.modes["freq_hz"], result.modes["freq_hz"])
