"""A geometry built from its nodes alone (``modal.setups.Geometry``): no
lines, no links, no sensors, no background, each an empty table or array
of the documented columns and shape, usable as such; frozen. Asked for by
the mutation run of ``modal.setups`` (issue 33)."""

import dataclasses

import numpy as np
import pandas as pd
import pytest

from modal.setups import Geometry, node_neighbours


def test_a_geometry_of_nodes_alone():
    nodes = pd.DataFrame({"x": [0.0, 3.0], "y": [0.0, 4.0], "z": [0.0, 0.0]}, index=pd.Index(["a", "b"], name="node"))
    g = Geometry(nodes)
    assert g.lines == [] and g.source == "geometry"
    assert list(g.links.columns) == ["parent", "child", "px", "py", "pz", "cx", "cy", "cz"] and g.links.empty
    assert list(g.sensors.columns) == ["name", "node", "x", "y", "z"] and g.sensors.empty
    assert g.background_nodes.shape == (0, 3) and g.background_lines.shape == (0, 2)
    assert g.background_lines.dtype.kind == "i"
    assert g.size == 5.0 and node_neighbours(g) == {}
    with pytest.raises(ValueError, match="^geometry: the geometry names no sensors, so it gives no channel table"):
        g.channel_table(["a"])
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.source = "elsewhere"
    other = Geometry(nodes)
    other.lines.append(("a", "b"))  # each geometry's own list
    assert g.lines == [] and np.array_equal(g.coordinates, nodes.to_numpy())


def _nodes(names="ab", z=0.0):
    return pd.DataFrame({"x": np.arange(len(names), dtype=float), "y": 0.0, "z": z},
                        index=pd.Index(list(names), name="node"))


def test_a_single_node_has_size_1_and_the_refusals_name_what_is_wrong():
    assert Geometry(_nodes("a")).size == 1.0  # no extent: drawings scale by 1
    links = pd.DataFrame({"parent": ["a"], "child": ["zz"], "px": [1.0], "py": [0.0], "pz": [0.0], "cx": [1.0],
                          "cy": [0.0], "cz": [0.0]})
    cases = [
        (dict(nodes=_nodes(z=np.nan)), "g: a node's coordinates are missing or not numbers"),
        (dict(nodes=_nodes(), links=links), "g: link a->zz names a node not in the geometry"),
        (dict(nodes=_nodes(), background_nodes=np.zeros((2, 3)), background_lines=np.array([[0, 2]])),
         "g: a background line names a background node that does not exist"),
        (dict(nodes=_nodes(), background_nodes=np.zeros((2, 3)), background_lines=np.array([[-1, 1]])),
         "g: a background line names a background node that does not exist"),
    ]
    for given, message in cases:
        with pytest.raises(ValueError) as caught:
            Geometry(**given, source="g")
        assert str(caught.value) == message
    assert Geometry(_nodes(), background_nodes=np.zeros((2, 3)), background_lines=np.array([[0, 1]])).size > 0
