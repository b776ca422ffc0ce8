"""Spikes: one to three samples far from both neighbours, then back, are
found sample for sample, named per channel with their count and times,
and replaced by the straight line between their neighbours before the
identification; a step, a smooth glitch, the onset of an impact and every
measured record the project ships are not spikes."""

import warnings
from pathlib import Path

import numpy as np
import pytest

import modal
from modal.records import despiked, spike_samples, spike_warnings
from modal.records._quality import SPIKE_RING_WINDOW, SPIKE_THRESHOLD, _MAD_TO_SIGMA, _spike_runs

from ..cases import PALISADEN, ambient_beam

DATA = Path(__file__).resolve().parents[2] / "data"
SHARED = Path(__file__).resolve().parents[3].parent / "shared" / "data"


def _smooth(n=20_000, fs=200.0, seed=3):
    """Two oversampled modes in light noise, as most measured records are
    (their second differences far below their standard deviation)."""
    t = np.arange(n) / fs
    rng = np.random.default_rng(seed)
    return np.column_stack([np.sin(2 * np.pi * 1.3 * t + p) + 0.4 * np.sin(2 * np.pi * 4.1 * t + 2 * p)
                            + 0.002 * rng.standard_normal(n) for p in (0.0, 0.7, 1.9, 2.5, 3.1)])


@pytest.mark.parametrize("width", [1, 2, 3])
@pytest.mark.parametrize("channel", [0, 2, 4])
def test_a_spike_is_found_sample_for_sample_in_its_own_channel(width, channel):
    acc = _smooth()
    at = 7_777 + np.arange(width)
    acc[at, channel] += 20 * acc[:, channel].std()
    found = spike_samples(acc)
    for c, samples in enumerate(found):
        np.testing.assert_array_equal(samples, at if c == channel else [])


def test_the_warning_names_the_channel_the_count_and_the_times():
    acc = _smooth()
    acc[4_000, 3] -= 30.0
    acc[[9_000, 9_001], 3] += 30.0
    acc[15_000, 1] += 30.0
    messages = spike_warnings(acc, 200.0, labels=list("abcde"))
    assert messages == [
        "channel b: 1 spike (1 sample far from both neighbours, then back), t = 75 s: replaced by the straight "
        "line between their neighbours before identifying (a spike gives spurious modes)",
        "channel d: 2 spikes (3 samples far from both neighbours, then back), t = 20, 45 s: replaced by the "
        "straight line between their neighbours before identifying (a spike gives spurious modes)"]
    assert spike_warnings(acc[:, [0, 2, 4]], 200.0) == []


def test_the_threshold_is_fifty_times_the_channel_variation():
    """An alternating channel: every second difference is +-2a, so the
    variation is exactly 1.4826 x 2a; a spike departing 50.5 times that
    from its neighbours is one, 49.5 times is not."""
    a = 1.0
    y = a * (-1.0) ** np.arange(4_000)
    variation = _MAD_TO_SIGMA * 2 * a
    for factor, found in ((SPIKE_THRESHOLD * 1.001, [2_000]), (SPIKE_THRESHOLD * 0.999, [])):
        spiky = y.copy()
        spiky[2_000] = y[1_999] + factor * variation  # its neighbours are both y[1999]
        np.testing.assert_array_equal(spike_samples(spiky[:, None])[0], found)


@pytest.mark.parametrize("shape", ["step", "ramp and back", "smooth glitch", "spike at the edge", "overshoot after",
                                   "overshoot before"])
