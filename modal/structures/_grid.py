"""A finite-element model of the AFAL grid (thesis Sec. 7.1).

The thesis describes the grid only as "nine thin aluminum strips",
"cantilevered at the top to an I-beam", with accelerometers at "places on the
grid where the strips overlapped", and gives the estimated frequencies of its
four lowest modes, 0.83, 1.76, 4.35 and 6.49 Hz (Tables 10-12). Its records
and drawings are not public, so :class:`Grid` is a virtual stand-in built to
match those four frequencies with physically plausible dimensions.

Layout (the tuned grid of the thesis workflow, below)::

      I-beam (clamp)  x-----x-----x-----x     y = 0.80 m
                      |     |     |     |
                      |     |     |     |     vertical strips: 4, 1.2 mm x 50 mm
                      |     |     |     |
                      +-----+-----+-----+     y = 0.37 m   horizontal strips: 5,
                      |     |     |     |                  2.9 mm x 16 mm
                      +-----+-----+-----+     y = 0.24 m
                      +-----+-----+-----+     y = 0.14 m
                      +-----+-----+-----+     y = 0.07 m
                      +-----+-----+-----+     y = 0
                    x = 0             x = 1.00 m

Four vertical strips hang from the clamp at equal spacing; five horizontal
strips cross them, the lowest along the bottom edge: nine strips and 20
crossings, numbered row by row from the top, left to right (crossing ``c`` is
node ``c``). The strips lie flat in the plane of the grid (width ``b`` in the
plane, thickness ``t`` out of it), so the out-of-plane motion is the flexible
one and the in-plane motion is ignored.

Model: a grillage of 3-DOF beam elements, one node DOF set
``(w, dw/dx, dw/dy)`` per node: out-of-plane displacement and its two slopes
(the rotations about the global y and x axes). Along an element of direction
``s`` with in-plane normal ``n``, ``dw/ds`` is the Euler-Bernoulli bending
rotation and ``dw/dn`` the Saint-Venant twist, so a crossing (a shared node)
rigidly couples the twist of one strip with the bending slope of the other.
Per element: Hermite-cubic bending (``EI = E b t^3 / 12``), linear torsion
(``GJ``, ``J = b t^3 / 3``), consistent translational mass ``rho b t`` and
consistent torsional inertia ``rho b t (b^2 + t^2) / 12``. A hanging grid is
stiffened by its weight (a pendulum effect of the same order as its elastic
stiffness at these frequencies), so the vertical strips carry the consistent
geometric stiffness of their tension ``N(y)`` (bending and the Wagner term of
torsion), with ``N`` from the weight hanging below on each vertical strip
(horizontal strips and crossing masses shared by tributary length). Set
``gravity=0`` to drop it.

Tuned values (set in one place, the ``grid.model`` block of the workflow's
``config/config.yaml``; :class:`Grid` has no defaults for them):
aluminium ``E = 70 GPa``, ``nu = 0.33``, ``rho = 2700 kg/m^3``, ``g = 9.81``;
grid 1.00 m wide and 0.80 m high; vertical strips 50 mm x 1.2 mm, horizontal
strips 16 mm x 2.9 mm at y = 0.37, 0.24, 0.14, 0.07, 0 m; 67 g at every
crossing (an accelerometer with its mount). Modes in Hz (4 elements per bay;
8 agree to 0.02 %): 0.825 (first bending), 1.778 (first torsion), 4.410
(second bending), 6.467 ("saddle": outer against inner vertical strips, the
horizontal strips bending), 9.821 (second torsion), 14.00, 15.50, 16.88,
21.65, 22.72, ...; 18 modes below 50 Hz. The lowest four lie within 1.4 % of
the thesis's 0.83, 1.76, 4.35 and 6.49 Hz, the fifth well clear of them.
Without gravity the first mode would drop to 0.50 Hz.

How the tuning went (differential evolution and least squares over
dimensions, thicknesses, widths, crossing masses and the spacing of the
horizontal strips): with equally spaced horizontal strips no
plausible 4 x 5 grid came within 25 % of all four frequencies, because the
weight-induced tension compresses the frequency ratios (a hanging chain has
ratios 1 : 2.3 : 3.6) while the thesis's are 1 : 2.1 : 5.2 : 7.8, and a wider
grid lowers the "saddle" mode (outer against inner vertical strips) below
6.5 Hz. Concentrating the horizontal strips towards the free edge (a
tip-mass effect) and making the horizontal strips thicker than the vertical
ones (a tuned scalar) matches all four. The grid is therefore smaller (about
1 m) than the "couple of metres" first guessed; nothing in the thesis fixes
its size.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg

from .._checks import nonnegative_float, positive_float, positive_int

def _stack(rows) -> np.ndarray:
    """``rows`` of per-element arrays -> ``(n_elements, n, n)``."""
    return np.moveaxis(np.array([np.broadcast_arrays(*row) for row in rows], dtype=float), -1, 0)


def _bending(ei, m, L):
    """Hermite-cubic beam elements, DOFs ``(w1, w1', w2, w2')``; arrays over elements."""
    k = _stack(
        [
            [12, 6 * L, -12, 6 * L],
            [6 * L, 4 * L**2, -6 * L, 2 * L**2],
            [-12, -6 * L, 12, -6 * L],
            [6 * L, 2 * L**2, -6 * L, 4 * L**2],
        ]
    ) * (ei / L**3)[:, None, None]
    mm = _stack(
        [
            [156, 22 * L, 54, -13 * L],
            [22 * L, 4 * L**2, 13 * L, -3 * L**2],
            [54, 13 * L, 156, -22 * L],
            [-13 * L, -3 * L**2, -22 * L, 4 * L**2],
        ]
    ) * (m * L / 420)[:, None, None]
    return k, mm


def _geometric(tension, L):
    """Consistent geometric stiffness of an axial force (tension > 0), DOFs as :func:`_bending`."""
    return _stack(
        [
            [36, 3 * L, -36, 3 * L],
            [3 * L, 4 * L**2, -3 * L, -(L**2)],
            [-36, -3 * L, 36, -3 * L],
            [3 * L, -(L**2), -3 * L, 4 * L**2],
        ]
    ) * (tension / (30 * L))[:, None, None]


def _bar(stiffness, inertia, L):
    """Linear (torsion) elements: stiffness ``GJ``, inertia per length; arrays over elements."""
    unit = np.array([[1.0, -1.0], [-1.0, 1.0]])
    k = (stiffness / L)[:, None, None] * unit
    m = (inertia * L / 6)[:, None, None] * np.array([[2.0, 1.0], [1.0, 2.0]])
    return k, m


@dataclass(frozen=True, kw_only=True)
class Grid:
    """Planar grid of thin strips, clamped along its top edge (thesis Sec. 7.1).

    Every parameter is keyword-only, and all but the three optional ones are
    required: the model of a particular grid is stated in full where it is
    used (the thesis's tuned grid in the workflow's config, ``grid.model``).

    Parameters
    ----------
    width, height : float
        Overall size in m; the outer vertical strips lie at ``x = 0`` and
        ``x = width``, the clamp at ``y = height``, the lowest horizontal
        strip at ``y = 0``.
    n_vertical, n_horizontal : int
        Number of vertical and horizontal strips (equally spaced); horizontal
        strip ``k = 1..n_horizontal`` lies at ``y = height (1 - k / n_horizontal)``.
    strip_width : float
        In-plane width ``b`` of every strip (m).
    thickness : float
        Thickness ``t`` of the vertical strips (m).
    thickness_horizontal : float, optional
        Thickness of the horizontal strips; default (None) ``thickness``.
    strip_width_horizontal : float, optional
        Width of the horizontal strips; default (None) ``strip_width``.
    horizontal_y : tuple of float, optional
        Heights (m) of the ``n_horizontal`` horizontal strips, strictly
        decreasing, ``height > y >= 0``; default (None) equal spacing.

    youngs_modulus, poisson, density : float
        ``E`` (Pa), ``nu`` (``G = E / (2 (1 + nu))``), ``rho`` (kg/m^3).
    elements_per_bay : int
        Beam elements between adjacent crossings (and between the clamp and
        the first crossing).
    sensor_mass : float
        Point mass (kg) lumped at every crossing: an accelerometer with its
        mount. The thesis moved its eleven accelerometers between data sets,
        so every crossing carries one.
    gravity : float
        Gravitational acceleration (m/s^2) for the tension of the hanging
        vertical strips; 0 drops the geometric stiffness.
    """

    width: float
    height: float
    n_vertical: int
    n_horizontal: int
    strip_width: float
    thickness: float
    youngs_modulus: float
    poisson: float
    density: float
    elements_per_bay: int
    sensor_mass: float
    gravity: float
    thickness_horizontal: float | None = None
    strip_width_horizontal: float | None = None
    horizontal_y: tuple[float, ...] | None = None

    def __post_init__(self):
        for name in ("width", "height", "strip_width", "thickness", "youngs_modulus", "density"):
            positive_float(name, getattr(self, name))
        for name in ("thickness_horizontal", "strip_width_horizontal"):
            if getattr(self, name) is not None:
                positive_float(name, getattr(self, name))
        positive_int("n_vertical", self.n_vertical, minimum=2)
        positive_int("n_horizontal", self.n_horizontal, minimum=1)
        positive_int("elements_per_bay", self.elements_per_bay)
        if self.horizontal_y is not None:
            object.__setattr__(self, "horizontal_y", tuple(float(v) for v in np.ravel(self.horizontal_y)))
            y = np.asarray(self.horizontal_y)
            if (
                y.shape != (self.n_horizontal,)
                or not np.all(np.isfinite(y))
                or np.any(np.diff(y) >= 0)
                or y[0] >= self.height
                or y[-1] < 0
            ):
                raise ValueError(
                    f"horizontal_y must hold {self.n_horizontal} strictly decreasing heights "
                    f"in [0, height), got {self.horizontal_y!r} (None: equal spacing)"
                )
        nonnegative_float("sensor_mass", self.sensor_mass)
        nonnegative_float("gravity", self.gravity)
        nu = float(self.poisson)
        if not np.isfinite(nu) or not -1 < nu < 0.5:
            raise ValueError(f"poisson must satisfy -1 < nu < 0.5, got {self.poisson!r}")

    # ------------------------------------------------------------------ geometry
    @property
    def shear_modulus(self) -> float:
        """``G = E / (2 (1 + nu))`` in Pa."""
        return self.youngs_modulus / (2 * (1 + self.poisson))

    @property
    def x_vertical(self) -> np.ndarray:
        """x (m) of the vertical strips."""
        return np.linspace(0.0, self.width, self.n_vertical)

    @property
    def y_horizontal(self) -> np.ndarray:
        """y (m) of the horizontal strips, top to bottom."""
        if self.horizontal_y is not None:
            return np.array(self.horizontal_y, dtype=float)
        k = np.arange(1, self.n_horizontal + 1)
        return self.height * (1 - k / self.n_horizontal)

    def section(self, direction: int):
        """``(b, t)`` of the vertical (``direction = 0``) or horizontal (1) strips."""
        if direction == 0:
            return self.strip_width, self.thickness
        b = self.strip_width_horizontal if self.strip_width_horizontal is not None else self.strip_width
        t = self.thickness_horizontal if self.thickness_horizontal is not None else self.thickness
        return b, t

    @cached_property
    def _mesh(self):
        """Nodes, elements and bookkeeping (computed once)."""
        ne = self.elements_per_bay
        xs, ys = self.x_vertical, self.y_horizontal
        nodes: list[tuple[float, float]] = []
        index: dict[tuple[int, int], int] = {}

        def node(x, y):
            key = (round(x * 1e9), round(y * 1e9))
            if key not in index:
                index[key] = len(nodes)
                nodes.append((x, y))
            return index[key]

        # Crossings first, so that crossing c is node c (row-major, top row first).
        crossings = [node(x, y) for y in ys for x in xs]
        elements = []  # (node a, node b, direction 0 = vertical / 1 = horizontal, strip index)
        stations_v = np.concatenate(([self.height], ys))
        for j, x in enumerate(xs):
            for y0, y1 in zip(stations_v[:-1], stations_v[1:]):
                pts = np.linspace(y0, y1, ne + 1)
                ids = [node(x, y) for y in pts]
                elements += [(a, b, 0, j) for a, b in zip(ids[:-1], ids[1:])]
        for k, y in enumerate(ys):
            for x0, x1 in zip(xs[:-1], xs[1:]):
                pts = np.linspace(x0, x1, ne + 1)
                ids = [node(x, y) for x in pts]
                elements += [(a, b, 1, k) for a, b in zip(ids[:-1], ids[1:])]
        xy = np.array(nodes)
        clamped = np.flatnonzero(np.isclose(xy[:, 1], self.height))
        fixed = np.concatenate([3 * clamped + c for c in range(3)])
        free = np.setdiff1d(np.arange(3 * len(nodes)), fixed)
        return dict(xy=xy, crossings=np.array(crossings), elements=np.array(elements), clamped=clamped, free=free)

    @property
    def coordinates(self) -> np.ndarray:
        """Node coordinates ``(n_nodes, 2)`` in m."""
        return self._mesh["xy"]

    @property
    def n_nodes(self) -> int:
        return len(self._mesh["xy"])

    @property
    def free_dofs(self) -> np.ndarray:
        """Global DOF numbers (``3 node + {0: w, 1: dw/dx, 2: dw/dy}``) kept after clamping."""
        return self._mesh["free"]

    def crossings(self):
        """Strip crossings, row by row from the top, left to right.

        Returns
        -------
        nodes : ndarray of int, shape (n_vertical * n_horizontal,)
            Node ids (crossing ``c`` is node ``c``).
        xy : ndarray, shape (n_crossings, 2)
            Their coordinates in m.
        """
        c = self._mesh["crossings"]
        return c, self._mesh["xy"][c]

    def dof(self, node) -> np.ndarray:
        """Index of the displacement DOF ``w`` of ``node`` (int or array) in the
        free-DOF vectors of :meth:`mass`, :meth:`stiffness` and :meth:`modes`."""
        node = np.asarray(node)
        if np.any((node < 0) | (node >= self.n_nodes)):
            raise ValueError(f"node must lie in 0..{self.n_nodes - 1}, got {node.tolist()}")
        pos = np.searchsorted(self.free_dofs, 3 * node)
        pos = np.minimum(pos, self.free_dofs.size - 1)
        if np.any(self.free_dofs[pos] != 3 * node):
            raise ValueError(f"node {node.tolist()} is clamped")
        return pos

    # ------------------------------------------------------------------ matrices
    def _tension(self, strip, y):
        """Axial force (N) in vertical strip ``strip`` at height ``y`` (arrays):
        the weight hanging below, horizontal strips and crossing masses
        shared among the vertical strips by tributary width."""
        mv = self.density * np.prod(self.section(0))  # kg/m, vertical strips
        mh = self.density * np.prod(self.section(1))
        bay = self.width / (self.n_vertical - 1)
        tributary = np.full(self.n_vertical, bay)
        tributary[[0, -1]] = bay / 2
        rows_below = np.sum(self.y_horizontal[None, :] < y[:, None] - 1e-12, axis=1)
        return self.gravity * (mv * y + rows_below * (mh * tributary[strip] + self.sensor_mass))

    @cached_property
    def _matrices(self):
        mesh = self._mesh
        xy = mesh["xy"]
        a, c, direction, strip = mesh["elements"].T
        d = xy[c] - xy[a]
        L = np.hypot(d[:, 0], d[:, 1])
        cs, sn = d[:, 0] / L, d[:, 1] / L
        (bv, tv), (bh, th) = self.section(0), self.section(1)
        vertical = direction == 0
        b, t = np.where(vertical, bv, bh), np.where(vertical, tv, th)
        G, E, rho = self.shear_modulus, self.youngs_modulus, self.density
        kb, mb = _bending(E * b * t**3 / 12, rho * b * t, L)
        kt, mt = _bar(G * b * t**3 / 3, rho * b * t * (b**2 + t**2) / 12, L)
        if self.gravity > 0:
            N = np.zeros(L.size)
            N[vertical] = self._tension(strip[vertical], 0.5 * (xy[a, 1] + xy[c, 1])[vertical])
            kb = kb + _geometric(N, L)
            # Wagner term: tension resists twist with N I_p / A, I_p / A = (b^2 + t^2) / 12.
            kt = kt + _bar(N * (b**2 + t**2) / 12, np.zeros_like(L), L)[0]
        ne = L.size
        kl, ml = np.zeros((ne, 6, 6)), np.zeros((ne, 6, 6))
        ib, it = [0, 1, 3, 4], [2, 5]
        # Local DOFs: w1, dw/ds1, dw/dn1, w2, dw/ds2, dw/dn2.
        kl[np.ix_(range(ne), ib, ib)], ml[np.ix_(range(ne), ib, ib)] = kb, mb
        kl[np.ix_(range(ne), it, it)], ml[np.ix_(range(ne), it, it)] = kt, mt
        # Local (w, dw/ds, dw/dn) = T @ global (w, dw/dx, dw/dy), per node.
        T = np.zeros((ne, 6, 6))
        for o in (0, 3):
            T[:, o, o] = 1.0
            T[:, o + 1, o + 1], T[:, o + 1, o + 2] = cs, sn
            T[:, o + 2, o + 1], T[:, o + 2, o + 2] = -sn, cs
        kg = np.einsum("eji,ejk,ekl->eil", T, kl, T)
        mg = np.einsum("eji,ejk,ekl->eil", T, ml, T)
        dofs = np.concatenate([3 * a[:, None] + np.arange(3), 3 * c[:, None] + np.arange(3)], axis=1)
        n = 3 * len(xy)
        K, M = np.zeros((n, n)), np.zeros((n, n))
        rows, cols = np.broadcast_arrays(dofs[:, :, None], dofs[:, None, :])
        np.add.at(K, (rows, cols), kg)
        np.add.at(M, (rows, cols), mg)
        wdofs = 3 * mesh["crossings"]
        M[wdofs, wdofs] += self.sensor_mass
        free = mesh["free"]
        K, M = K[np.ix_(free, free)], M[np.ix_(free, free)]
        # Symmetrise against round-off of the transformations.
        return 0.5 * (K + K.T), 0.5 * (M + M.T)

    def stiffness(self) -> np.ndarray:
        """Stiffness matrix ``K`` over the free DOFs (elastic plus geometric)."""
        return self._matrices[0].copy()

    def mass(self) -> np.ndarray:
        """Consistent mass matrix ``M`` over the free DOFs, with the crossing masses."""
        return self._matrices[1].copy()

    @cached_property
    def _eig(self):
        K, M = self._matrices
        lam, phi = scipy.linalg.eigh(K, M)
        return np.sqrt(np.clip(lam, 0, None)), phi

    def modes(self, n_modes=None, fmax_hz=None):
        """Undamped modes from ``K phi = omega^2 M phi`` (``scipy.linalg.eigh``).

        Parameters
        ----------
        n_modes : int, optional
            Keep the lowest ``n_modes``.
        fmax_hz : float, optional
            Keep the modes at or below ``fmax_hz`` (combined with ``n_modes``
            by taking the fewer).

        Returns
        -------
        omega : ndarray, shape (n,)
            Natural frequencies in rad/s, ascending.
        shapes : ndarray, shape (n_free_dofs, n)
            Mass-normalised mode shapes (``shapes.T M shapes = I``) over the
            free DOFs; the displacement of node ``i`` is row ``dof(i)``.
        """
        omega, phi = self._eig
        n = omega.size
        if n_modes is not None:
            n = min(n, positive_int("n_modes", n_modes))
        if fmax_hz is not None:
            n = min(n, int(np.searchsorted(omega, 2 * np.pi * positive_float("fmax_hz", fmax_hz), side="right")))
        return omega[:n].copy(), phi[:, :n].copy()

    def frequencies_hz(self, n_modes: int) -> np.ndarray:
        """The ``n_modes`` lowest natural frequencies in Hz."""
        return self.modes(n_modes)[0] / (2 * np.pi)

    @property
    def total_mass(self) -> float:
        """Mass of the strips and crossing masses (kg)."""
        rho = self.density
        return (
            rho * np.prod(self.section(0)) * self.height * self.n_vertical
            + rho * np.prod(self.section(1)) * self.width * self.n_horizontal
            + self.sensor_mass * self.n_vertical * self.n_horizontal
        )
