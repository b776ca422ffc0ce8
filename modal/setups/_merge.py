"""Several setups, one result: each setup identified on its own, its modes
matched across setups by frequency and the reference channels' MAC, and
its shapes rescaled through the reference channels into one shape per mode
(PoSER: post-identification separate estimation re-scaling), then resolved
node by node into the global frame."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..identification import Stabilisation, mac, modal_phase_collinearity
from ..records import read_record
from ._agreement import (DISAGREEMENT_COLUMNS, REF_MAC_AGREE, REF_RESIDUAL_MAX, relative_uncertainty,
                         setup_disagreements, tolerance)
from ._channels import dof_keys, read_channel_table, read_pyoma_setup, unit_factor

#: Record files a setup folder may hold beside ``channels.csv``.
RECORD_SUFFIXES = (".npy", ".npz", ".csv", ".txt", ".tsv", ".lvm", ".uff", ".unv")

#: A node's direction is resolved when its measuring directions span it to
#: this tolerance (squared norm of the axis projected on their span).
SPAN_TOL = 1e-6

#: A node moving more than this many times as much as every node linked to
#: it is flagged and does not set a shape's scale (:func:`normalise`). A
#: coarse grid's legitimate step towards an unmeasured antinode reaches
#: sin 60° / sin 30° = 1.73; the Weimar frame's node 24 reads 1.99-2.01.
NODE_FACTOR = 1.8
#: Without a geometry a node is compared with every other node that moves,
#: and only when there are at least this many: one node above one or two
#: others (a single setup's two nodes, one near a modal node) is how a mode
#: can look, no evidence of a bad channel.
NODE_PEERS = 3


@dataclass(frozen=True)
class Setup:
    """One setup of a roving test: a record and its channel table.

    Attributes
    ----------
    name : str
    record : MeasuredRecord
    channels : pandas.DataFrame
        The channel table of the channels used (:mod:`modal.setups._channels`).
    path : Path, optional
        Where the setup was read from (a folder or a record): an input no
        results may overwrite.
    """

    name: str
    record: object
    channels: pd.DataFrame
    path: Path | None = None

    @property
    def reference_keys(self) -> list[tuple]:
        keys = dof_keys(self.channels)
        return [k for k, role in zip(keys, self.channels["role"]) if role == "reference"]


def read_setup(path, fs=None, geometry=None) -> Setup:
    """Read a setup: a pyOMA setup folder (``channel_dofs.txt``,
    ``setup_info.txt``, one ``.npy``), a folder with ``channels.csv`` and one
    record file (:func:`modal.setups.read_channel_table`), or a record file
    whose channels the ``geometry``'s sensors name (pyOMA2).

    ``fs`` (Hz) is the rate of a record that does not carry one; a pyOMA
    folder's stated rate must agree with it. Every node must be in the
    ``geometry`` when one is given.
    """
    path = Path(path)
    nodes = None if geometry is None else geometry.nodes.index
    if path.is_dir() and (path / "channel_dofs.txt").exists():
        record_path, rate, table = read_pyoma_setup(path)
        if fs is not None and abs(fs - rate) > 1e-6 * rate:
            raise ValueError(f"{path}: setup_info.txt states {rate:g} Hz, --fs {fs:g} Hz")
        record = read_record(record_path, rate)
        if table["channel"].max() >= record.acc.shape[1]:
            raise ValueError(f"{path}: channel_dofs.txt names channel {table['channel'].max()}, the record has "
                             f"{record.acc.shape[1]}")
        if nodes is not None:
            unknown = sorted(set(table["node"]) - set(nodes))
            if unknown:
                raise ValueError(f"{path}: node(s) {', '.join(unknown)} not in the geometry {geometry.source}")
    elif path.is_dir():
        if not (path / "channels.csv").is_file():
            raise ValueError(f"{path}: a setup folder holds channel_dofs.txt and setup_info.txt (pyOMA) "
                             "or channels.csv beside one record")
        files = [p for p in sorted(path.iterdir()) if p.suffix.lower() in RECORD_SUFFIXES
                 and p.name != "channels.csv" and p.is_file()]
        if len(files) != 1:
            raise ValueError(f"{path}: expected one record file beside channels.csv, found "
                             f"{', '.join(p.name for p in files) or 'none'}")
        record = read_record(files[0], fs)
        table = read_channel_table(path / "channels.csv", record.acc.shape[1], nodes)
    elif path.is_file():
        record = read_record(path, fs)
        if geometry is None:
            raise ValueError(f"{path}: a record alone has no channel table: give a setup folder (channels.csv "
                             "beside the record, or pyOMA's layout) or a --geometry that names its sensors")
        table = geometry.channel_table(record.channels["name"])
    else:
        raise ValueError(f"{path}: no such setup (a folder or a record file)")
    return Setup(path.name if path.is_dir() else path.stem, record, table, path)


def check_setups(setups) -> list[tuple]:
    """The reference DOFs common to ``setups`` (node and direction), or
    ``ValueError``: setups of one test share their references; several
    setups need at least one; setup names must differ."""
    setups = list(setups)
    if not setups:
        raise ValueError("setups: none given")
    names = [s.name for s in setups]
    if len(set(names)) != len(names):
        raise ValueError(f"setups: names repeat ({', '.join(names)}); each setup needs a name of its own")
    keys = setups[0].reference_keys
    if len(setups) > 1 and not keys:
        raise ValueError(f"setup {setups[0].name}: no reference channel: several setups are merged through "
                         "the reference channels (role reference), present in every setup")
    for s in setups[1:]:
        missing = [k for k in keys if k not in s.reference_keys]
        extra = [k for k in s.reference_keys if k not in keys]
        if missing or extra:
            def say(ks):
                return "; ".join(f"node {k[0]} along ({k[1]:g}, {k[2]:g}, {k[3]:g})" for k in ks)
            raise ValueError(f"setup {s.name}: its reference channels differ from setup {setups[0].name}'s: "
                             + (f"missing {say(missing)}" if missing else "")
                             + ("; " if missing and extra else "") + (f"extra {say(extra)}" if extra else ""))
    seen = {}
    for s in setups:  # a setup given twice, e.g. through a symbolic link, would count as two
        path = getattr(s.record, "path", None)
        if path is not None:
            first = seen.setdefault(Path(path).resolve(), s.name)
            if first != s.name:
                raise ValueError(f"setups {first} and {s.name} are one record ({Path(path).resolve()}): "
                                 "give each setup once")
    return keys


def identify_setup(setup: Setup, options=None, **keywords) -> tuple[Stabilisation, float]:
    """:func:`modal.identify_record` on a setup's channels, in SI units, with
    each channel's quantity (so mixed quantities give one shape), as ``modal
    identify`` identifies a record alone: every channel is a reference of
    the correlations, so a mode seen only by the roving sensors is found
    too (the reference channels serve the merge, :func:`merge_setups`, not
    the identification: with them as the only correlation references, a
    15-storey building gave 6 modes per setup instead of 7-9).

    Parameters
    ----------
    setup : Setup
    options : IdentifyOptions or str
        The identification's options (or the excitation, the options as
        ``keywords``, as :func:`modal.identify_record` takes them), without
        ``channels``, ``refs`` and ``quantities``: the setup's channel table
        says those.
    **keywords
        Options, and :func:`modal.identify_record`'s ``log``, ``progress``,
        ``criteria``, ``details``.
    """
    from ..measured import identify_options, identify_record

    calls = {k: keywords.pop(k) for k in ("log", "progress", "criteria", "details") if k in keywords}
    options = identify_options(options, **keywords)
    given = [name for name in ("channels", "refs", "quantities") if getattr(options, name) is not None]
    if given:
        raise ValueError(f"{', '.join(given)}: a setup's channel table says which channels are used, which are "
                         "references and what they measure")
    t = setup.channels
    factors = np.array([unit_factor(q, u) for q, u in zip(t["quantity"], t["unit"])])
    acc = setup.record.acc[:, t["channel"].to_numpy()] * factors
    options = options.replace(quantities=list(t["quantity"]))
    return identify_record(acc, setup.record.dt, options, channel_labels=list(t["channel"]), **calls)


@dataclass(frozen=True)
class MergedModes:
    """Modes of several setups merged into one set.

    Attributes
    ----------
    modes : pandas.DataFrame
        One row per mode: ``mode``, ``freq_hz`` and ``freq_spread_hz``,
        ``damping`` and ``damping_spread`` (ratio; mean and standard
        deviation over the setups in which the mode was selected and
        merged), ``freq_std_hz`` and ``damping_std`` (the standard deviation
        of that mean, from the setups' own and their spread:
        :func:`std_of_mean`), ``n_setups`` (selected and merged in), ``n_from_diagram``
        (setups whose shape came from their diagram, :func:`merge_setups`),
        ``setups`` (names), ``left_out`` (setups left out of this mode: see
        ``matches``), ``ref_mac`` (smallest MAC of a merged setup's
        reference part with the others'), ``mpc`` of the merged shape,
        ``n_nodes`` (nodes with a shape), ``n_flagged`` (nodes flagged in
        ``shapes``), ``flag`` (empty, or "doubtful in every setup that
        selected it" with the setups' most common reason: such a mode is kept
        out of the printed list, as a single record's doubtful modes are).
    shapes : pandas.DataFrame
        Long form, one row per mode and node: ``mode``, ``node``, ``x``,
        ``y``, ``z`` (real view in the global frame, NaN where no channel
        measures that direction), ``x_im``, ``y_im``, ``z_im`` (the
        imaginary parts: a complex mode's phases), ``flag`` (why a node's
        motion is doubtful, empty when it is not). Normalised so that the
        largest component of the nodes not flagged is 1 (:func:`normalise`).
    matches : pandas.DataFrame
        One row per mode and setup that holds it or was left out of it:
        ``mode``, ``setup``, ``setup_mode`` (its number in the setup's
        ``modes.csv``; 0 when taken from the diagram or not found),
        ``source`` (``selected`` or ``diagram``), ``status`` (``merged`` or
        ``left out``), ``reason`` (why it was left out), ``freq_hz``,
        ``damping``, ``ref_mac`` (MAC of its reference part with the
        others': 1 - ``ref_mac`` is the squared relative residual of its
        complex scale fit), ``ref_share`` (the reference channels' part of
        the setup's shape: small means a poorly scaled merge), ``scale``
        (modulus of the rescaling factor).
    disagreements : pandas.DataFrame
        The setups left out of the whole merge, one row per check they
        failed: ``setup``, ``check``, ``evidence``
        (:func:`modal.setups._agreement.setup_disagreements`).
    """

    modes: pd.DataFrame
    shapes: pd.DataFrame
    matches: pd.DataFrame
    disagreements: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(columns=DISAGREEMENT_COLUMNS))


def _consensus(refs: np.ndarray) -> np.ndarray:
    """The direction shared by the columns of ``refs`` (n_refs, k): the first
    left singular vector (scipy's SVD), invariant to each column's complex
    scale."""
    unit = refs / np.linalg.norm(refs, axis=0)
    return np.linalg.svd(unit, full_matrices=False)[0][:, 0]


def _match(items, freq_rtol, mac_min) -> list[list]:
    """Greedy clusters of ``items`` (setup, mode, freq, refs, relative
    uncertainty) in order of frequency: an item joins the nearest cluster in
    frequency that holds no mode of its setup yet, lies within the
    tolerance (``freq_rtol``, or :func:`tolerance` of the item's and the
    cluster's uncertainty, the scatter of its members included) and whose
    consensus reference part it matches with MAC >= ``mac_min``."""
    clusters = []
    for item in sorted(items, key=lambda it: it[2]):
        s, _, f, r, u = item
        best, best_gap = None, None
        for cluster in clusters:
            freqs = np.array([it[2] for it in cluster])
            freq = freqs.mean()
            gap = abs(f - freq) / freq
            spread = np.sqrt(np.mean([it[4] ** 2 for it in cluster]) + (freqs.std() / freq) ** 2)
            limit = tolerance(u, spread) if freq_rtol is None else freq_rtol
            if gap > limit or any(it[0] == s for it in cluster):
                continue
            if r.size and mac(r[:, None], _consensus(np.stack([it[3] for it in cluster], axis=1))[:, None])[0, 0] \
                    < mac_min:
                continue
            if best is None or gap < best_gap:
                best, best_gap = cluster, gap
        if best is None:
            clusters.append([item])
        else:
            best.append(item)
    return clusters


def _left_one_out(cluster) -> tuple[list, list]:
    """The members of ``cluster`` whose reference part agrees with the
    consensus of the others (the residual of its complex scale fit at most
    REF_RESIDUAL_MAX), and those that do not (with their MAC): a cluster
    that a wrong reference part happened to start is not kept with it.
    Clusters of fewer than three are kept as they are (with two, which one
    is wrong cannot be told)."""
    if len(cluster) < 3 or not cluster[0][3].size:
        return cluster, []
    kept, out = [], []
    for i, item in enumerate(cluster):
        others = np.stack([it[3] for j, it in enumerate(cluster) if j != i], axis=1)
        value = mac(item[3][:, None], _consensus(others)[:, None])[0, 0]
        if value >= REF_MAC_AGREE:
            kept.append(item)
        else:
            out.append((item, value))
    return kept, out


def required_setups(n_setups: int, min_setups=None) -> int:
    """The setups a merged mode must be selected in: ``min_setups``, or more
    than half of ``n_setups`` (2 of 2, 2 of 3, 3 of 4, 3 of 5): a mode seen
    in fewer is more likely a setup's spurious pole than the structure's."""
    return n_setups // 2 + 1 if min_setups is None else int(min_setups)


def normalise(per_node: dict, neighbours=None) -> tuple[complex, dict]:
    """The complex factor that scales a merged shape, and the nodes flagged.

    The rule: the nodes are taken from the largest motion (modulus over
    their components) down; a node that moves more than NODE_FACTOR times
    as much as every node linked to it (``neighbours``: node -> nodes, from
    the geometry's lines and links; without them, every other node, if
    there are at least NODE_PEERS) is flagged, down to the first node that
    is not; the shape is divided by
    the largest component of the nodes not flagged, which becomes 1 (real). One node that
    disagrees with its neighbours (a miscalibrated or mislabelled channel)
    then does not set the scale of all the others, and says so.
    """
    moduli = {node: float(np.sqrt(np.nansum(np.abs(u) ** 2))) for node, u in per_node.items()
              if np.isfinite(u).any()}
    flags = {}
    for node in sorted(moduli, key=moduli.get, reverse=True):
        if neighbours is None:
            near = [m for other, m in moduli.items() if other != node]
            near = near if len(near) >= NODE_PEERS else []
        else:
            near = [moduli[other] for other in neighbours.get(node, ()) if other in moduli]
        if near and moduli[node] > NODE_FACTOR * max(near):
            flags[node] = (f"moves {moduli[node] / max(near):.3g} x as much as any "
                           f"{'node linked to it' if neighbours is not None else 'other node'}: not used to normalise")
            continue
        break
    values = [c for node, u in per_node.items() if node not in flags for c in u if np.isfinite(c)]
    pivot = max(values, key=abs) if values else 1.0
    return (pivot if abs(pivot) > 0 else 1.0), flags


def _from_diagram(result: Stabilisation, ref_rows, freq, consensus, freq_rtol, mac_min):
    """The shape of a mode the setup did not select, from its diagram: among
    its stable physical poles within ``freq_rtol`` of ``freq`` whose
    reference part matches ``consensus`` (MAC >= ``mac_min``), the medoid
    (largest summed MAC with the others); None when there is none."""
    poles = result.poles
    near = (poles["stable"] & poles["physical"] & (np.abs(poles["freq_hz"] - freq) <= freq_rtol * freq)).to_numpy()
    rows = np.flatnonzero(near)
    if rows.size == 0:
        return None
    shapes = result.pole_shapes[rows].T
    if len(ref_rows):
        keep = mac(shapes[ref_rows], consensus[:, None])[:, 0] >= mac_min
        rows, shapes = rows[keep], shapes[:, keep]
        if rows.size == 0:
            return None
    medoid = int(np.argmax(mac(shapes, shapes).sum(axis=0)))
    pole = poles.iloc[rows[medoid]]
    return shapes[:, medoid], float(pole["freq_hz"]), float(pole["damping"])


def node_shapes(channel_rows, values) -> dict:
    """Each node's complex motion in the global frame from its channels.

    ``channel_rows``: (node, direction) pairs, ``values``: the channels'
    complex shape values (a channel measures ``e . u``). Per node the
    least-squares ``u`` (scipy's ``lstsq``) of all its channels; components
    outside the span of the node's directions are NaN: one direction
    measured gives only that direction's axis, if it is one.
    """
    import scipy.linalg

    by_node = {}
    for (node, e), v in zip(channel_rows, values):
        by_node.setdefault(node, ([], []))
        by_node[node][0].append(e)
        by_node[node][1].append(v)
    out = {}
    for node, (directions, vals) in by_node.items():
        e = np.array(directions, dtype=float)
        u, _, rank, sv = scipy.linalg.lstsq(e.astype(complex), np.array(vals, dtype=complex), cond=1e-6)
        basis = np.linalg.svd(e)[2][:rank]
        spanned = np.sum(basis**2, axis=0) >= 1 - SPAN_TOL
        out[node] = np.where(spanned, u, np.nan + 0j)
    return out


def node_neighbours(geometry) -> dict | None:
    """Node -> the nodes a line or a link joins it to (None without a
    geometry)."""
    if geometry is None:
        return None
    pairs = [(str(a), str(b)) for a, b in geometry.lines]
    pairs += [(str(p), str(c)) for p, c in zip(geometry.links["parent"], geometry.links["child"])]
    out = {}
    for a, b in pairs:
        out.setdefault(a, set()).add(b)
        out.setdefault(b, set()).add(a)
    return out


def std_of_mean(estimates, stds) -> float:
    """Standard deviation of the mean of ``n`` setups' estimates of one
    quantity (a mode's frequency or damping), each with its own standard
    deviation ``sigma_i`` (:func:`modal.identification.segment_std`).

    The larger of the internal ``sqrt(sum sigma_i^2) / n`` (the setups'
    records independent) and, with two setups or more, the external
    ``s / sqrt(n)``, ``s`` the estimates' standard deviation (``ddof=1``):
    setups that disagree beyond their own noise (the roving sensors' mass,
    the temperature changing between setups) widen it, as Birge's ratio of
    external to internal consistency does for a mean of measurements. The
    internal part is unknown where a setup's ``sigma_i`` is NaN; NaN where
    neither part is known (one setup without its own).

    Parameters
    ----------
    estimates, stds : array_like, shape (n,)

    Returns
    -------
    float
    """
    estimates, stds = np.asarray(estimates, dtype=float), np.asarray(stds, dtype=float)
    n = estimates.size
    internal = np.sqrt(np.sum(stds**2)) / n if n else np.nan  # NaN where a setup's own is
    external = np.std(estimates, ddof=1) / np.sqrt(n) if n > 1 else np.nan
    return float(np.nanmax([internal, external])) if np.isfinite([internal, external]).any() else np.nan


def merge_setups(setups, results, freq_rtol=None, mac_min=0.8, min_setups=None, geometry=None) -> MergedModes:
    """Merge the modes of several setups (PoSER).

    1. The setups are compared with each other before any is merged
       (:func:`modal.setups._agreement.setup_disagreements`: reference
       levels, the ratio between reference channels, the reference part of
       each mode, the frequencies); a setup that disagrees with more than
       half of the others is left out of every mode, named in
       ``disagreements`` and in ``matches``.
    2. Modes are matched across setups (:func:`_match`): within the
       frequency tolerance their own uncertainty and scatter give (or a
       fixed ``freq_rtol``) and with reference parts of MAC >= ``mac_min``;
       at most one mode per setup, the nearest cluster in frequency.
       A member whose reference part disagrees with the consensus of the
       others (the residual of its complex scale fit, sqrt(1 - MAC), above
       REF_RESIDUAL_MAX) is left out of that mode and named in ``matches``.
    3. A matched mode a setup did not select is looked for in that setup's
       diagram (stable physical poles near it, matching reference part), so
       the setup's roving nodes still get a shape (``source`` "diagram").
    4. Each setup's shape ``phi_s`` is rescaled by the least-squares factor
       ``a_s = r_s^H u / r_s^H r_s`` that brings its reference part ``r_s``
       onto the consensus ``u`` (first singular vector of the reference
       parts); reference channels take the mean of the rescaled values.
    5. Each node's motion is resolved in the global frame from its channels'
       directions (:func:`node_shapes`); the shape is normalised by
       :func:`normalise` (largest component 1 among the nodes that agree
       with their neighbours; the others flagged).

    Parameters
    ----------
    setups : sequence of Setup
    results : sequence of Stabilisation
        One per setup, as :func:`identify_setup` returns them.
    freq_rtol : float, optional
        A fixed relative frequency tolerance of a match; default: from the
        modes' own uncertainty (:func:`modal.setups._agreement.tolerance`).
    mac_min : float
        Smallest MAC of reference parts for a match.
    min_setups : int, optional
        A mode must be selected in at least this many setups (left-out
        setups do not count); default more than half of them
        (:func:`required_setups`: both of two).
    geometry : Geometry, optional
        Its lines and links say which nodes are neighbours (:func:`normalise`).

    Returns
    -------
    MergedModes
    """
    setups, results = list(setups), list(results)
    if len(setups) != len(results):
        raise ValueError(f"results: {len(results)} for {len(setups)} setups")
    keys = check_setups(setups)
    required = required_setups(len(setups), min_setups)
    ref_rows = [[dof_keys(s.channels).index(k) for k in keys] for s in setups]
    disagreements = setup_disagreements(setups, results, keys, ref_rows)
    bad = {s: "; ".join(disagreements.loc[disagreements["setup"] == setup.name, "evidence"])
           for s, setup in enumerate(setups) if setup.name in set(disagreements["setup"])}
    uncertainty = [relative_uncertainty(r.modes) for r in results]
    freqs = [r.modes["freq_hz"].to_numpy(dtype=float) for r in results]
    if not keys:  # one setup without references: every mode stands alone
        items = [(0, k, f, np.empty(0), uncertainty[0][k]) for k, f in enumerate(freqs[0])]
    else:
        items = [(i, k, f, res.complex_shapes[ref_rows[i], k], uncertainty[i][k])
                 for i, res in enumerate(results) if i not in bad for k, f in enumerate(freqs[i])]
    kept = []
    for cluster in _match(items, freq_rtol, mac_min):
        members, ejected = _left_one_out(cluster)
        if len(members) >= required:
            kept.append((members, ejected))
    kept.sort(key=lambda c: np.mean([it[2] for it in c[0]]))
    used = {(it[0], it[1]) for members, _ in kept for it in members}
    neighbours = node_neighbours(geometry)
    modes, shape_rows, matches = [], [], []
    for number, (cluster, ejected) in enumerate(kept, start=1):
        # doubtful where every setup that selected it flags it (the selection's or the witness's reasons)
        doubts = [str(results[s].modes["flag"].iloc[k]) if "flag" in results[s].modes else ""
                  for s, k, _, _, _ in cluster]
        doubts = [d for d in doubts if d and d != "nan"] if all(d and d != "nan" for d in doubts) else []
        flag = f"doubtful in every setup that selected it ({max(set(doubts), key=doubts.count)})" if doubts else ""
        members, own_std = {}, {}
        for s, k, f, _, _ in cluster:
            m = results[s].modes.iloc[k]
            members[s] = (results[s].complex_shapes[:, k], float(f), float(m["damping"]), int(m["mode"]), "selected")
            own_std[s] = (float(m.get("freq_std_hz", np.nan)), float(m.get("damping_std", np.nan)))
        selected_refs = {s: results[s].complex_shapes[ref_rows[s], k] for s, k, _, _, _ in cluster}
        consensus = _consensus(np.stack(list(selected_refs.values()), axis=1)) if keys else np.empty(0)
        freq = float(np.mean([it[2] for it in cluster]))
        spread = float(np.sqrt(np.mean([it[4] ** 2 for it in cluster])
                               + (np.std([it[2] for it in cluster]) / freq) ** 2))
        left_out = {}
        for (s, k, f, r, _), value in ejected:
            left_out[s] = (k, f, value, f"its reference part disagrees with the others': residual of its complex "
                                        f"scale fit {np.sqrt(1 - value):.2f} > {REF_RESIDUAL_MAX:g} (MAC {value:.2f})")
        for s in range(len(setups)):
            if s in members or s in left_out or not keys:
                continue
            near = [k for k in range(len(freqs[s])) if (s, k) not in used and
                    abs(freqs[s][k] - freq) <= (freq_rtol or tolerance(uncertainty[s][k], spread)) * freq]
            k = min(near, key=lambda k: abs(freqs[s][k] - freq)) if near else None
            value = np.nan if k is None else \
                float(mac(results[s].complex_shapes[ref_rows[s], k][:, None], consensus[:, None])[0, 0])
            if s in bad:
                left_out[s] = (k, np.nan if k is None else freqs[s][k], value, bad[s])
            elif k is not None and value < mac_min:
                left_out[s] = (k, freqs[s][k], value, f"its mode {int(results[s].modes['mode'].iloc[k])} "
                                                      f"({freqs[s][k]:.4g} Hz) has a reference part of MAC "
                                                      f"{value:.2f} < {mac_min:g} with the others'")
            else:
                found = _from_diagram(results[s], ref_rows[s], freq, consensus, freq_rtol or tolerance(spread, 0.0),
                                      mac_min)
                if found is not None:
                    members[s] = (*found, 0, "diagram")
        rows, values, ref_values = [], [], []
        for s in sorted(members):
            phi, f, zeta, setup_mode, source = members[s]
            r = phi[ref_rows[s]]
            scale = (np.vdot(r, consensus) / np.vdot(r, r)) if keys else 1.0
            table = setups[s].channels
            directions = table[["x", "y", "z"]].to_numpy(dtype=float)
            for c, (node, role) in enumerate(zip(table["node"], table["role"])):
                if role != "reference" or not keys:
                    rows.append((node, tuple(directions[c])))
                    values.append(scale * phi[c])
            ref_values.append(scale * r)
            others = [v for t, v in selected_refs.items() if t != s]
            against = _consensus(np.stack(others, axis=1)) if others else consensus
            matches.append({"mode": number, "setup": setups[s].name, "setup_mode": setup_mode, "source": source,
                            "status": "merged", "reason": "", "freq_hz": f, "damping": zeta,
                            "ref_mac": float(mac(r[:, None], against[:, None])[0, 0]) if keys else np.nan,
                            "ref_share": float(np.linalg.norm(r) / np.linalg.norm(phi)) if keys else np.nan,
                            "scale": float(abs(scale))})
        for s, (k, f, value, reason) in sorted(left_out.items()):
            matches.append({"mode": number, "setup": setups[s].name,
                            "setup_mode": 0 if k is None else int(results[s].modes["mode"].iloc[k]),
                            "source": "" if k is None else "selected", "status": "left out", "reason": reason,
                            "freq_hz": f,
                            "damping": np.nan if k is None else float(results[s].modes["damping"].iloc[k]),
                            "ref_mac": value, "ref_share": np.nan, "scale": np.nan})
        if keys:
            mean_refs = np.mean(ref_values, axis=0)
            for j, key in enumerate(keys):
                rows.append((key[0], key[1:]))
                values.append(mean_refs[j])
        per_node = node_shapes(rows, values)
        pivot, flags = normalise(per_node, neighbours)
        for node, u in per_node.items():
            u = u / pivot
            shape_rows.append({"mode": number, "node": node, "x": u[0].real, "y": u[1].real, "z": u[2].real,
                               "x_im": u[0].imag, "y_im": u[1].imag, "z_im": u[2].imag, "flag": flags.get(node, "")})
        stacked = np.concatenate([per_node[n] for n in per_node])
        known = stacked[~np.isnan(stacked)]
        selected = [s for s in members if members[s][4] == "selected"]
        frequencies, dampings = np.array([members[s][1] for s in selected]), np.array([members[s][2] for s in selected])
        freq_std, damping_std = np.array([own_std[s] for s in selected]).T
        ref_macs = [m["ref_mac"] for m in matches if m["mode"] == number and m["status"] == "merged"]
        modes.append({
            "mode": number, "freq_hz": frequencies.mean(), "freq_std_hz": std_of_mean(frequencies, freq_std),
            "freq_spread_hz": frequencies.std(ddof=1) if len(frequencies) > 1 else np.nan,
            "damping": dampings.mean(), "damping_std": std_of_mean(dampings, damping_std),
            "damping_spread": dampings.std(ddof=1) if len(frequencies) > 1 else np.nan,
            "n_setups": len(selected), "n_from_diagram": len(members) - len(selected),
            "setups": " ".join(setups[s].name for s in sorted(members)),
            "left_out": " ".join(setups[s].name for s in sorted(left_out)),
            "ref_mac": float(np.min(ref_macs)) if keys and len(setups) > 1 else np.nan,
            "mpc": float(modal_phase_collinearity(known[:, None])[0]) if known.size else np.nan,
            "n_nodes": len(per_node), "n_flagged": len(flags), "flag": flag,
        })
    mode_columns = ["mode", "freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std", "damping_spread",
                    "n_setups", "n_from_diagram", "setups", "left_out", "ref_mac", "mpc", "n_nodes", "n_flagged",
                    "flag"]
    shape_columns = ["mode", "node", "x", "y", "z", "x_im", "y_im", "z_im", "flag"]
    match_columns = ["mode", "setup", "setup_mode", "source", "status", "reason", "freq_hz", "damping", "ref_mac",
                     "ref_share", "scale"]
    return MergedModes(pd.DataFrame(modes, columns=mode_columns), pd.DataFrame(shape_rows, columns=shape_columns),
                       pd.DataFrame(matches, columns=match_columns), disagreements)