def test_what_is_not_a_spike(shape):
    """A step does not come back; a seven-sample smooth bump (the Weimar
    records' block glitch) curves the same way at its ends; a departure
    that rises over four samples is wider than three; a spike on the first
    or last two samples has no neighbours' neighbours; three samples whose
    neighbour on one side swings on past the level (its second difference
    not opposite to the run) are not sharp at that end."""
    acc = _smooth()[:, :1]
    big = 100 * acc.std()
    if shape == "step":
        acc[8_000:] += big
    elif shape == "ramp and back":
        acc[8_000:8_009, 0] += big * np.array([1, 2, 3, 4, 5, 4, 3, 2, 1]) / 5
    elif shape == "smooth glitch":
        acc[8_000:8_007, 0] -= big * np.sin(np.pi * np.arange(1, 8) / 8)
    elif shape == "spike at the edge":
        acc[[0, 1, -2, -1], 0] += big
    else:
        swing = big * np.array([1, 1, 1, 0.2, -0.5, 0])
        acc[8_000:8_006, 0] += swing if shape == "overshoot after" else swing[::-1]
    assert spike_samples(acc)[0].size == 0
    if shape.startswith("overshoot"):  # the same three samples with a quiet neighbour are a spike
        acc[8_000:8_006, 0] -= swing if shape == "overshoot after" else swing[::-1]
        acc[8_000:8_003, 0] += big
        np.testing.assert_array_equal(spike_samples(acc)[0], [8_000, 8_001, 8_002])


def test_the_onset_of_an_impact_is_not_a_spike_but_a_spike_in_its_decay_is():
    """A hammer blow of one sample on a mass: the driving-point acceleration
    is a one-sample pulse, then the structure rings (spread after > 10 x
    before). The same pulse in the middle of the decay is a spike."""
    fs, n, blow = 1000.0, 20_000, 5_000
    t = np.arange(n) / fs
    rng = np.random.default_rng(1)
    ring = np.where(t >= blow / fs, np.exp(-0.3 * (t - blow / fs)) * np.sin(2 * np.pi * 5.0 * (t - blow / fs)), 0.0)
    y = 0.05 * ring + 1e-4 * rng.standard_normal(n)
    y[blow] += 1.0
    assert spike_samples(y[:, None])[0].size == 0
    y[blow + 3_000] += 1.0
    np.testing.assert_array_equal(spike_samples(y[:, None])[0], [blow + 3_000])


def test_a_spike_before_an_impact_is_judged_by_what_follows_it():
    """The ringing must start right after the run: a spike more than the
    ring window before the blow is found; one just before it is not."""
    fs, n, blow = 1000.0, 20_000, 10_000
    t = np.arange(n) / fs
    rng = np.random.default_rng(2)
    y = np.where(t >= blow / fs, np.exp(-0.3 * (t - blow / fs)) * np.sin(2 * np.pi * 5.0 * (t - blow / fs)), 0.0)
    y = y + 1e-3 * rng.standard_normal(n)
    early, late = blow - 2 * SPIKE_RING_WINDOW, blow - 5
    y[[early, late]] += 0.5
    np.testing.assert_array_equal(spike_samples(y[:, None])[0], [early])


def test_despiked_puts_the_samples_on_the_line_between_their_neighbours():
    acc = _smooth()[:, :2]
    clean = acc.copy()
    acc[[100, 101, 102], 1] += 40.0
    acc[5_000, 0] -= 40.0
    out = despiked(acc)
    assert not np.shares_memory(out, acc)
    np.testing.assert_allclose(out[5_000, 0], (acc[4_999, 0] + acc[5_001, 0]) / 2, rtol=0, atol=1e-15)
    np.testing.assert_allclose(out[[100, 101, 102], 1], acc[99, 1] + (acc[103, 1] - acc[99, 1]) * np.array([1, 2, 3]) / 4,
                               rtol=0, atol=1e-15)
    changed = np.flatnonzero(np.any(out != acc, axis=1))
    np.testing.assert_array_equal(changed, [100, 101, 102, 5_000])
    assert np.max(np.abs(out - clean)) < 0.02  # the line through a curve, against spikes of 40


