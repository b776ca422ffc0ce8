"""Side bands of an amplitude-modulated response are flagged, modes are not
(issue 32: the USC cantilever's 110.2 Hz line, 116.9 - 6.6 Hz, was trusted).

The rule (:func:`modal.identification._stabilisation._side_bands`): a
symmetric pair of weaker lines ``f_p -+ f_m`` of the carrier ``p``'s shape,
``m`` the slowest trusted mode, ``f_p`` no multiple of ``f_m``. Each case
sits on one side of one condition, so that an inverted comparison, a
dropped condition or a wrong width turns a test red; the families of real
modes that lie at ``f_p +- f_m`` by nature (a string's harmonics, a simply
supported beam's ``n^2``) stay unflagged."""

import numpy as np
import pandas as pd
import pytest

import modal
from modal.identification._stabilisation import SIDE_BAND_ZETA, _flags, _side_bands

#: The USC cantilever with --free-decay --fmax 150, as identified (frequency, damping, poles).
CANTILEVER = pd.DataFrame({
    "freq_hz": [6.617, 34.78, 41.38, 47.89, 51.84, 110.22, 116.88, 123.19],
    "damping": [0.0029, 0.0062, 0.0015, 0.0035, 0.0327, 0.0023, 0.0025, 0.0036],
    "n_poles": [28, 16, 29, 15, 12, 18, 27, 18],
})


def side_bands(table, mode_mac=None, trusted=None, mac_min=0.98):
    n = len(table)
    return _side_bands(table["freq_hz"].to_numpy(float), table["damping"].to_numpy(float),
                       table["n_poles"].to_numpy(), np.ones((n, n)) if mode_mac is None else mode_mac,
                       [True] * n if trusted is None else trusted, mac_min)


def test_the_cantilevers_side_bands_are_flagged_and_its_modes_are_not():
    flags = side_bands(CANTILEVER)
    assert flags == ["", "side band of 41.38 Hz by 6.617 Hz", "", "side band of 41.38 Hz by 6.617 Hz", "",
                     "side band of 116.9 Hz by 6.617 Hz", "", "side band of 116.9 Hz by 6.617 Hz"]


def test_one_line_alone_is_no_side_band():
    """Without 123.19 Hz, 110.22 Hz is a coincidence, not a side band (41.38's pair stays flagged)."""
    flags = side_bands(CANTILEVER.drop(index=7).reset_index(drop=True))
    assert flags[5] == "" and flags[1] and flags[3]


def test_the_families_of_real_modes_are_not_side_bands():
    """A string (f_n = n f_1: f_{n-1} and f_{n+1} lie at f_n -+ f_1 exactly),
    with each harmonic weaker than the one below, and a simply supported
    beam (f_n = n^2 f_1), seen by one channel (every MAC 1): nothing flagged.
    A string whose harmonics are each 0.05 % off (a stiff cable) neither."""
    n = np.arange(1, 9)
    string = pd.DataFrame({"freq_hz": 2.0 * n, "damping": 0.005, "n_poles": 30 - n})
    assert side_bands(string) == [""] * 8
    stiff = string.assign(freq_hz=2.0 * n * (1 + 0.0005 * (-1) ** n))
    assert side_bands(stiff) == [""] * 8
    beam = pd.DataFrame({"freq_hz": 1.5 * n**2, "damping": 0.01, "n_poles": 30 - n})
    assert side_bands(beam) == [""] * 8


def test_a_line_of_another_shape_than_the_carrier_is_a_mode():
    """Three channels: the lines around 116.88 Hz with a shape of MAC 0.979
    with its (below mac_min 0.98) are modes; at 0.98 they are side bands.
    The MAC taken is the line's with the carrier, not with the modulator."""
    table = CANTILEVER.iloc[[0, 5, 6, 7]].reset_index(drop=True)
    alike = np.ones((4, 4))
    other = alike.copy()
    other[1, 2] = other[2, 1] = 0.979
    assert side_bands(table, other) == ["", "", "", ""]  # and 123.19 Hz is then one line alone
    other[1, 2] = other[2, 1] = 0.98
    assert side_bands(table, other)[1] == "side band of 116.9 Hz by 6.617 Hz"
    with_modulator = alike.copy()
    with_modulator[0, 1] = with_modulator[1, 0] = 0.1  # unlike the modulator: still the carrier's side band
    assert side_bands(table, with_modulator)[1].startswith("side band")


def test_a_line_as_strong_as_the_carrier_is_a_mode():
    """Fewer poles than the carrier's, strictly: 27 poles as the carrier's 27 is no side band."""
    table = CANTILEVER.iloc[[0, 5, 6, 7]].reset_index(drop=True)
    assert side_bands(table.assign(n_poles=[28, 26, 27, 26]))[1].startswith("side band")
    assert side_bands(table.assign(n_poles=[28, 27, 27, 26])) == [""] * 4


