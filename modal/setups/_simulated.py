"""A simulated roving test with known modes (a simply supported plate), and
setups saved in the project's own format: the truth the merge is checked
against, and an example campaign for the workflow."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from .._checks import nonnegative_float, positive_float, positive_int
from ..records import MeasuredRecord, save_record_npz
from ..structures import SimplySupportedPlate, ambient_response
from ._geometry import Geometry
from ._merge import Setup


def plate_roving_test(plate: SimplySupportedPlate, divisions=(6, 5), references=("1-1", "5-3"), per_setup=3,
                      n_modes=5, duration=300.0, fs=100.0, damping=0.01, noise=0.02, seed=0):
    """A roving test of ``plate`` simulated setup by setup.

    The nodes are the interior points of a ``divisions`` grid (``"i-j"``:
    ``x = i a / nx``, ``y = j b / ny``), every sensor measures vertical
    acceleration. The ``references`` stay in every setup; the other nodes
    are visited ``per_setup`` at a time. Every other channel points down
    (direction ``-z``) and the roving sensors of every third setup record
    in ``g``, so directions and units matter. Each setup has its own white
    forces at every node (seed ``seed + setup``) at a level that differs
    from setup to setup (a factor 1 to 3), and Gaussian noise of ``noise``
    times each channel's RMS.

    Returns
    -------
    setups : list of Setup
    geometry : Geometry
        The nodes, the grid lines and the plate's outline as background.
    truth : tuple (freq_hz, shapes)
        Natural frequencies and the modes ``(n_nodes, n_modes)`` along
        ``+z`` at ``geometry.nodes``.
    """
    nx, ny = (positive_int("divisions", d, minimum=2) for d in divisions)
    per_setup = positive_int("per_setup", per_setup)
    duration, fs = positive_float("duration", duration), positive_float("fs", fs)
    noise = nonnegative_float("noise", noise)
    names = [f"{i}-{j}" for j in range(1, ny) for i in range(1, nx)]
    xy = np.array([[plate.length_x * int(n.split("-")[0]) / nx, plate.length_y * int(n.split("-")[1]) / ny]
                   for n in names])
    unknown = [r for r in references if r not in names]
    if unknown:
        raise ValueError(f"references {unknown} are not nodes of the grid ({names[0]} ... {names[-1]})")
    roving = [n for n in names if n not in references]
    omega = plate.natural_frequencies(n_modes)
    modes = plate.mode_shapes(xy, n_modes)
    n_samples = int(round(duration * fs))
    rng = np.random.default_rng(seed)
    setups = []
    for s, start in enumerate(range(0, len(roving), per_setup)):
        nodes = list(references) + roving[start:start + per_setup]
        sign = np.where(np.arange(len(nodes)) % 2, -1.0, 1.0)
        rows = [names.index(n) for n in nodes]
        level = 1 + 2 * rng.random()
        acc = ambient_response(omega, damping, modes[rows] * sign[:, None], modes, n_samples, 1 / fs,
                               seed=seed + 1 + s, force_rms=level)
        acc += noise * acc.std(axis=0) * rng.standard_normal(acc.shape)
        in_g = (s % 3 == 2) & (np.arange(len(nodes)) >= len(references))
        acc[:, in_g] /= 9.80665
        table = pd.DataFrame({
            "channel": range(len(nodes)), "name": [f"{'ref' if k < len(references) else 'rov'}_{n}"
                                                   for k, n in enumerate(nodes)],
            "node": nodes, "x": 0.0, "y": 0.0, "z": sign, "quantity": "acceleration",
            "unit": np.where(in_g, "g", "m/s2"),
            "role": ["reference" if k < len(references) else "roving" for k in range(len(nodes))],
        })
        setups.append(Setup(f"setup_{s + 1}", MeasuredRecord(acc, 1 / fs), table))
    lines = [(f"{i}-{j}", f"{i + 1}-{j}") for j in range(1, ny) for i in range(1, nx - 1)] + \
            [(f"{i}-{j}", f"{i}-{j + 1}") for j in range(1, ny - 1) for i in range(1, nx)]
    corners = np.array([[0, 0, 0], [plate.length_x, 0, 0], [plate.length_x, plate.length_y, 0],
                        [0, plate.length_y, 0]], dtype=float)
    geometry = Geometry(pd.DataFrame({"x": xy[:, 0], "y": xy[:, 1], "z": 0.0}, index=pd.Index(names, name="node")),
                        lines, background_nodes=corners, background_lines=np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
                        source="simulated plate")
    return setups, geometry, (omega / (2 * np.pi), modes)


def save_setup(setup: Setup, folder) -> Path:
    """Write ``setup`` in the project's own format: ``folder/record.npz``
    (:func:`modal.save_record_npz`, with its rate) and ``folder/channels.csv``
    (:func:`modal.setups.read_channel_table` reads it back)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    save_record_npz(folder / "record.npz", setup.record.acc, setup.record.dt)
    setup.channels.to_csv(folder / "channels.csv", index=False)
    return folder


def save_geometry(geometry: Geometry, folder) -> Path:
    """Write ``geometry`` in the project's own format (``nodes.csv``,
    ``lines.csv``; :func:`modal.setups.read_geometry` reads it back)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    geometry.nodes.reset_index().to_csv(folder / "nodes.csv", index=False)
    pd.DataFrame(geometry.lines, columns=["node_1", "node_2"]).to_csv(folder / "lines.csv", index=False)
    return folder
