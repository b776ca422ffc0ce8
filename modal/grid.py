"""A finite-element model of the AFAL grid (thesis Sec. 7.1).

The thesis describes the grid only as "nine thin aluminum strips",
"cantilevered at the top to an I-beam", with accelerometers at "places on the
grid where the strips overlapped", and gives the estimated frequencies of its
four lowest modes, 0.83, 1.76, 4.35 and 6.49 Hz (Tables 10-12). Its records
and drawings are not public, so :class:`Grid` is a virtual stand-in built to
match those four frequencies with physically plausible dimensions.

Layout (default, as tuned)::

        I-beam (clamp)  x   x   x   x        y = height
                        |   |   |   |
                        +---+---+---+        horizontal strip 1
                        |   |   |   |
                        +---+---+---+        horizontal strip 2
                        |   |   |   |
                        +---+---+---+        horizontal strip 3
                        |   |   |   |
                        +---+---+---+        horizontal strip 4
                        |   |   |   |
                        +---+---+---+        horizontal strip 5, y = 0
                      x = 0       x = width

Four vertical strips hang from the clamp at equal spacing; five horizontal
strips cross them at equal spacing, the lowest one along the bottom edge: nine
strips, 20 crossings. The strips lie flat in the plane of the grid (width ``b``
in the plane, thickness ``t`` out of it), so the out-of-plane motion is the
flexible one and the in-plane motion is ignored.

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

Tuned values (defaults of :class:`Grid`): grid 1.20 m wide and 2.20 m high,
aluminium ``E = 70 GPa``, ``nu = 0.33``, ``rho = 2700 kg/m^3``; strips 50 mm
wide, 2.0 mm thick (vertical) and 2.0 mm thick (horizontal); 60 g lumped at
every crossing (an accelerometer with its mount). These give 0.83, 1.76,
4.35 and 6.49 Hz within 5 % (see ``tests/test_grid.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg

from ._checks import nonnegative_float, positive_float, positive_int

#: Estimated frequencies (Hz) of the grid's four lowest modes, thesis Tables 10-12.
THESIS_ESTIMATES_HZ = (0.83, 1.76, 4.35, 6.49)


def _bending(ei: float, m: float, length: float):
    """Hermite-cubic beam element, DOFs ``(w1, w1', w2, w2')``."""
    L = length
    k = ei / L**3 * np.array(
        [
            [12, 6 * L, -12, 6 * L],
            [6 * L, 4 * L**2, -6 * L, 2 * L**2],
            [-12, -6 * L, 12, -6 * L],
            [6 * L, 2 * L**2, -6 * L, 4 * L**2],
        ]
    )
    mm = m * L / 420 * np.array(
        [
            [156, 22 * L, 54, -13 * L],
            [22 * L, 4 * L**2, 13 * L, -3 * L**2],
            [54, 13 * L, 156, -22 * L],
            [-13 * L, -3 * L**2, -22 * L, 4 * L**2],
        ]
    )
    return k, mm


def _geometric(tension: float, length: float):
    """Consistent geometric stiffness of an axial force (tension > 0), DOFs as :func:`_bending`."""
    L = length
    return tension / (30 * L) * np.array(
        [
            [36, 3 * L, -36, 3 * L],
            [3 * L, 4 * L**2, -3 * L, -(L**2)],
            [-36, -3 * L, 36, -3 * L],
            [3 * L, -(L**2), -3 * L, 4 * L**2],
        ]
    )


def _bar(stiffness: float, inertia: float, length: float):
    """Linear (torsion) element: stiffness ``GJ``, inertia per length."""
    k = stiffness / length * np.array([[1.0, -1.0], [-1.0, 1.0]])
    m = inertia * length / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
    return k, m


@dataclass(frozen=True)
class Grid:
    """Planar grid of thin strips, clamped along its top edge (thesis Sec. 7.1).

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
        Thickness of the horizontal strips; default ``thickness``.
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

    width: float = 1.20
    height: float = 2.20
    n_vertical: int = 4
    n_horizontal: int = 5
    strip_width: float = 0.050
    thickness: float = 0.0020
    thickness_horizontal: float | None = None
    youngs_modulus: float = 70e9
    poisson: float = 0.33
    density: float = 2700.0
    elements_per_bay: int = 4
    sensor_mass: float = 0.060
    gravity: float = 9.81

    def __post_init__(self):
        for name in ("width", "height", "strip_width", "thickness", "youngs_modulus", "density"):
            positive_float(name, getattr(self, name))
        if self.thickness_horizontal is not None:
            positive_float("thickness_horizontal", self.thickness_horizontal)
        positive_int("n_vertical", self.n_vertical, minimum=2)
        positive_int("n_horizontal", self.n_horizontal, minimum=1)
        positive_int("elements_per_bay", self.elements_per_bay)
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
        k = np.arange(1, self.n_horizontal + 1)
        return self.height * (1 - k / self.n_horizontal)

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
        return dict(xy=xy, crossings=np.array(crossings), elements=elements, clamped=clamped, free=free)

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
    def _tension(self):
        """Axial force (N) in each vertical strip at height y, by tributary weight."""
        g = self.gravity
        b = self.strip_width
        th = self.thickness_horizontal or self.thickness
        mv = self.density * b * self.thickness  # kg/m, vertical strips
        mh = self.density * b * th
        bay = self.width / (self.n_vertical - 1)
        tributary = np.full(self.n_vertical, bay)
        tributary[[0, -1]] = bay / 2
        ys = self.y_horizontal

        def tension(j, y):
            below = ys[ys < y - 1e-12]
            w_point = below.size * (mh * tributary[j] + self.sensor_mass)
            return g * (mv * y + w_point)

        return tension

    @cached_property
    def _matrices(self):
        mesh = self._mesh
        xy = mesh["xy"]
        n = 3 * len(xy)
        K, M = np.zeros((n, n)), np.zeros((n, n))
        b, G, E, rho = self.strip_width, self.shear_modulus, self.youngs_modulus, self.density
        tension = self._tension()
        for a, c, direction, strip in mesh["elements"]:
            t = self.thickness if direction == 0 else (self.thickness_horizontal or self.thickness)
            ei, gj = E * b * t**3 / 12, G * b * t**3 / 3
            m, ip = rho * b * t, rho * b * t * (b**2 + t**2) / 12
            d = xy[c] - xy[a]
            L = float(np.hypot(*d))
            cs, sn = d / L
            kb, mb = _bending(ei, m, L)
            kt, mt = _bar(gj, ip, L)
            if direction == 0 and self.gravity > 0:
                N = tension(strip, 0.5 * (xy[a, 1] + xy[c, 1]))
                kb = kb + _geometric(N, L)
                kt = kt + N * (b**2 + t**2) / 12 / L * np.array([[1.0, -1.0], [-1.0, 1.0]])
            # Local (w, dw/ds, dw/dn) = T @ global (w, dw/dx, dw/dy).
            T = np.array([[1.0, 0, 0], [0, cs, sn], [0, -sn, cs]])
            Te = scipy.linalg.block_diag(T, T)
            kl, ml = np.zeros((6, 6)), np.zeros((6, 6))
            ib, it = [0, 1, 3, 4], [2, 5]
            kl[np.ix_(ib, ib)], ml[np.ix_(ib, ib)] = kb, mb
            kl[np.ix_(it, it)], ml[np.ix_(it, it)] = kt, mt
            dofs = np.r_[3 * a : 3 * a + 3, 3 * c : 3 * c + 3]
            K[np.ix_(dofs, dofs)] += Te.T @ kl @ Te
            M[np.ix_(dofs, dofs)] += Te.T @ ml @ Te
        wdofs = 3 * mesh["crossings"]
        M[wdofs, wdofs] += self.sensor_mass
        free = mesh["free"]
        return K[np.ix_(free, free)], M[np.ix_(free, free)]

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
        b, rho = self.strip_width, self.density
        th = self.thickness_horizontal or self.thickness
        return (
            rho * b * self.thickness * self.height * self.n_vertical
            + rho * b * th * self.width * self.n_horizontal
            + self.sensor_mass * self.n_vertical * self.n_horizontal
        )