def test_the_modulator_is_the_slowest_trusted_mode():
    """The slowest mode doubted for another reason (a 0.8 Hz drift) is not
    the modulator: 6.617 Hz is. Were the drift taken, nothing would be a
    side band (116.88 -+ 0.8 Hz holds no mode)."""
    table = pd.concat([pd.DataFrame({"freq_hz": [0.8], "damping": [0.2], "n_poles": [5]}),
                       CANTILEVER.iloc[[0, 5, 6, 7]]], ignore_index=True)
    trusted = [False, True, True, True, True]
    assert side_bands(table, trusted=trusted)[2] == "side band of 116.9 Hz by 6.617 Hz"
    assert side_bands(table) == [""] * 5
    assert side_bands(table, trusted=[False] * 5) == [""] * 5
    unsorted = table.iloc[::-1].reset_index(drop=True)  # the slowest by frequency, not by place
    assert side_bands(unsorted, trusted=trusted[::-1])[2] == "side band of 116.9 Hz by 6.617 Hz"


def test_a_line_lies_within_its_own_half_power_half_width():
    """110.22 Hz damped 0.23 %: its half-width is 0.2535 Hz; f_p - f_m =
    110.263. Moved to 0.2535 Hz off minus a hair it is a side band, plus a
    hair not. The width is the line's own (zeta f), not the carrier's: the
    carrier damped 10 % widens nothing. A line damped 0.001 % is taken at
    0.1 %, one damped 40 % at 10 %."""
    table = CANTILEVER.iloc[[0, 5, 6, 7]].reset_index(drop=True)
    target = 116.88 - 6.617
    width = 0.0023 * 110.22
    inside = table.copy()
    inside.loc[1, "freq_hz"] = target - width * 0.999
    inside.loc[1, "damping"] = width / inside.loc[1, "freq_hz"]
    assert side_bands(inside)[1].startswith("side band")
    outside = inside.copy()
    outside.loc[1, "freq_hz"] = target - width * 1.002
    assert side_bands(outside)[1] == ""
    assert side_bands(outside.assign(damping=[0.0029, outside.loc[1, "damping"], 0.1, 0.0036]))[1] == ""
    floor = table.copy()
    floor.loc[1, ["freq_hz", "damping"]] = [target + 0.0009 * target, 1e-5]
    assert side_bands(floor)[1].startswith("side band")
    floor.loc[1, "freq_hz"] = target + 0.0011 * target
    assert side_bands(floor)[1] == ""
    cap = table.copy()
    cap.loc[1, ["freq_hz", "damping"]] = [target * 0.75, 0.4]  # within 0.4 f, not within 0.1 f
    assert side_bands(cap)[1] == ""
    cap.loc[1, "freq_hz"] = target / 1.09  # within 0.1 f
    assert side_bands(cap)[1].startswith("side band")
    assert SIDE_BAND_ZETA == (0.001, 0.1)


def test_a_carrier_at_a_multiple_of_the_modulator_is_judged_by_its_own_width():
    """A carrier 0.3 Hz from 18 f_m (width 0.29 Hz) has side bands; one 0.28 Hz from it not."""
    table = CANTILEVER.iloc[[0, 5, 6, 7]].reset_index(drop=True)
    for offset, expected in ((0.3, True), (0.28, False)):
        carrier = 18 * 6.617 + offset
        moved = table.assign(freq_hz=[6.617, carrier - 6.617, carrier, carrier + 6.617])
        assert bool(side_bands(moved)[1]) is expected, offset


def test_the_bounds_are_inclusive():
    """Numbers whose distances equal the widths exactly in floating point: a
    carrier at 64.5 Hz (16 f_m + 0.5) of width 0.5 Hz is a harmonic (no
    side bands); a line at 40 Hz of width 0.5 Hz, 0.5 Hz from 44.5 - 4, is
    a side band. A NaN damping counts as the lower bound, 0.1 %: a line
    0.02 Hz from 48.5 Hz is within it, 0.06 Hz not."""
    harmonic = pd.DataFrame({"freq_hz": [4.0, 60.5, 64.5, 68.5], "damping": [0.01, 0.01, 1 / 129, 0.01],
                             "n_poles": [20, 10, 20, 10]})
    assert side_bands(harmonic) == [""] * 4
    assert side_bands(harmonic.assign(damping=[0.01, 0.01, 1 / 130, 0.01]))[1].startswith("side band")
    table = pd.DataFrame({"freq_hz": [4.0, 40.0, 44.5, 48.52], "damping": [0.01, 1 / 80, 0.002, np.nan],
                          "n_poles": [20, 10, 20, 10]})
    assert side_bands(table) == ["", "side band of 44.5 Hz by 4 Hz", "", "side band of 44.5 Hz by 4 Hz"]
    assert side_bands(table.assign(damping=[0.01, 1 / 81, 0.002, np.nan]))[1] == ""
    assert side_bands(table.assign(freq_hz=[4.0, 40.0, 44.5, 48.56]))[3] == ""


