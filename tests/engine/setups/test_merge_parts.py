"""The merge's small parts on hand-made inputs, each at its bounds: a mode
a setup did not select taken from its diagram (``_from_diagram``), a node's
motion from nearly parallel channels (``node_shapes``), and the geometry's
links both ways (``node_neighbours``)."""

from types import SimpleNamespace

import numpy as np
import pandas as pd

from modal.setups import Geometry
from modal.setups._merge import _from_diagram, node_neighbours, node_shapes


def diagram(rows):
    """A setup's result holding only a pole table and the poles' shapes:
    ``rows`` of (freq_hz, stable, physical, shape)."""
    poles = pd.DataFrame({"freq_hz": [r[0] for r in rows], "stable": [r[1] for r in rows],
                          "physical": [r[2] for r in rows], "damping": 0.01 + 0.001 * np.arange(len(rows))})
    return SimpleNamespace(poles=poles, pole_shapes=np.array([r[3] for r in rows], dtype=complex))


def test_a_mode_from_the_diagram_is_the_medoid_of_the_stable_physical_poles_within_the_window():
    """Window 8 Hz +- 25 %: the poles at 6 and 10 Hz lie on its edges (in),
    10.5 Hz outside; an unstable and a non-physical pole in it do not count.
    Of the three, the 9 Hz pole's shape lies between the others': the medoid
    (the first pole is not)."""
    a, b, c = [1.0, 0.2, 0.0], [1.0, 0.5, 0.1], [1.0, 0.8, 0.2]
    result = diagram([(6.0, True, True, a), (9.0, True, True, b), (10.0, True, True, c), (10.5, True, True, b),
                      (7.0, False, True, [0.0, 1.0, 0.0]), (8.5, True, False, [0.0, 0.0, 1.0])])
    shape, freq, damping = _from_diagram(result, [], 8.0, None, 0.25, 0.8)
    assert (freq, damping) == (9.0, 0.011) and np.array_equal(shape, np.array(b, dtype=complex))
    # a pole exactly on the window's edge is in it
    assert _from_diagram(diagram([(10.0, True, True, a)]), [], 8.0, None, 0.25, 0.8)[1] == 10.0
    # neither an unstable nor a non-physical pole is taken
    assert _from_diagram(diagram([(8.0, False, True, a), (8.1, True, False, b)]), [], 8.0, None, 0.25, 0.8) is None


def test_a_mode_from_the_diagram_has_the_consensus_reference_part():
    """Reference channels 0 and 1, consensus (1, 1): a pole whose reference
    part is (1, -1) (MAC 0) is not the mode; (1, 0) has MAC 0.5 exactly, the
    bound given, and is."""
    consensus = np.array([1.0, 1.0], dtype=complex)
    other, half = [1.0, -1.0, 0.3], [1.0, 0.0, 0.7]
    result = diagram([(8.0, True, True, other), (8.0, True, True, half)])
    shape, freq, _ = _from_diagram(result, [0, 1], 8.0, consensus, 0.01, 0.5)
    assert np.array_equal(shape, np.array(half, dtype=complex))
    assert _from_diagram(diagram([(8.0, True, True, other)]), [0, 1], 8.0, consensus, 0.01, 0.5) is None


def test_nearly_parallel_channels_give_one_axis_not_a_blown_up_second():
    """Two channels at a node 1e-7 rad apart read 1.0 and 1.0 + 1e-9: they
    measure the z axis (rank 1 below the relative bound 1e-6), not y as a
    difference of two nearly equal readings (1e-9 / 1e-7 = 0.01 or more)."""
    tilt = np.array([0.0, 1e-7, 1.0]) / np.hypot(1e-7, 1.0)
    motion = node_shapes([("n", (0.0, 0.0, 1.0)), ("n", tuple(tilt))], [1.0 + 0j, 1.0 + 1e-9 + 0j])["n"]
    assert np.isnan(motion[0]) and np.isnan(motion[1])
    assert abs(motion[2] - 1.0) < 1e-8


def test_a_line_joins_both_nodes_and_a_link_too():
    geometry = Geometry(nodes=pd.DataFrame({"x": [0.0, 1.0, 2.0], "y": 0.0, "z": 0.0},
                                           index=pd.Index(["1", "2", "3"], name="node")),
                        lines=[("1", "2")],
                        links=pd.DataFrame({"parent": ["2"], "child": ["3"], "px": [1.0], "py": [0.0], "pz": [0.0],
                                            "cx": [1.0], "cy": [0.0], "cz": [0.0]}))
    assert node_neighbours(geometry) == {"1": {"2"}, "2": {"1", "3"}, "3": {"2"}}
    assert node_neighbours(None) is None
