"""Names of the vibration modes of a gear body (paper 000 §4, Table 4).

Paper 000 (Lin, Yao, Xie 2020) names the modes of its spiral bevel gears, found by an
ANSYS modal analysis, by looking at them: *torsional* (a repeated pair, "the end face
oscillates back and forth along the radial straight line passing through the axis"),
*folding* (pair, "V-shaped along the axis, regular polygon on the end face"),
*umbrella* (single, "teeth contracted into an umbrella shape along the large end in the
axial direction"), *circumferential* (single, "substantially no axial displacement,
circumferential vibration on the end face"), *bending* (pair, "regular wave pattern in
the axial direction, regular polygon on the end face") and *radial* (pair, "expands and
contracts along the radial direction, elliptical end face, basically no axial
vibration"). This module names a mode shape automatically, by the following documented
reading of those words.

The body is a solid of revolution (with teeth) whose axis is the ``z`` axis of the frame
of the points. A mode shape is given by its nodes ``p`` (m) and their displacements
``u`` (any scale), optionally with nodal mass weights ``w`` (kg, or any positive
measure; uniform when omitted).

Mass weights
------------
A mesh is graded (fine in the teeth, coarse in the blank), so uniform weights count the
finely meshed parts many times over: the shares become shares of *nodes*, not of the
body. The FE callers therefore weight each node by its mass, the **HRZ lumped mass**
(Hinton, Rock & Zienkiewicz 1976): the diagonal of the consistent mass matrix that the
eigen-solution used (``fe.elasticity.assemble``, ``rho u . v`` on 10-node tetrahedra),
scaled to the body's mass. It is positive at every node (unlike the row sums of the
quadratic tetrahedron's consistent mass, which are negative at the corners), takes the
curved geometry and the element sizes from the assembly itself, and
``sum_i w_i |u_i|^2`` is a quadrature of the kinetic energy ``int rho |u|^2 dV`` exact
for a rigid translation (``docs/assumptions.md``). :func:`node_shapes` returns the nodes,
shapes and these weights of a scikit-fem basis.

Features
--------
* **Components.** ``u`` is split into cylindrical components about ``z``: radial
  ``u_r``, tangential ``u_t`` (positive counter-clockwise about ``+z``) and axial
  ``u_z``. Their *shares* are ``s_c = sum_i w_i u_c,i^2 / sum_i w_i |u_i|^2``
  (``s_r + s_t + s_z = 1``): the fraction of the kinetic energy of the mode in each
  direction.
* **Rings.** The nodes off the axis are binned into rings: ``n_z`` axial bands
  (quantiles of ``z``; up to 3), and in each band up to 12 radial bins (quantiles of
  ``r`` within the band), sized so that a ring holds about ``4 kmax + 4`` nodes or
  more. A ring is used up to the harmonic ``K = min(kmax, (m - 1) // 4, floor(pi /
  gap))``, ``m`` its node count and ``gap`` the largest angle between neighbouring nodes
  (a half wave of the highest harmonic must not fit into a gap, and the fit has at least
  twice as many nodes as unknowns: well below the Nyquist limit of half the nodes per
  ring); rings with ``K < 1`` are not used.
* **Nodal diameters** ``n``. In each ring, each component is fitted (weighted least
  squares) by ``c_0 + sum_k Re(c_k exp(i k theta))``, ``k = 0 .. K``. The power of
  harmonic ``k`` (``c_0^2``, or ``|c_k|^2 / 2``: the mean square over the circle) is
  weighted by the ring's mass and summed over the rings and the three components;
  ``n`` is the harmonic of largest power and the *purity* is its fraction of the power
  of all harmonics ``0 .. kmax``. A gear with ``Z`` teeth couples the harmonics ``n``
  and ``Z - n``; keep ``kmax`` below ``Z / 2``.
* **Nodal circles.** The component with most power in harmonic ``n`` is followed along
  the radius in the axial band where it has most power: each ring's coefficient
  ``c_n`` is projected onto that of the ring of largest amplitude (a standing wave has
  one angular phase, so this is its signed amplitude). A nodal circle is counted each
  time this profile, ordered by radius, passes between values of opposite sign, each at
  least 10 % of its largest magnitude.
* **Axial reversal** (folding). The signed amplitude of the in-plane component (radial
  or tangential, whichever has more power in harmonic ``n``) is averaged over each
  axial band; with ``S_lo``, ``S_hi`` the averages of the lowest and highest bands,
  ``axial_reversal = -S_lo S_hi / max(S_lo^2, S_hi^2)`` is +1 when the two axial ends
  move in plane in anti-phase (the in-plane motion changes sign along the axis: the
  "V"), -1 when they move in phase, 0 when one end does not move in plane, and NaN
  when it cannot be told (a single axial band, or no in-plane motion in harmonic
  ``n``).

Names
-----
* ``n = 0``: the largest share names it: axial -> ``"umbrella"``, tangential ->
  ``"circumferential"``, radial -> ``"radial"`` (breathing).
* ``n = 1`` -> ``"torsional"``: the end face rocks about a diameter (our reading of
  "oscillates back and forth along the radial straight line passing through the axis").
* ``n >= 2``: ``s_z >= s_r + s_t`` (mostly axial) -> ``"bending"``; otherwise (mostly
  in plane) ``"folding"`` when ``axial_reversal > 0``, else ``"radial"``.

Repeated roots
--------------
A body of revolution has its ``n >= 1`` modes in pairs of equal frequency, the two
shapes turned by ``pi / (2 n)`` about the axis (a mode solver returns any orthogonal
combination of them). :func:`mode_families` groups two modes into a family when their
frequencies agree within a relative tolerance and they have the same ``n >= 1``;
:func:`classify_modes` classifies each family from the summed power of its members, so
both members get the same name. ``n = 0`` modes stay single.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = [
    "MODE_NAMES",
    "ModeType",
    "classify_mode",
    "classify_modes",
    "mode_families",
    "node_shapes",
    "vertex_shapes",
]

Array = NDArray[np.float64]

#: The names of paper 000's Table 4.
MODE_NAMES = ("torsional", "folding", "umbrella", "circumferential", "bending", "radial")
_COMPONENTS = ("radial", "tangential", "axial")
_MAX_BANDS = 3
_MAX_RADIAL = 12
_SIGNIFICANT = 0.1  # fraction of the largest ring amplitude that counts for a sign change


@dataclass(frozen=True)
class ModeType:
    """The named type of one vibration mode of a body of revolution.

    Attributes
    ----------
    name : str
        One of :data:`MODE_NAMES`: ``"torsional"``, ``"folding"``, ``"umbrella"``,
        ``"circumferential"``, ``"bending"``, ``"radial"``.
    nodal_diameters : int
        ``n``, the dominant circumferential harmonic (-).
    nodal_circles : int
        Sign changes of the dominant component's harmonic-``n`` amplitude along the
        radius (-).
    shares : dict of str to float
        ``{"radial", "tangential", "axial"}``: fractions (-) of the mass-weighted squared
        displacement in each cylindrical direction; they sum to 1.
    purity : float
        Fraction (-) of the circumferential-harmonic power in harmonic ``n``, in (0, 1].
    axial_reversal : float
        In [-1, 1]: +1 when the in-plane harmonic-``n`` motion of the two axial ends is
        in anti-phase, -1 in phase; NaN when it cannot be told (module docstring).
    family : int or None
        Index of the mode's family (a repeated pair or a single mode) in
        :func:`classify_modes`'s result; None from :func:`classify_mode`.
    """

    name: str
    nodal_diameters: int
    nodal_circles: int
    shares: dict[str, float]
    purity: float
    axial_reversal: float
    family: int | None = None


def classify_mode(
    points: ArrayLike,
    displacement: ArrayLike,
    weights: ArrayLike | None = None,
    *,
    kmax: int = 12,
) -> ModeType:
    """Name one mode shape of a body of revolution about ``z`` (module docstring).

    Parameters
    ----------
    points : array_like (n, 3)
        Node positions (m) in the body's frame (axis = ``z``).
    displacement : array_like (n, 3)
        The mode shape's nodal displacements (any scale; only ratios matter).
    weights : array_like (n,), optional
        Nodal mass weights (kg, or any non-negative measure); uniform if omitted.
    kmax : int
        Highest circumferential harmonic analysed (-).

    Returns
    -------
    ModeType
        With ``family=None``.

    Raises
    ------
    ReducerlabError
        A shape mismatch, a non-finite value, a zero displacement, points all on the
        axis, negative or all-zero weights, or too few points for the ring analysis.
    """
    p = _points(points)
    u = _array("displacement", displacement, (len(p), 3))
    if not np.any(u):
        raise ReducerlabError("classify_mode: displacement must not be zero everywhere")
    w = _weights(weights, len(p))
    return _classify(p, u[:, :, None], w, _kmax(kmax))


def classify_modes(
    points: ArrayLike,
    shapes: ArrayLike,
    frequencies: ArrayLike,
    weights: ArrayLike | None = None,
    pair_tol: float = 1e-2,
    *,
    kmax: int = 12,
) -> list[ModeType]:
    """Name the modes of a body of revolution, repeated pairs named alike.

    Each mode is classified alone to find its ``n``; :func:`mode_families` then groups
    the repeated pairs, and each family is classified again from the summed power of its
    members (their ring coefficients side by side), so both members of a pair get the
    same :class:`ModeType` (the same name, ``n``, shares, ...) and ``family`` index.

    Parameters
    ----------
    points : array_like (n, 3)
        Node positions (m), axis = ``z``.
    shapes : array_like (n, 3, modes)
        Nodal displacements of each mode (any scale).
    frequencies : array_like (modes,)
        Natural frequencies (Hz), finite and >= 0.
    weights : array_like (n,), optional
        Nodal mass weights (kg); uniform if omitted.
    pair_tol : float
        Relative frequency tolerance of a repeated pair (-), >= 0.
    kmax : int
        Highest circumferential harmonic analysed (-).

    Returns
    -------
    list of ModeType
        One per mode, in the order of ``shapes``; ``family`` indexes
        ``mode_families(frequencies, [m.nodal_diameters ...], pair_tol)``.

    Raises
    ------
    ReducerlabError
        Bad input (as :func:`classify_mode`; a mode of zero displacement is named by its
        index), or ``frequencies`` / ``pair_tol`` out of their rules.
    """
    p = _points(points)
    try:
        s = np.asarray(shapes, dtype=float)
    except (TypeError, ValueError):
        raise ReducerlabError("classify_modes: shapes must be an array of numbers") from None
    if s.ndim != 3 or s.shape[:2] != (len(p), 3) or s.shape[2] < 1:
        raise ReducerlabError(
            f"classify_modes: shapes must have shape (n, 3, modes) with n = {len(p)} "
            f"points, got {s.shape}"
        )
    s = _array("shapes", s, s.shape)
    f = _array("frequencies", frequencies, (s.shape[2],))
    if np.any(f < 0):
        raise ReducerlabError("classify_modes: frequencies must be >= 0 (Hz)")
    zero = [j for j in range(s.shape[2]) if not np.any(s[:, :, j])]
    if zero:
        raise ReducerlabError(
            f"classify_modes: shapes of mode(s) {zero} are zero everywhere (no displacement)"
        )
    w = _weights(weights, len(p))
    k = _kmax(kmax)
    lay = _layout(p, w, k)  # the rings and their fits: the same for every mode
    single = [_classify(p, s[:, :, j : j + 1], w, k, lay) for j in range(s.shape[2])]
    families = mode_families(f, [m.nodal_diameters for m in single], pair_tol)
    out: list[ModeType | None] = [None] * s.shape[2]
    for index, members in enumerate(families):
        joint = _classify(p, s[:, :, list(members)], w, k, lay) if len(members) > 1 else None
        for j in members:
            m = single[j] if joint is None else joint
            out[j] = dataclasses.replace(m, shares=dict(m.shares), family=index)
    return [m for m in out if m is not None]


def mode_families(
    frequencies: ArrayLike, nodal_diameters: Sequence[int], tol: float = 1e-2
) -> list[tuple[int, ...]]:
    """Group the repeated pairs of a body of revolution.

    Modes are taken in ascending frequency; a mode of ``n >= 1`` not yet grouped is
    paired with the next ungrouped mode of the same ``n`` whose frequency agrees within
    ``|f_j - f_i| <= tol max(f_i, f_j)``. A family has at most two members (the double
    roots of a body of revolution); ``n = 0`` modes stay single.

    Parameters
    ----------
    frequencies : array_like (modes,)
        Natural frequencies (Hz), finite and >= 0.
    nodal_diameters : sequence of int (modes,)
        ``n`` of each mode.
    tol : float
        Relative frequency tolerance (-), >= 0.

    Returns
    -------
    list of tuple of int
        Mode indices of each family (ascending frequency inside), the families in
        ascending frequency of their first member.
    """
    f = _array("frequencies", frequencies, (-1,))
    n = np.asarray(nodal_diameters)
    if n.shape != f.shape or (len(n) and not np.issubdtype(n.dtype, np.integer)):
        raise ReducerlabError(
            "mode_families: nodal_diameters must be integers, one per frequency "
            f"({len(f)}), got shape {n.shape}"
        )
    if np.any(f < 0):
        raise ReducerlabError("mode_families: frequencies must be >= 0 (Hz)")
    if isinstance(tol, bool) or not isinstance(tol, int | float) or not (tol >= 0):
        raise ReducerlabError(f"mode_families: tol (pair_tol) must be a number >= 0, got {tol!r}")
    if not math.isfinite(tol):
        raise ReducerlabError(f"mode_families: tol (pair_tol) must be finite, got {tol!r}")
    order = [int(i) for i in np.argsort(f, kind="stable")]
    taken: set[int] = set()
    families: list[tuple[int, ...]] = []
    for a, i in enumerate(order):
        if i in taken:
            continue
        taken.add(i)
        members = [i]
        if n[i] >= 1:
            for j in order[a + 1 :]:
                if abs(f[j] - f[i]) > tol * max(f[i], f[j]):
                    break
                if j not in taken and n[j] == n[i]:
                    taken.add(j)
                    members.append(j)
                    break
        families.append(tuple(members))
    return families


def vertex_shapes(basis: Any, shapes: ArrayLike) -> tuple[Array, Array]:
    """The vertex displacements of FE shapes of a vector scikit-fem basis.

    Parameters
    ----------
    basis : skfem.Basis
        A basis of ``ElementVector`` (e.g. from :func:`~reducerlab.fe.assemble`).
    shapes : array_like (dofs,) or (dofs, modes)
        Shapes in the basis' DOFs (e.g. :attr:`~reducerlab.fe.BodyModes.shapes`).

    Returns
    -------
    points : ndarray (vertices, 3)
        The mesh vertices (m).
    displacements : ndarray (vertices, 3, modes)
        Their displacements (the shapes' units).
    """
    dofs = np.asarray(basis.nodal_dofs)
    s = np.asarray(shapes, dtype=float)
    if s.ndim == 1:
        s = s[:, None]
    if dofs.ndim != 2 or dofs.shape[0] != 3:
        raise ReducerlabError("vertex_shapes: basis must be a 3-D vector basis (ElementVector)")
    if s.ndim != 2 or s.shape[0] != basis.N:
        raise ReducerlabError(
            f"vertex_shapes: shapes must have {basis.N} rows (the basis' DOFs), got {s.shape}"
        )
    points = np.asarray(basis.doflocs)[:, dofs[0]].T
    return points, np.transpose(s[dofs], (1, 0, 2))


def node_shapes(basis: Any, shapes: ArrayLike, mass: Any) -> tuple[Array, Array, Array]:
    """All nodes of a vector scikit-fem basis, the shapes there and their HRZ masses.

    The nodes are the vertices followed by the mid-edge nodes (10-node tetrahedra); the
    weight of a node is the diagonal entry of ``mass`` of its ``x`` DOF, scaled so that
    the weights sum to the body's mass (the HRZ lumped mass: module docstring).

    Parameters
    ----------
    basis : skfem.Basis
        A basis of ``ElementVector`` of a Lagrange element with DOFs at the vertices and
        at most one per edge (``ElementTetP1``, ``ElementTetP2``).
    shapes : array_like (dofs,) or (dofs, modes)
        Shapes in the basis' DOFs.
    mass : sparse matrix (dofs, dofs)
        The consistent mass matrix of ``basis`` (kg), e.g. from
        :func:`~reducerlab.fe.assemble`.

    Returns
    -------
    points : ndarray (nodes, 3)
        The node positions (m).
    displacements : ndarray (nodes, 3, modes)
        Their displacements (the shapes' units).
    weights : ndarray (nodes,)
        Node masses (kg), > 0, summing to ``e^T M e`` for a unit translation ``e``.
    """
    dofs = np.asarray(basis.nodal_dofs)
    if dofs.ndim != 2 or dofs.shape[0] != 3:
        raise ReducerlabError("node_shapes: basis must be a 3-D vector basis (ElementVector)")
    edges = np.asarray(basis.edge_dofs)
    if edges.size:
        if edges.ndim != 2 or edges.shape[0] != 3:
            raise ReducerlabError("node_shapes: at most one node per edge is supported")
        dofs = np.concatenate([dofs, edges], axis=1)
    other = (np.asarray(getattr(basis, name, [])).size for name in ("facet_dofs", "interior_dofs"))
    if any(other) or dofs.size != basis.N:
        raise ReducerlabError("node_shapes: the basis has DOFs off its vertices and edges")
    s = np.asarray(shapes, dtype=float)
    if s.ndim == 1:
        s = s[:, None]
    if s.ndim != 2 or s.shape[0] != basis.N:
        raise ReducerlabError(
            f"node_shapes: shapes must have {basis.N} rows (the basis' DOFs), got {s.shape}"
        )
    if getattr(mass, "shape", None) != (basis.N, basis.N):
        raise ReducerlabError(f"node_shapes: mass must be a ({basis.N}, {basis.N}) matrix")
    diag = np.asarray(mass.diagonal(), dtype=float)[dofs[0]]
    if not np.all(diag > 0):
        raise ReducerlabError("node_shapes: the mass matrix has a diagonal entry <= 0")
    one = np.zeros(basis.N)
    one[dofs[0]] = 1.0
    total = float(one @ (mass @ one))
    points = np.asarray(basis.doflocs)[:, dofs[0]].T
    return points, np.transpose(s[dofs], (1, 0, 2)), diag * (total / diag.sum())


# -- the analysis ------------------------------------------------------------------------


@dataclass(frozen=True)
class _Layout:
    """What the analysis of a mode takes from the points and weights alone: the polar
    coordinates, the off-axis nodes, the rings and each ring's weighted least-squares
    matrix (built once for all the modes of :func:`classify_modes`)."""

    r: Array
    theta: Array
    cos: Array
    sin: Array
    off: NDArray[np.bool_]
    rings: list[_Ring]
    fits: list[tuple[Array, Array]]


def _layout(p: Array, w: Array, kmax: int) -> _Layout:
    """:class:`_Layout` of the points ``p`` with weights ``w``."""
    r = np.hypot(p[:, 0], p[:, 1])
    theta = np.arctan2(p[:, 1], p[:, 0])
    off = r > 1e-9 * r.max()  # nodes on the axis have no angle
    rings = _rings(r[off], p[off, 2], theta[off], w[off], kmax)
    fits = [_fit(theta[off][g.index], w[off][g.index], g.kmax) for g in rings]
    return _Layout(r, theta, np.cos(theta), np.sin(theta), off, rings, fits)


def _classify(p: Array, u: Array, w: Array, kmax: int, lay: _Layout | None = None) -> ModeType:
    """Classify the family ``u`` (n, 3, members) at points ``p`` with weights ``w``
    (``lay``: their :class:`_Layout`, built here when omitted)."""
    lay = _layout(p, w, kmax) if lay is None else lay
    r, theta, c, s = lay.r, lay.theta, lay.cos, lay.sin
    cyl = np.stack(
        [
            c[:, None] * u[:, 0] + s[:, None] * u[:, 1],
            -s[:, None] * u[:, 0] + c[:, None] * u[:, 1],
            u[:, 2],
        ],
        axis=1,
    )  # (n, 3, members): u_r, u_t, u_z
    energy = np.einsum("i,icm->c", w, cyl**2)
    if not energy.sum() > 0:
        raise ReducerlabError(
            "classify_mode: displacement is zero at every node of non-zero weight"
        )
    shares = energy / energy.sum()

    off = lay.off
    r, theta, values = r[off], theta[off], cyl[off]
    rings = lay.rings
    if not rings:
        raise ReducerlabError(
            f"classify_mode: points must cover the circumference: no ring of >= 5 nodes "
            f"(of {int(off.sum())} off the axis) spans 2 pi without a gap over pi"
        )
    bands = np.array([g.band for g in rings])
    weight = np.array([g.weight for g in rings])
    kring = np.array([g.kmax for g in rings])
    ring_r = np.array([r[g.index].mean() for g in rings])
    coef = np.zeros((len(rings), kmax + 1, 3, u.shape[2]), dtype=complex)
    for a, g in enumerate(rings):
        i = g.index
        coef[a, : g.kmax + 1] = _fourier(lay.fits[a], values[i], g.kmax)
    power = np.abs(coef) ** 2
    power[:, 1:] *= 0.5
    total = np.einsum("a,akcm->kc", weight, power)  # (harmonic, component)
    per_k = total.sum(axis=1)
    if not per_k.sum() > 0:
        raise ReducerlabError(
            "classify_mode: displacement has no circumferential content at the rings "
            "(zero off the axis)"
        )
    n = int(np.argmax(per_k))
    purity = float(per_k[n] / per_k.sum())

    # nodal circles: the dominant component along the radius, in its strongest band
    comp = int(np.argmax(total[n]))
    usable = kring >= n
    band_power = {
        b: float(np.sum(weight[m] * np.sum(power[m, n, comp], axis=-1)))
        for b in np.unique(bands[usable])
        for m in [np.flatnonzero(usable & (bands == b))]
    }
    best = max(band_power, key=lambda b: band_power[b])
    in_band = np.flatnonzero(usable & (bands == best))
    in_band = in_band[np.argsort(ring_r[in_band])]
    circles = _sign_changes(_signed(coef[in_band, n, comp]))

    # axial reversal: the in-plane component's band averages at the two axial ends
    plane = int(np.argmax(total[n, :2]))
    reversal = math.nan
    ends = np.unique(bands[usable])
    if len(ends) >= 2 and total[n, plane] > 0:
        amp = _signed(coef[usable, n, plane])
        wu, bu = weight[usable], bands[usable]
        lo, hi = (
            float(np.sum(wu[bu == b] * amp[bu == b]) / np.sum(wu[bu == b]))
            for b in (ends[0], ends[-1])
        )
        scale = max(lo * lo, hi * hi)
        if scale > 0:
            reversal = -lo * hi / scale

    sr, st, sz = (float(x) for x in shares)
    if n == 0:
        name = {0: "radial", 1: "circumferential", 2: "umbrella"}[int(np.argmax(shares))]
    elif n == 1:
        name = "torsional"
    elif sz >= sr + st:
        name = "bending"
    else:
        name = "folding" if reversal > 0 else "radial"
    return ModeType(
        name,
        n,
        circles,
        dict(zip(_COMPONENTS, (sr, st, sz), strict=True)),
        purity,
        float(reversal),
    )


@dataclass(frozen=True)
class _Ring:
    index: NDArray[np.int64]
    band: int
    weight: float
    kmax: int


def _bins(x: Array, count: int) -> NDArray[np.int64]:
    """Quantile bin numbers of ``x`` (ties kept together; empty bins possible)."""
    if count <= 1:
        return np.zeros(len(x), dtype=np.int64)
    edges = np.unique(np.quantile(x, np.linspace(0, 1, count + 1)[1:-1]))
    return np.searchsorted(edges, x, side="right").astype(np.int64)


def _rings(r: Array, z: Array, theta: Array, w: Array, kmax: int) -> list[_Ring]:
    """The rings of the module docstring (indices into the off-axis nodes)."""
    n = len(r)
    need = 4 * kmax + 4
    scale = max(float(r.max()), float(np.ptp(z)))
    nz = _MAX_BANDS if np.ptp(z) > 1e-9 * scale else 1
    nz = max(1, min(nz, n // (2 * need)))
    rings: list[_Ring] = []
    zbin = _bins(z, nz)
    for band, zb in enumerate(np.unique(zbin)):
        in_band = np.flatnonzero(zbin == zb)
        nr = max(1, min(_MAX_RADIAL, len(in_band) // need))
        rbin = _bins(r[in_band], nr)
        for rb in np.unique(rbin):
            index = in_band[rbin == rb]
            m = len(index)
            if m < 5:
                continue
            t = np.sort(theta[index])
            gap = float(np.max(np.diff(np.concatenate([t, [t[0] + 2 * math.pi]]))))
            k = min(kmax, (m - 1) // 4, int(math.pi / gap) if gap > 0 else 0)
            if k >= 1 and np.sum(w[index]) > 0:
                rings.append(_Ring(index, band, float(np.sum(w[index])), k))
    return rings


def _fit(theta: Array, w: Array, k: int) -> tuple[Array, Array]:
    """A ring's weighted least-squares solution operator: the pseudo-inverse of
    ``sqrt(w) [1, cos(j theta), sin(j theta)]`` (``j = 1..k``; full column rank: a ring
    has at least ``4 k + 1`` nodes and no gap of a half wave), and ``sqrt(w)``
    (column). Made once per ring for all the modes (one SVD, as ``numpy.linalg.lstsq``
    makes for each right-hand side)."""
    cols = [np.ones_like(theta)]
    for j in range(1, k + 1):
        cols += [np.cos(j * theta), np.sin(j * theta)]
    A = np.stack(cols, axis=1)
    sw = np.sqrt(w)[:, None]
    return np.linalg.pinv(A * sw), sw


def _fourier(fit: tuple[Array, Array], values: Array, k: int) -> NDArray[np.complex128]:
    """Weighted least-squares harmonics ``c_0 .. c_k`` (k+1, 3, members) of a ring from
    its :func:`_fit` and the values at its nodes."""
    pinv, sw = fit
    rhs = values.reshape(len(sw), -1)
    x = (pinv @ (rhs * sw)).reshape(2 * k + 1, *values.shape[1:])
    out = np.empty((k + 1, *values.shape[1:]), dtype=complex)
    out[0] = x[0]
    out[1:] = x[1::2] - 1j * x[2::2]
    return out


def _signed(v: NDArray[np.complex128]) -> Array:
    """Signed amplitudes of the rows of ``v`` (rings, members) along the largest row."""
    norms = np.linalg.norm(v, axis=1)
    ref = v[int(np.argmax(norms))]
    size = float(np.linalg.norm(ref))
    if size == 0:
        return np.zeros(len(v))
    return np.real(v @ np.conj(ref)) / size


def _sign_changes(profile: Array) -> int:
    """Sign changes between values of at least ``_SIGNIFICANT`` of the largest."""
    if not len(profile):
        return 0
    big = np.abs(profile) >= _SIGNIFICANT * np.max(np.abs(profile))
    signs = np.sign(profile[big & (profile != 0)])
    return int(np.count_nonzero(signs[1:] != signs[:-1]))


# -- input checks ------------------------------------------------------------------------


def _array(name: str, value: ArrayLike, shape: tuple[int, ...]) -> Array:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ReducerlabError(f"{name} must be an array of numbers") from None
    if a.ndim != len(shape) or any(s not in (-1, t) for s, t in zip(shape, a.shape, strict=True)):
        want = "(" + ", ".join("any" if s == -1 else str(s) for s in shape) + ")"
        raise ReducerlabError(f"{name} must have shape {want}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ReducerlabError(f"{name} must be finite (no NaN or inf)")
    return a


def _points(points: ArrayLike) -> Array:
    p = _array("points", points, (-1, 3))
    if len(p) < 5:
        raise ReducerlabError(f"points must hold at least 5 nodes, got {len(p)}")
    r = np.hypot(p[:, 0], p[:, 1])
    if not r.max() > 1e-9 * float(np.abs(p).max()):
        raise ReducerlabError(
            "points must not all lie on the axis (x = y = 0): the mode's type is read "
            "around the z axis"
        )
    return p


def _weights(weights: ArrayLike | None, n: int) -> Array:
    if weights is None:
        return np.ones(n)
    w = _array("weights", weights, (n,))
    if np.any(w < 0) or not w.sum() > 0:
        raise ReducerlabError("weights must be >= 0 and not all zero")
    return w


def _kmax(kmax: int) -> int:
    if isinstance(kmax, bool) or not isinstance(kmax, int | np.integer) or kmax < 1:
        raise ReducerlabError(f"kmax must be an integer >= 1, got {kmax!r}")
    return int(kmax)