def test_flags_join_the_side_band_to_the_other_reasons():
    """Through :func:`_flags`: a low-MAMC line keeps that reason and gains
    the side band's; the modulator is chosen among modes with no other
    reason."""
    modes = CANTILEVER.assign(mode=np.arange(1, 9), mpc=1.0, mamc=[1, 0.86, 1, 0.9, 0.96, 0.96, 1, 0.91])
    one_channel = np.ones((8, 8))
    flags = _flags(modes, np.ones((1, 8)), modal.StabilityCriteria(), one_channel)
    assert flags[1] == "low MAMC 0.86; side band of 41.38 Hz by 6.617 Hz"
    assert flags[5] == "side band of 116.9 Hz by 6.617 Hz"
    assert flags[4] == "damping 3.3 % implausibly high (median 0.32 %)"
    assert flags[0] == flags[2] == flags[6] == ""
    doubted = modes.assign(mpc=[0.3] + [1.0] * 7)
    assert _flags(doubted, np.ones((1, 8)), modal.StabilityCriteria(), one_channel)[5] == ""
    assert _flags(modes, np.ones((1, 8)), modal.StabilityCriteria())[5] == ""  # no MAC given: no shape alike


def free_decay(lines, n_channels, fs=1000.0, seconds=8.0, seed=1):
    """A free decay of ``lines``: each ``(freq_hz, damping, amplitude, shape)``."""
    t = np.arange(0.0, seconds, 1 / fs)
    y = np.zeros((t.size, n_channels))
    for f, zeta, amplitude, shape in lines:
        y += amplitude * np.outer(np.exp(-zeta * 2 * np.pi * f * t) * np.cos(2 * np.pi * f * t), shape)
    y = np.vstack([np.zeros((200, n_channels)), y])
    return y + 1e-4 * np.random.default_rng(seed).standard_normal(y.shape)


def test_a_modulated_carrier_has_its_side_bands_flagged_end_to_end():
    """A 40 Hz carrier modulated by a 5.3 Hz mode (lines at 34.7 and 45.3 Hz
    of its shape), three channels: the lines are flagged, the two modes not.
    The same four frequencies as modes of four different shapes: none."""
    carrier, modulator = np.array([1.0, 0.7, 0.4]), np.array([0.3, 1.0, 0.6])
    lines = [(5.3, 0.004, 0.5, modulator), (40.0, 0.003, 1.0, carrier),
             (34.7, 0.004, 0.15, carrier), (45.3, 0.003, 0.15, carrier)]
    result, _ = modal.identify_record(free_decay(lines, 3), 1e-3, "free_decay")
    flag = dict(zip(result.modes["freq_hz"].round(1), result.modes["flag"]))
    assert set(flag) == {5.3, 34.7, 40.0, 45.3}
    assert "side band of 40 Hz by 5.3 Hz" in flag[34.7] and "side band of 40 Hz by 5.3 Hz" in flag[45.3]
    assert flag[5.3] == flag[40.0] == ""
    shapes = [modulator, carrier, np.array([1.0, -0.2, -0.8]), np.array([-0.5, 1.0, -0.9])]
    modes_lines = [(f, z, 1.0 if k < 2 else 0.15, s) for k, ((f, z, _, _), s) in enumerate(zip(lines, shapes))]
    result, _ = modal.identify_record(free_decay(modes_lines, 3), 1e-3, "free_decay")
    assert len(result.modes) == 4
    assert not result.modes["flag"].str.contains("side band").any()


@pytest.mark.parametrize("seed", range(3))
def test_random_structures_have_no_side_bands(seed):
    """Frequencies of 3-8 modes drawn at random (1-50 Hz), damping 0.5-3 %,
    shapes of MAC below 0.98 with each other: whatever their spacing, never
    a side band (a line needs the carrier's shape)."""
    rng = np.random.default_rng(seed)
    for _ in range(200):
        n = int(rng.integers(3, 9))
        table = pd.DataFrame({"freq_hz": np.sort(rng.uniform(1, 50, n)), "damping": rng.uniform(0.005, 0.03, n),
                              "n_poles": rng.integers(10, 30, n)})
        shapes = rng.standard_normal((6, n))
        mode_mac = modal.mac(shapes, shapes)
        if (mode_mac[~np.eye(n, dtype=bool)] >= 0.98).any():
            continue
        assert side_bands(table, mode_mac) == [""] * n
