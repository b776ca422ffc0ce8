"""Mode shapes drawn on the structure: a 3D picture of the undeformed and
deformed geometry, and an animation over one cycle (matplotlib, imported
here only)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .._checks import printable
from ._geometry import Geometry

#: The largest drawn displacement as a fraction of the structure's size
#: (:attr:`Geometry.size`).
DRAWN_FRACTION = 0.12


def node_motion(geometry: Geometry, shapes: pd.DataFrame, mode: int) -> tuple[np.ndarray, np.ndarray]:
    """Complex motion ``(n_nodes, 3)`` of each geometry node in ``mode`` and
    a mask of the nodes that have a measured component.

    From ``shapes`` (long form, :class:`modal.setups.MergedModes`); a
    direction no channel measured moves as a linked parent says
    (``geometry.links``), else not at all: a node without data is drawn at
    rest.
    """
    rows = shapes[shapes["mode"] == mode].set_index("node")
    index = {str(n): i for i, n in enumerate(geometry.nodes.index)}
    u = np.full((len(index), 3), np.nan + 0j)
    for node, row in rows.iterrows():
        if str(node) in index:
            u[index[str(node)]] = row[["x", "y", "z"]].to_numpy(dtype=float) + \
                1j * row[["x_im", "y_im", "z_im"]].to_numpy(dtype=float)
    measured = ~np.all(np.isnan(u), axis=1)
    for link in geometry.links.itertuples():
        parent, child = index[str(link.parent)], index[str(link.child)]
        p, c = np.array([link.px, link.py, link.pz]), np.array([link.cx, link.cy, link.cz])
        c_unit = c / np.linalg.norm(c)
        along = np.nan_to_num(u[parent]) @ p
        axis = int(np.argmax(np.abs(c_unit)))
        if np.isnan(u[child, axis]):
            u[child] = np.where(np.abs(c_unit) > 0, c_unit * along, u[child])
    return np.nan_to_num(u), measured


def _axes(figure, geometry, position=(1, 1, 1)):
    ax = figure.add_subplot(*position, projection="3d")
    points = np.vstack([geometry.coordinates, geometry.background_nodes])
    span = np.ptp(points, axis=0)
    # room for the largest drawn displacement either way, also across a flat structure
    ax.set_box_aspect(np.maximum(span, 2 * DRAWN_FRACTION * geometry.size))
    ax.set_axis_off()
    return ax


def _draw(ax, geometry, xyz, colour, style="-", width=1.5):
    index = {str(n): i for i, n in enumerate(geometry.nodes.index)}
    for a, b in geometry.lines:
        i, j = index[str(a)], index[str(b)]
        ax.plot(*xyz[[i, j]].T, style, color=colour, lw=width)


def _scale(geometry, u) -> float:
    peak = np.max(np.abs(u)) if u.size else 0.0
    return DRAWN_FRACTION * geometry.size / peak if peak > 0 else 0.0


def draw_mode(ax, geometry: Geometry, shapes: pd.DataFrame, mode: int, title: str | None = None) -> None:
    """Draw the mode on the 3D axes ``ax``: background (grey), the
    undeformed lines (dashed) and the deformed ones (the real view of the
    shape, the largest displacement :data:`DRAWN_FRACTION` of the
    structure's size); measured nodes as dots."""
    u, measured = node_motion(geometry, shapes, mode)
    xyz = geometry.coordinates
    for a, b in geometry.background_lines:
        ax.plot(*geometry.background_nodes[[a, b]].T, color="0.85", lw=0.8)
    _draw(ax, geometry, xyz, "0.6", "--", 0.8)
    deformed = xyz + _scale(geometry, u) * u.real
    _draw(ax, geometry, deformed, "C0", "-", 1.8)
    ax.scatter(*deformed[measured].T, color="C3", s=12, depthshade=False)
    ax.set_title(printable(title or f"mode {mode}"), fontsize=10)


def mode_shape_figure(geometry: Geometry, shapes: pd.DataFrame, mode: int, title: str | None = None):
    """One mode drawn on the structure (:func:`draw_mode`); a matplotlib
    ``Figure``."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(5, 5))
    draw_mode(_axes(figure, geometry), geometry, shapes, mode, title)
    figure.subplots_adjust(0, 0, 1, 0.95)
    return figure


def modes_figure(geometry: Geometry, shapes: pd.DataFrame, titles: dict, columns: int = 3):
    """Every mode of ``titles`` (mode number -> title) drawn side by side,
    ``columns`` per row (:func:`draw_mode`); a matplotlib ``Figure``."""
    from matplotlib.figure import Figure

    rows = max(1, -(-len(titles) // columns))
    figure = Figure(figsize=(3.6 * columns, 3.6 * rows))
    for k, (mode, title) in enumerate(titles.items()):
        draw_mode(_axes(figure, geometry, (rows, columns, k + 1)), geometry, shapes, mode, title)
    figure.subplots_adjust(0, 0, 1, 0.95, wspace=0, hspace=0.08)
    return figure


def mode_shape_animation(geometry: Geometry, shapes: pd.DataFrame, mode: int, path, title: str | None = None,
                         frames: int = 16, dpi: int = 70) -> None:
    """Write an animated GIF of the mode over one cycle (the complex shape
    times ``exp(i theta)``, so a complex mode travels) to ``path``."""
    from matplotlib.animation import FuncAnimation, PillowWriter
    from matplotlib.figure import Figure

    u, measured = node_motion(geometry, shapes, mode)
    xyz, scale = geometry.coordinates, _scale(geometry, u)
    figure = Figure(figsize=(4, 4))
    ax = _axes(figure, geometry)
    ax.set_title(printable(title or f"mode {mode}"), fontsize=9)
    figure.subplots_adjust(0, 0, 1, 0.93)
    lo = np.vstack([xyz - scale * np.abs(u), geometry.background_nodes]).min(axis=0)
    hi = np.vstack([xyz + scale * np.abs(u), geometry.background_nodes]).max(axis=0)

    def frame(k):
        for artist in list(ax.lines) + list(ax.collections):
            artist.remove()
        for a, b in geometry.background_lines:
            ax.plot(*geometry.background_nodes[[a, b]].T, color="0.85", lw=0.8)
        _draw(ax, geometry, xyz, "0.7", "--", 0.6)
        deformed = xyz + scale * (u * np.exp(2j * np.pi * k / frames)).real
        _draw(ax, geometry, deformed, "C0", "-", 1.6)
        ax.scatter(*deformed[measured].T, color="C3", s=8, depthshade=False)
        ax.set(xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]), zlim=(lo[2], hi[2]))
        return []

    FuncAnimation(figure, frame, frames=frames).save(path, writer=PillowWriter(fps=10), dpi=dpi)