@pytest.mark.slow
def test_identify_record_warns_and_replaces_the_spike(monkeypatch):
    """One spike of 1000 standard deviations in the Palisaden record loses
    its 3.63 Hz mode and doubles the 1.88 Hz one; replaced, the record gives the
    clean record's modes (one sample of 36000 differs: frequencies within
    1e-6)."""
    import modal.measured._pipeline as pipeline

    acc = np.load(PALISADEN)
    options = dict(fmax=5, highpass_hz=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", modal.ModalWarning)
        clean, _ = modal.identify_record(acc, 1 / 20, "ambient", **options)
    spiky = acc.copy()
    spiky[12_000, 4] += 1000 * acc[:, 4].std()
    with pytest.warns(modal.ModalWarning, match=r"channel 4: 1 spike \(1 sample .*\), t = 600 s"):
        result, _ = modal.identify_record(spiky, 1 / 20, "ambient", **options)
    assert len(clean.modes) == 4
    np.testing.assert_allclose(result.modes["freq_hz"], clean.modes["freq_hz"], rtol=1e-6)
    np.testing.assert_allclose(result.modes["damping"], clean.modes["damping"], rtol=1e-4)
    with monkeypatch.context() as patch:  # the spike left in
        patch.setattr(pipeline, "spike_samples", lambda a: [np.empty(0, dtype=int)] * np.shape(a)[1])
        left_in, _ = modal.identify_record(spiky, 1 / 20, "ambient", **options)
    found = left_in.modes["freq_hz"].to_numpy()
    assert np.min(np.abs(found - clean.modes["freq_hz"].iloc[3])) > 0.1  # 3.63 Hz lost
    assert np.sort(np.abs(found - clean.modes["freq_hz"].iloc[0]))[1] < 0.02  # a second mode by 1.88 Hz


def test_cli_names_the_channel_and_the_count(tmp_path, capsys):
    from modal.cli import main

    acc, dt, _ = ambient_beam(60.0)
    acc = acc.copy()
    acc[3_000, 2] += 500 * acc[:, 2].std()
    record = tmp_path / "spiky.npz"
    np.savez(record, acc=acc, dt=dt)
    out = tmp_path / "out"
    code = main(["identify", str(record), "--ambient", "--max-order", "20", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "modal identify: warning: channel 2: 1 spike (1 sample far from both neighbours, then back), t = 30 s" in err
    assert "channel 2: 1 spike" in (out / "report.html").read_text()


def _no_spike(acc):
    return [int(at.size) for at in spike_samples(acc)]


def _largest_statistic(acc):
    return max([run[2] for y in np.asarray(acc, dtype=float).T for run in _spike_runs(y, threshold=5.0)] + [0.0])


@pytest.mark.parametrize("record", ["palisaden_20hz_30min.npy", "palisaden_12.5hz_90min.npy"]
                         + [f"roving_plate/setup_{k}/record.npz" for k in range(1, 7)])
def test_no_spike_in_the_shipped_records(record):
    path = DATA / record
    acc = np.load(path) if path.suffix == ".npy" else np.load(path)["acc"]
    assert _no_spike(acc) == [0] * acc.shape[1]
    assert _largest_statistic(acc) < SPIKE_THRESHOLD / 4


def _shared_records():
    for k in range(1, 16):
        yield f"weimar_frame/measurement_{k}/measurement_{k}.npy"
    yield "palisaden/palisaden_accel_100Hz_float32.npy"
    yield "usc_cantilever/timeseries_data.lvm"


@pytest.mark.slow
@pytest.mark.parametrize("record", list(_shared_records()))
def test_no_spike_in_the_measured_records_beside_the_project(record):
    """Every record of ../shared/data (when present): no alarm. The largest
    statistic is 28.5 (Palisaden at 100 Hz, channel 1, a two-sample dip of
    8 standard deviations), the others below 5."""
    path = SHARED / record
    if not path.exists():
        pytest.skip(f"{path} is not here")
    acc = modal.read_record(path).acc if path.suffix == ".lvm" else np.load(path).astype(float)
    assert _no_spike(acc) == [0] * acc.shape[1]
    assert _largest_statistic(acc) < (30.0 if "palisaden" in record else 5.0)


def test_simulated_ambient_and_impact_records_raise_no_alarm():
    acc, _, _ = ambient_beam(200.0)
    assert _no_spike(acc) == [0] * 5
    beam = modal.SimplySupportedBeam(length=1.0, bending_stiffness=50.0, mass_per_length=2.0)
    decay = modal.structures.beam_impulse_response(beam, 6, 0.31, np.array([0.2, 0.5, 0.8]), 1 / 500, 20_000,
                                                   damping=0.01).acceleration
    rng = np.random.default_rng(0)
    noise = 0.001 * decay.std(axis=0)
    impact = np.vstack([noise * rng.standard_normal((2_000, 3)), decay + noise * rng.standard_normal(decay.shape)])
    assert _no_spike(impact) == [0] * 3


def _screen_records():
    """Records on which the spike check's screen (``_within``) does and does
    not tell the answer: noise (even and odd lengths), a simulated ambient
    record, noise with a real spike, heavy tails, a coarsely quantised record
    (the variation's fallback), an alternating one (screened), a constant one."""
    rng = np.random.default_rng(11)
    noise = rng.standard_normal(30_001)
    spiky = noise.copy()
    spiky[12_345] += 80.0
    yield "noise, odd", noise, True
    yield "noise, even", noise[:-1], True
    yield "ambient", ambient_beam(200.0)[0][:, 0], True
    yield "a spike", spiky, False
    yield "heavy tails", rng.standard_t(1.5, 20_000), False
    yield "quantised", np.round(0.3 * rng.standard_normal(20_000)), False
    yield "alternating", (-1.0) ** np.arange(4_000), True
    yield "constant", np.full(5_000, 2.5), False


@pytest.mark.parametrize("name, y, screened", list(_screen_records()), ids=lambda v: v if isinstance(v, str) else "")
@pytest.mark.parametrize("threshold", [None, 5.0])
def test_the_screen_gives_the_rules_result(monkeypatch, name, y, screened, threshold):
    """Where the screen tells that no second difference reaches the edge, it
    saves the variation's median and finds no spike, as the rule does; the
    rule's runs are the same with and without it (the spike found)."""
    from modal.records import _quality

    told = []
    within = _quality._within
    monkeypatch.setattr(_quality, "_within", lambda *args: told.append(within(*args)) or told[-1])
    runs = _spike_runs(y, threshold)
    assert told == [screened and threshold is None]  # at a tenth of the threshold, the edge is within the noise
    monkeypatch.setattr(_quality, "_within", lambda *args: False)
    assert runs == _spike_runs(y, threshold)
    if name == "a spike":
        assert [run[:2] for run in runs] == [(12_345, 12_345)]


def test_the_screen_tells_only_what_is_true():
    """``_within`` is True only where every ``|d| <= edge x variation``
    (here on 400 records of several kinds, lengths odd and even, edges
    around the ratio of the largest ``|d|`` to the variation): never the
    wrong way, and often enough to matter."""
    from modal.records._quality import _variation, _within

    rng = np.random.default_rng(12)
    told = 0
    for k in range(400):
        n = int(rng.integers(5, 3_000))
        d = [rng.standard_normal(n), rng.standard_t(2.0, n), np.round(rng.standard_normal(n)),
             rng.laplace(size=n)][k % 4]
        deviation = np.abs(d - np.median(d))
        ratio = np.max(np.abs(d)) / _variation(d)
        for edge in ratio * np.array([0.9, 0.999, 1.001, 1.1, 2.0]):
            if _within(d, deviation, edge):
                told += 1
                assert np.max(np.abs(d)) <= edge * _variation(d, deviation)
    assert told > 100


@pytest.mark.parametrize("d, edge, told", [
    ([-1.0, -1.0, 1.0, 1.0], 0.7, True),  # variation 1.4826: every |d| = 1 <= 0.7 x 1.4826, at an edge below 1
    ([-100.0, -100.0, 100.0, 100.0], 0.7, True),  # the same a hundred times larger
    ([-2.0, -2.0, 0.0, 0.1, 2.0, 2.0, -0.1], 1.0, True),  # 3 of 7 deviations below the level 1.35, fewer than 4
    ([0.0, 0.0, 3.0, -3.0], 1.0, False),  # 2 of 4 below the level: the median of 4 may be too (variation 2.22 < 3)
    ([0.0, 0.0, 0.0, 3.0, -3.0], 1.0, False),  # 3 of 5 below the level: the median is (variation 1.50 < 3)
    ([-1.0, -1.0, 1.0, 1.0], 0.0, False),  # no edge: no |d| is within it
    ([-1.0, -1.0, 1.0, 1.0], -0.7, False),
    ([1.0, -1.0, np.inf, -1.0, 1.0], 6.25, False),  # an infinite second difference
    ([-1.5e-323, -1.5e-323, 1.5e-323, 1.5e-323], 0.6, False),  # subnormal: the level's rounding fails the check
    ([], 6.25, False),
], ids=["pairs", "pairs x 100", "3 of 7 below", "2 of 4 below", "3 of 5 below", "edge 0", "edge < 0", "infinite",
        "subnormal", "empty"])
def test_the_screen_on_second_differences_small_enough_to_check_by_hand(d, edge, told):
    """``_within`` on a few second differences whose answer is known: True
    where every ``|d| <= edge x variation`` and fewer than half of the
    deviations are at or below the level ``max|d| / (1.4826 edge)``, False
    where as many as half are (the median may be below the level), where the
    edge is not positive, a ``d`` is not finite, the level's rounding fails
    its check, or there is none; the rule agrees with each answer."""
    from modal.records._quality import _variation, _within

    d = np.array(d, dtype=float)
    deviation = np.abs(d - np.median(d)) if d.size else d
    assert _within(d, deviation, edge) is told
    if d.size:
        assert bool(np.max(np.abs(d)) <= edge * _variation(d, deviation)) is told


def test_the_statistic_is_the_departure_over_the_channel_variation_whatever_its_curvature():
    """A one-sample spike of 100 on unit noise and a parabola (a steady
    curvature: every second difference -2 besides the noise's): its
    statistic is its second difference over the channel's variation,
    1.4826 x the median absolute deviation of all the second differences
    but the two ends' about their median (the curvature does not count),
    here larger than the local one (32 second differences each side, clear
    of the run)."""
    n, at = 301, 150
    rng = np.random.default_rng(1)
    y = rng.standard_normal(n) + 2.0 * (np.arange(n) - at) ** 2
    y[at] += 100.0
    d = np.zeros(n)
    d[1:-1] = y[1:-1] - (y[:-2] + y[2:]) / 2

    def spread(x):
        return _MAD_TO_SIGMA * np.median(np.abs(x - np.median(x)))

    variation = spread(d[1:-1])
    assert variation > max(spread(d[at - 33:at - 1]), spread(d[at + 2:at + 34]))
    [(first, last, statistic)] = _spike_runs(y)
    assert (first, last) == (at, at)
    assert statistic == pytest.approx(d[at] / variation, rel=1e-12)
    assert statistic == pytest.approx(81.16, abs=0.01)


def test_a_dead_channel_has_no_spike_and_the_others_are_still_checked():
    """A constant channel (a dead sensor): every second difference is 0, no
    variation, no spike; the spike of the channel beside it is found and
    replaced, the dead one left as it is."""
    acc = _smooth()[:, :2]
    acc[:, 0] = 0.25
    acc[7_777, 1] += 20 * acc[:, 1].std()
    found = spike_samples(acc)
    assert [list(at) for at in found] == [[], [7_777]]
    out = despiked(acc, found)
    np.testing.assert_array_equal(out[:, 0], 0.25)
    np.testing.assert_allclose(out[7_777, 1], (acc[7_776, 1] + acc[7_778, 1]) / 2, rtol=0, atol=1e-15)
