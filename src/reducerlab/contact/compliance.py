"""Tooth bending compliance from finite-element influence coefficients.

The compliance of a loaded tooth contact splits into a *local* part, the half-space
deformation near each loaded point (``contact.halfspace``: Boussinesq, exact on the
fine contact grid), and a *global* part: bending, shear, fillet and rim deformation of
the teeth, smooth over the flank. The global part comes from a finite-element model of
a few teeth (quadratic tetrahedra, ``fe.gear_mesh`` and ``fe.elasticity``):

1. A grid of ``n_u x n_v`` load points on the flank of each of the teeth ``-1, 0, 1``.
   At each, a unit normal force spread as a smooth bump ``(1 - r^2/a^2)^2`` over the
   flank (radius ``a``, a few element sizes, so that the mesh resolves it).
2. One factorisation of the stiffness matrix (base of the rim and the sector's end walls
   held), all loads at once; the influence coefficient ``K_FE[k, l]`` is the
   work-conjugate normal displacement of bump ``k`` under bump ``l`` (symmetric):
   ``K_FE = F^T K^-1 F = Y^T Y`` with ``Y = L^-1 P F``, the forward substitution of the
   Cholesky factor ``P K P^T = L L^T`` alone (``fe.elasticity.pardiso_gram``).
3. The finite-element response still holds the local half-space deformation of the
   bumps, which the contact grid adds exactly: it is removed by subtracting, for two
   bumps on the same flank, their half-space interaction
   ``(1 - nu^2) / (pi E a) I(d / a)`` with
   ``I(s) = int_0^inf phi(k)^2 J0(k s) dk``, ``phi(k) = 48 J3(k) / k^3`` (the Hankel
   transform of the unit bump; ``I(s) -> 1/s`` far away). This is the decomposition of
   Vijayakar (Int. J. Numer. Meth. Eng. 31, 1991, combined surface integral and finite
   element method), with the surface integral on the contact grid.
4. Between the load points the global compliance is interpolated bilinearly in the
   flank parameters; beyond the outermost load points (which sit one bump radius inside
   the flank edges) it is extrapolated linearly.

The result for a gear is a :class:`ToothCompliance`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..fe.elasticity import STEEL, Material
from ..kinematics.rotations import rot_z
from ..threads import with_compute_threads

__all__ = [
    "FILLET_SIZE",
    "FacetQuadrature",
    "FacetQuadratureError",
    "ToothCompliance",
    "bump_interaction",
    "compliance_estimate",
    "extend_teeth",
    "facet_quadrature",
    "fe_tooth_compliance",
    "fillet_mesh_size",
    "flank_influence",
    "load_nodes",
    "tooth_sectors",
]

Array = NDArray[np.float64]
Stage = Callable[[str], None]

#: teeth modelled around the loaded one (tooth pairs -1, 0, 1 of the contact analysis)
TEETH = (-1, 0, 1)


@lru_cache(maxsize=1)
def _interaction_table() -> tuple[Array, Array]:
    """``I(s)`` on ``0 <= s <= 20`` (dimensionless, unit bump radius), by Simpson's rule
    on ``0 <= k <= 200`` (``phi(k)^2 <= 2e-9`` there; the step resolves ``J0(20 k)``)."""
    from scipy.integrate import simpson
    from scipy.special import j0, jv

    k = np.linspace(0.0, 200.0, 20001)
    with np.errstate(all="ignore"):
        phi = np.where(k < 1e-3, 1.0 - k * k / 16.0, 48.0 * jv(3, k) / k**3)
    s = np.linspace(0.0, S_MAX, 401)
    out = np.array([simpson(phi**2 * j0(k * si), x=k) for si in s])
    return s, out


#: beyond this distance (in bump radii) ``I(s) = 1/s`` to 3e-4 (the bumps' second
#: moments add ``1/(8 s^3)``)
S_MAX = 20.0


def bump_interaction(distance: Array, radius: float) -> Array:
    """``I(d/a) / a`` (1/m): the half-space interaction of two unit bumps of radius
    ``a`` whose centres are ``d`` apart; times ``(1 - nu^2)/(pi E)`` it is the
    work-conjugate displacement (m/N). ``I(s) = 1/s`` beyond ``S_MAX``."""
    s_tab, i_tab = _interaction_table()
    s = np.asarray(distance, float) / radius
    far = s > s_tab[-1]
    out = np.interp(np.where(far, 0.0, s), s_tab, i_tab)
    return np.where(far, 1.0 / np.where(far, s, 1.0), out) / radius


@dataclass(frozen=True)
class ToothCompliance:
    """Global (bending) compliance of one gear's teeth on a grid of load points.

    Attributes
    ----------
    u_nodes, v_nodes : ndarray
        Flank parameters of the load grid (``n_u``, ``n_v``).
    teeth : tuple of int
        Tooth indices of the blocks (``-1, 0, 1``).
    matrix : ndarray, shape (T L, T L)
        Influence coefficients (m/N) between the ``L = n_u n_v`` load points of the
        ``T`` teeth, local half-space part removed; order: tooth, ``u``, ``v``.
    dofs : int
        Size of the finite-element model.
    radius : float
        Bump radius ``a`` (m).
    fillet : contact.rootstress.FilletInfluence, optional
        Stress influence coefficients of the same load bumps at the root fillets of the
        teeth (built on request, ``root_stress=True``; None otherwise).
    """

    u_nodes: Array
    v_nodes: Array
    teeth: tuple[int, ...]
    matrix: Array
    dofs: int
    radius: float
    fillet: Any = None

    def stencil(self, tooth: Array, u: Array, v: Array) -> tuple[NDArray[np.int64], Array]:
        """Bilinear interpolation of points ``(u, v)`` on teeth ``tooth`` from the load
        points: the columns (n, 4) into ``matrix`` and their weights (n, 4)."""
        tooth = np.asarray(tooth, int)
        nu, nv = len(self.u_nodes), len(self.v_nodes)
        L = nu * nv
        iu, wu = _linear(self.u_nodes, np.asarray(u, float))
        iv, wv = _linear(self.v_nodes, np.asarray(v, float))
        try:
            t = np.array([self.teeth.index(int(k)) for k in tooth], dtype=int)
        except ValueError:
            raise ReducerlabError(
                f"compliance: tooth pairs must be among {self.teeth}; got {sorted(set(tooth))}"
            ) from None
        cols = np.stack([t * L + (iu + a) * nv + (iv + b) for a in (0, 1) for b in (0, 1)], axis=1)
        w = np.stack([wu[:, a] * wv[:, b] for a in (0, 1) for b in (0, 1)], axis=1)
        return cols.astype(np.int64), w


#: tooth pairs two pitches apart are coupled through the finite-element model's outer
#: teeth ``(-1, +1)``; beyond, :func:`extend_teeth` takes no coupling
COUPLED_PITCHES = 2


def extend_teeth(comp: ToothCompliance, teeth: Sequence[int]) -> ToothCompliance:
    """The compliance of any set of tooth pairs from one of teeth ``-1, 0, 1``, by the
    gear's cyclic symmetry (issue 30).

    In a whole gear the influence block between teeth ``i`` and ``j`` depends on
    ``d = j - i`` alone (tooth ``i`` turned onto tooth 0 carries tooth ``j`` onto tooth
    ``d``): the compliance of any tooth set is block-Toeplitz,
    ``K_ij = B(j - i)``, ``B(-d) = B(d)^T`` (Maxwell). From the three-tooth model:
    ``B(0)`` is tooth 0's own block (the middle of the finite-element sector, farthest
    from its cut faces); ``B(1) = (K_{0,1} + K_{-1,0}) / 2`` (the two neighbour blocks
    that cyclic symmetry makes equal, the sector's ends make differ slightly);
    ``B(2) = K_{-1,1}``; ``B(d) = 0`` for ``|d| > COUPLED_PITCHES`` (a tooth's load
    bends the rim under it and its neighbours; the finite-element rim is held at its
    bore or outer surface, so the coupling decays over a few pitches and a load two
    pitches away is already small, ``benchmarks/khv_sharing.py`` measures it against a
    seven-tooth model). Blocks between teeth the model has (``-1, 0, 1``) stay its own,
    so a set within them returns ``comp`` unchanged.

    Parameters
    ----------
    comp : ToothCompliance
        With teeth ``(-1, 0, 1)``.
    teeth : sequence of int
        The tooth pairs wanted (distinct).

    Returns
    -------
    ToothCompliance
        Teeth ``tuple(sorted(teeth))``; the fillet stress influence is dropped when the
        set goes beyond ``comp.teeth`` (it has the modelled teeth only).

    Raises
    ------
    ReducerlabError
        ``comp`` without teeth ``-1, 0, 1``, or an empty or repeated tooth set.
    """
    if tuple(comp.teeth) != TEETH:
        raise ReducerlabError(f"compliance: needs teeth {TEETH} to extend; has {comp.teeth}")
    try:
        want = [int(k) for k in teeth]
    except (TypeError, ValueError):
        raise ReducerlabError(f"teeth: must be integers; got {teeth!r}") from None
    if not want or len(set(want)) != len(want) or any(isinstance(k, bool) for k in teeth):
        raise ReducerlabError(f"teeth: must be distinct integers, at least one; got {teeth!r}")
    want = sorted(want)
    if set(want) <= set(TEETH):
        return comp
    L = len(comp.u_nodes) * len(comp.v_nodes)

    def block(i: int, j: int) -> Array:
        a, b = TEETH.index(i), TEETH.index(j)
        return comp.matrix[a * L : (a + 1) * L, b * L : (b + 1) * L]

    toeplitz = {0: block(0, 0), 1: 0.5 * (block(0, 1) + block(-1, 0)), 2: block(-1, 1)}
    out = np.zeros((len(want) * L, len(want) * L))
    for a, i in enumerate(want):
        for b, j in enumerate(want):
            d = j - i
            if i in TEETH and j in TEETH:
                B = block(i, j)
            elif abs(d) > COUPLED_PITCHES:
                continue
            else:
                B = toeplitz[d] if d >= 0 else toeplitz[-d].T
            out[a * L : (a + 1) * L, b * L : (b + 1) * L] = B
    return ToothCompliance(comp.u_nodes, comp.v_nodes, tuple(want), out, comp.dofs, comp.radius)


def _linear(nodes: Array, x: Array) -> tuple[NDArray[np.int64], Array]:
    """Cell index and the two linear weights (extrapolating beyond the ends)."""
    i = np.clip(np.searchsorted(nodes, x) - 1, 0, len(nodes) - 2)
    t = (x - nodes[i]) / (nodes[i + 1] - nodes[i])
    return i, np.stack([1.0 - t, t], axis=1)


def _sizes(m_n: float, tooth_size: float | None, body_size: float | None) -> tuple[float, float]:
    ts = 0.3 * m_n if tooth_size is None else float(tooth_size)
    bs = 1.0 * m_n if body_size is None else float(body_size)
    return ts, max(bs, ts)


#: Default element size of a bevel tooth model's root band (``fe.gear_mesh.FILLET_BAND``)
#: with ``root_stress``, in normal modules: the fillet stress of the nutation drive's
#: external gear is converged there to 1.7 % (its internal gear's is not: a root without
#: a fillet radius; docs/contact.md, "Tooth-root stress")
FILLET_SIZE = 0.2


def fillet_mesh_size(
    tooth_size: float, root_stress: bool, fillet_size: float | None, module: float
) -> float | None:
    """The root-band element size (m) of a bevel tooth model (``fe.gear_mesh.
    FILLET_BAND``): ``fillet_size`` when given (a length ``> 0``, at most the tooth size,
    equal to it: no refinement; with ``root_stress`` only); else ``FILLET_SIZE m_n``
    with ``root_stress`` (none where the tooth size is finer) and none without it.

    Raises
    ------
    ReducerlabError
        A ``fillet_size`` that is not a length ``> 0`` or exceeds the tooth size, or one
        given without ``root_stress``.
    """
    if fillet_size is None:
        fs = FILLET_SIZE * module
        return fs if root_stress and fs < tooth_size else None
    if (
        isinstance(fillet_size, bool)
        or not isinstance(fillet_size, int | float)
        or not (math.isfinite(fillet_size) and fillet_size > 0)
    ):
        raise ReducerlabError(f"fillet_size: must be a length > 0 (m); got {fillet_size!r}")
    if fillet_size > tooth_size:
        raise ReducerlabError(
            f"fillet_size: must be at most the tooth element size {tooth_size!r} m; "
            f"got {fillet_size!r}"
        )
    if not root_stress:
        raise ReducerlabError("fillet_size: refines the root fillets for root_stress=True only")
    return float(fillet_size)


def compliance_estimate(
    pair, tooth_size: float | None = None, body_size: float | None = None,
    grid: tuple[int, int] = (6, 9), rim: float | None = None, concurrent: bool = False,
    root_stress: bool = False, fillet_size: float | None = None,
) -> Any:  # fmt: skip
    """The :class:`~reducerlab.budget.Estimate` of both gears' tooth-compliance models
    of ``pair`` (five tooth sectors each, and the dense loads and responses of the
    flank loads), from the element sizes before any meshing; the larger of the two, or
    with ``concurrent`` (both models built at once, in two processes) their sum.
    ``root_stress``: with the displacements of the loads too (twice the dense
    columns); ``fillet_size``: the root band refined (:func:`fillet_mesh_size`)."""
    import dataclasses

    from ..fe.gear_mesh import BlankFeatures, MeshSizes, mesh_estimate

    worst = None
    total = 0.0
    for flank in (pair.flank_a, pair.flank_b):
        crown, gear = flank.crown, flank.gear
        m_n = crown.profile.module
        ts, bs = _sizes(m_n, tooth_size, body_size)
        fs = fillet_mesh_size(ts, root_stress, fillet_size, m_n)
        est = mesh_estimate(
            crown, gear, 2.0 * m_n if rim is None else rim, BlankFeatures(),
            MeshSizes(ts, bs, fs),
            what=f"contact: the tooth compliance of the {gear.kind} gear",
            control="the tooth element size (--tooth-size, tooth_size=)", sectors=5,
            dense_columns=len(TEETH) * grid[0] * grid[1] * (2 if root_stress else 1),
        )  # fmt: skip
        total += est.memory
        if worst is None or est.memory > worst.memory:
            worst = est
    if concurrent:
        what = "contact: the tooth compliance of both gears at once (two processes)"
        return dataclasses.replace(worst, what=what, memory=total)
    return worst


@with_compute_threads
def fe_tooth_compliance(
    flank,
    *,
    material: Material = STEEL,
    grid: tuple[int, int] = (6, 9),
    tooth_size: float | None = None,
    body_size: float | None = None,
    rim: float | None = None,
    stage: Stage | None = None,
    root_stress: bool = False,
    fillet_size: float | None = None,
    _legacy: bool = False,
) -> ToothCompliance:
    """Finite-element tooth compliance of a crown-generated bevel gear's flank.

    Parameters
    ----------
    flank : contact.flanks.BevelFlank
        The loaded flank (its gear, crown gear and flank side).
    material : Material
    grid : (int, int)
        Load points along the profile and along the face on each tooth.
    tooth_size, body_size : float, optional
        Element sizes (m) in the teeth and in the rim; default ``0.3 m_n`` and ``m_n``.
    rim : float, optional
        Rim thickness below the root cone (m); its base is held. Default ``2 m_n``.
    stage : callable, optional
        ``stage(text)`` at each step (progress display).
    root_stress : bool
        Also the stress influence of every load bump at the root-fillet nodes of the
        three teeth (``contact.rootstress``; :func:`_bevel_fillet`; one backward
        substitution more and about ``24 dofs x loads`` bytes more at the peak).
    fillet_size : float, optional
        Element size (m) in the root band (``fe.gear_mesh.FILLET_BAND``), at most the
        tooth size (equal: no refinement), with ``root_stress`` only; default
        ``FILLET_SIZE m_n`` with ``root_stress`` (:func:`fillet_mesh_size`), where the
        external nutation gear's fillet stress is converged to 1.7 %, at 1.8x the DOFs of
        the plain model (docs/contact.md).
    _legacy : bool
        Private: the finite-element path as before issue 28 (:func:`flank_influence`).
    """
    from ..fe.gear_mesh import MeshSizes, mesh_gear
    from ..geometry.solid import cone_coordinates

    say = stage or (lambda _s: None)
    crown, gear = flank.crown, flank.gear
    m_n = crown.profile.module
    ts, bs = _sizes(m_n, tooth_size, body_size)
    n_u, n_v = (int(g) for g in grid)
    if n_u < 2 or n_v < 2:
        raise ReducerlabError(f"grid: needs at least 2 x 2 load points; got {grid!r}")
    if not isinstance(root_stress, bool):
        raise ReducerlabError(f"root_stress: must be True or False; got {root_stress!r}")
    fs = fillet_mesh_size(ts, root_stress, fillet_size, m_n)
    a = 2.0 * ts  # bump radius: two tooth elements
    say("meshing five tooth sectors")
    sizes = MeshSizes(ts, bs, fs)
    mesh = mesh_gear(crown, gear, rim=rim, sizes=sizes, sectors=tooth_sectors(flank))
    # load grid, inset by the bump radius from the flank's edges (arc length)
    u_nodes, v_nodes = load_nodes(flank, a, n_u, n_v)
    uu, vv = np.meshgrid(u_nodes, v_nodes, indexing="ij")
    P0, N0 = flank.evaluate(uu.ravel(), vv.ravel())
    skm = mesh.skfem()
    angles = [-2 * math.pi * k / gear.teeth for k in TEETH]
    fillet = _bevel_fillet(flank, mesh.blank, angles) if root_stress else None
    out = flank_influence(
        skm, lambda basis: _held_dofs(basis, mesh, cone_coordinates), P0, N0, angles,
        a, material, stage=say, name=f"{gear.kind} gear (z = {gear.teeth})", fillet=fillet,
        _legacy=_legacy,
    )  # fmt: skip
    inf = fillet.influence(out[2]) if root_stress else None
    return ToothCompliance(u_nodes, v_nodes, TEETH, out[0], out[1], a, inf)


def tooth_sectors(flank) -> range:
    """The five tooth sectors of :func:`~reducerlab.fe.gear_mesh.mesh_gear` that hold the
    modelled teeth ``-1, 0, 1`` of ``flank`` (a ``contact.flanks.BevelFlank``) whole.

    ``mesh_gear``'s sector ``k`` holds the tooth space ``k`` of its solid (walls through
    the middle of the teeth either side), and its tooth ``j`` (tooth 0 turned by ``-j``
    pitches) lies between spaces ``-j`` and ``1 - j``. The flank's tooth 0 is the
    solid's tooth ``-t``, ``t`` the crown tooth that generates the loaded flank on the
    solid's tooth 0 (``geometry.bevel_surface.tooth_flanks``): 0 for both flanks of the
    external gear and for flank -1 of the internal gear, 1 for flank +1 of the internal
    gear. Sectors ``t - 2 ... t + 2`` put the modelled teeth ``1, 0, -1`` at ``-0.5,
    0.5, 1.5`` pitches from the middle of the five (a tooth space: five sectors hold four
    whole teeth between their walls), the centre of tooth 1 two pitches and that of
    tooth -1 one pitch from the nearer wall (``tests/test_tooth_sector.py``).
    Before, every gear had sectors ``-2 ... 2``: a wall through the middle of the
    internal gear's tooth -1 under flank +1."""
    from ..geometry.bevel_surface import tooth_flanks

    (fa, ta), (_, tb) = tooth_flanks(flank.gear)
    t = round(ta if flank.flank == fa else tb)
    return range(t - 2, t + 3)


class _bevel_fillet:
    """The root fillets of a crown-generated bevel gear's tooth model (cone coordinates
    ``(L, h, psi)``, ``geometry.solid.cone_coordinates``).

    A boundary facet is in the root region when its corners lie between the bottom of
    the tooth spaces (the deepest boundary point of the model in each slice along the
    face) and the root-side edge of the active flanks of both flanks that bound a tooth
    space (0.25 m_n above the bottom where the flank runs into it: the internal gears of
    the nutation drive), above the middle of the rim, and not all on the toe or heel
    cone. The space of the
    loaded flank's tooth 0 lies between the lower edge of the loaded flank
    (azimuth ``psi_A(L)``) and that of the opposite flank of the same crown tooth
    (``psi_B(L)``); every space is that one turned by whole pitches. A facet in a space
    belongs to the tooth on its side of the space's mid azimuth: side +1 (the loaded
    flank's fillet) on the ``psi_A`` side, -1 on the ``psi_B`` side; the tooth block is
    found from the tooth's rotation (``angles``)."""

    def __init__(self, flank, blank, angles: Sequence[float]) -> None:
        from ..geometry.solid import cone_coordinates
        from .flanks import BevelFlank

        gear = flank.gear
        self.delta = gear.cone_angle
        self.pitch = 2 * math.pi / gear.teeth
        self.sign = 1.0 if gear.kind == "external" else -1.0
        self.blank = blank
        self.blocks = {round(t / self.pitch): k for t, k in zip(angles, TEETH, strict=True)}
        self.module = flank.crown.profile.module
        other = BevelFlank(flank.crown, gear, -flank.flank, flank.addendum)
        v = np.linspace(0.0, 1.0, 61)
        edges, u_root = [], []
        for f in (flank, other):
            # the end of the active flank nearer the root cone (internal gears: u = 1)
            ends = [(u, cone_coordinates(f.evaluate(np.full_like(v, u), v)[0], self.delta))
                    for u in f.u_range]  # fmt: skip
            u, (L, h, psi) = min(ends, key=lambda e: abs(float(np.median(e[1][1])) - blank.root))
            o = np.argsort(L)
            edges.append((L[o], h[o], np.unwrap(psi[o])))
            u_root.append(u)
        (self.L_a, self.h_a, self.psi_a), (self.L_b, self.h_b, self.psi_b) = edges
        self._cone = cone_coordinates
        # do the two edges bound a tooth space (the loaded flank's normal, out of the
        # material, turns toward the other edge) or the tooth itself?
        u0 = 0.9 * u_root[0] + 0.1 * (sum(flank.u_range) - u_root[0])
        P, N = flank.evaluate(np.array([u0]), np.array([0.5]))
        L0, _, psi0 = cone_coordinates(P, self.delta)
        e_psi = np.array([-math.sin(psi0[0]), math.cos(psi0[0]), 0.0])
        toward = np.angle(np.exp(1j * (np.interp(L0, self.L_b, self.psi_b) - psi0)))[0]
        self.space_between = bool(np.sign(N[0] @ e_psi) == np.sign(toward))

    def _edges(self, L: Array) -> tuple[Array, Array, Array]:
        """Mid azimuth of the loaded flank's tooth space, offset of the loaded flank's
        edge from it (rad) and the height of the root region's upper bound (m) at cone
        distances ``L``."""
        pa = np.interp(L, self.L_a, self.psi_a)
        pb = np.interp(L, self.L_b, self.psi_b)
        pb = pa + np.angle(np.exp(1j * (pb - pa)))
        h = np.interp(L, self.L_a, self.h_a), np.interp(L, self.L_b, self.h_b)
        top = np.maximum(*h) if self.sign > 0 else np.minimum(*h)
        mid = 0.5 * (pa + pb)
        if not self.space_between:  # the edges bound tooth 0: its space half a pitch on
            mid = mid + np.sign(pa - pb) * 0.5 * self.pitch
        return mid, pa - mid, top

    def _place(self, L: Array, psi: Array) -> tuple[Array, Array, Array]:
        """Tooth rotation (in pitches), side and centre-line azimuth offset of points."""
        mid, half, _ = self._edges(L)
        d = np.angle(np.exp(1j * (psi - mid)))
        j = np.rint(d / self.pitch)
        e = d - j * self.pitch
        a_side = np.sign(half)
        side = np.where(np.sign(e) == a_side, 1, -1)
        # side -1: the tooth across the space, one pitch on the psi_B side
        turn = np.where(side == 1, j, j - a_side)
        return turn, side, mid

    def __call__(self, basis) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
        skm = basis.mesh
        bl = self.blank
        bf = skm.boundary_facets()
        P = skm.p[:, skm.facets[:, bf]]  # (3, 3 corners, facets)
        L, h, psi = self._cone(np.moveaxis(P, 0, -1), self.delta)  # (3, facets)
        _, _, top = self._edges(L)
        tol = 1e-6 * float(np.max(np.abs(skm.p)))
        floor = bl.root + 0.5 * (bl.body - bl.root)
        ends = np.all(np.abs(L - bl.front) < tol, axis=0)
        ends |= np.all(np.abs(L - bl.back) < tol, axis=0)
        # the open sector's end walls: planes through the axis
        nrm = np.cross((P[:, 1] - P[:, 0]).T, (P[:, 2] - P[:, 0]).T)
        nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
        c = P.mean(axis=1).T
        walls = (np.abs(np.einsum("ij,ij->i", nrm, c)) < 1e-6 * np.linalg.norm(c, axis=1)) & (
            np.abs(nrm[:, 2]) < 1e-6
        )
        above = np.all(self.sign * (h - floor) > tol, axis=0) & ~ends & ~walls
        # the bottom of the tooth spaces along the face (the deepest boundary point in
        # each of 40 slices of L); the root region reaches from there to the active
        # flank's root-side edge, or 0.25 m_n where the flank runs into the bottom
        Lc, hc = L.mean(axis=0), h.mean(axis=0)
        bins = np.linspace(bl.front, bl.back, 41)
        idx = np.clip(np.searchsorted(bins, Lc) - 1, 0, 39)
        deep = np.full(40, np.inf)
        np.minimum.at(deep, idx[above], self.sign * hc[above])
        ok = np.isfinite(deep)
        bottom = self.sign * np.interp(L, 0.5 * (bins[1:] + bins[:-1])[ok], deep[ok])
        top = np.where(self.sign * (top - bottom) > 0.1 * self.module, top,
                       bottom + self.sign * 0.25 * self.module)  # fmt: skip
        band = above & np.all(self.sign * (top - h) >= -tol, axis=0)
        Lc, psic = L.mean(axis=0), np.angle(np.exp(1j * psi).mean(axis=0))
        turn, side, _ = self._place(Lc, psic)
        block = np.array([self.blocks.get(int(t), 99) for t in turn])
        keep = band & ~ends & (block != 99)
        return bf[keep], block[keep], side[keep]

    def influence(self, raw):
        """The :class:`~reducerlab.contact.rootstress.FilletInfluence` of the fillet
        nodes: radius from the axis, face position ``L - (L_toe + L_heel)/2`` and the
        tangent angle to the tooth centre line in the section normal to the pitch-cone
        generatrix (the centre line: the ``h`` direction at the tooth's mid azimuth)."""
        from .rootstress import FilletInfluence

        ss, tooth, side, S = raw
        p, n = ss.points, ss.normals
        L, _, psi = self._cone(p, self.delta)
        mid, half, _ = self._edges(L)
        # tooth 0's centre line: half a pitch from the space's mid azimuth, on the
        # loaded flank's side; tooth block k is turned by -k pitches
        centre = mid + np.sign(half) * 0.5 * self.pitch - tooth * self.pitch
        sd, cd = math.sin(self.delta), math.cos(self.delta)
        e_l = np.stack([sd * np.cos(psi), sd * np.sin(psi), np.full_like(psi, cd)], axis=1)
        e_h = np.stack([cd * np.cos(centre), cd * np.sin(centre), np.full_like(psi, -sd)], 1)
        nt = n - np.einsum("ij,ij->i", n, e_l)[:, None] * e_l
        nt /= np.maximum(np.linalg.norm(nt, axis=1, keepdims=True), 1e-300)
        angle = np.arcsin(np.clip(np.abs(np.einsum("ij,ij->i", nt, e_h)), 0.0, 1.0))
        face = L - 0.5 * (self.blank.front + self.blank.back)
        ends = np.minimum(L - self.blank.front, self.blank.back - L)
        return FilletInfluence(p, n, np.asarray(tooth, np.int64), np.asarray(side, np.int64),
                               np.hypot(p[:, 0], p[:, 1]), face, angle, S, ends,
                               self.module)  # fmt: skip


def flank_influence(
    skm,
    held: Callable,
    points: Array,
    normals: Array,
    angles: Sequence[float],
    radius: float,
    material: Material,
    stage: Stage | None = None,
    *,
    name: str = "gear",
    fillet: Callable | None = None,
    _legacy: bool = False,
) -> tuple[Array, int] | tuple[Array, int, Any]:
    """Bending influence coefficients of load points on several teeth of one FE model.

    Parameters
    ----------
    skm : skfem.MeshTet2
        The teeth and their rim (m), gear axis ``z``.
    held : callable
        ``held(basis) -> DOF indices`` held at zero.
    points, normals : ndarray (L, 3)
        Load points on the flank of tooth 0 (m) and the flank's outward normals.
    angles : sequence of float
        Rotations about ``z`` (rad) taking tooth 0 to each modelled tooth.
    radius : float
        Bump radius ``a`` (m).
    material : Material
    stage : callable, optional
        ``stage(text)`` at each step (progress display).
    name : str
        The gear in messages, e.g. ``"internal gear (z = 32)"``.
    fillet : callable, optional
        ``fillet(basis) -> (facets, tooth, side)``: the boundary facets of the root
        fillets, each facet's tooth block (index into ``angles``' teeth) and side (+1
        the loaded flank's fillet, -1 the other). Given, the displacements of all
        bumps are solved too (the backward substitution of the same factor) and their
        stresses recovered at the fillet nodes (``fe.stress.surface_stress_operator``).
    _legacy : bool
        Private: scikit-fem's assembly and PARDISO's whole solve, as before issue 28
        (``benchmarks/fe_compliance_speed.py`` times both in one run).

    Returns
    -------
    matrix : ndarray (T L, T L)
        Influence coefficients (m/N), tooth-major, the bumps' own half-space interaction
        removed between load points of the same tooth (module docstring).
    dofs : int
        Size of the finite-element model.
    fillet : (SurfaceStress, tooth, side, ndarray (n, 6, T L))
        Only with ``fillet``: the fillet nodes, their tooth block and side, and the
        stress (Pa) at each under each unit bump (Pa/N).

    Raises
    ------
    FacetQuadratureError
        When the load integration finds the mesh's facets off its elements (named by
        ``name``; :func:`facet_quadrature`).
    """
    from ..fe.elasticity import assemble

    say = stage or (lambda _s: None)
    say(f"assembling {skm.t.shape[1]} quadratic tetrahedra")
    if _legacy:  # scikit-fem's assembly, the mass too, as before issue 28 (benchmarks)
        K, _, basis = assemble(skm, material, order=2, _engine="skfem")
    else:
        K, _, basis = assemble(skm, material, order=2, mass=False)
    fixed = held(basis)
    centres = np.concatenate([points @ rot_z(t).T for t in angles])
    nrm = np.concatenate([normals @ rot_z(t).T for t in angles])
    say(f"{len(centres)} flank loads")
    try:
        F = _bump_loads(basis, skm, centres, nrm, radius)
    except FacetQuadratureError as exc:
        raise FacetQuadratureError(
            f"compliance: the finite-element tooth model of the {name}: {exc}; mesh it "
            "again with another tooth element size (tooth_size; reducerlab contact --tooth-size)"
        ) from None
    say(f"solving {K.shape[0]} DOFs for {F.shape[1]} loads")
    raw = None
    if fillet is None:
        Kfe = _influence(K, F, fixed, _legacy)
    else:
        Kfe, raw = _fillet_influence(K, F, fixed, basis, material, fillet, say)
    L = len(points)
    E, nu = material.E, material.nu
    for t in range(len(angles)):
        sl = slice(t * L, (t + 1) * L)
        d = np.linalg.norm(centres[sl, None, :] - centres[None, sl, :], axis=2)
        Kfe[sl, sl] -= (1 - nu**2) / (math.pi * E) * bump_interaction(d, radius)
    if raw is not None:
        return Kfe, int(K.shape[0]), raw
    return Kfe, int(K.shape[0])


def root_stress_estimate(dofs: int, loads: int, samples: int = 0) -> Any:
    """The :class:`~reducerlab.budget.Estimate` of the root-stress influence: the
    displacements of ``loads`` bumps on ``dofs`` DOFs (with their forward
    substitution and a copy of the loads: three dense blocks) and the stress of each at
    ``samples`` fillet nodes (six components)."""
    from ..budget import Estimate

    return Estimate(
        what="contact: the root-stress influence of the flank loads",
        memory=3 * 8.0 * dofs * loads + 6 * 8.0 * samples * loads,
        control="the tooth element size (tooth_size, --tooth-size) or the load grid",
    )


def _fillet_influence(K, F: Array, fixed, basis, material, fillet, say) -> tuple[Array, Any]:
    """``F^T K^-1 F`` (m/N) and the fillet stresses of ``U = K^-1 F`` (one factorisation,
    PARDISO's forward and backward substitutions, or SuperLU without pypardiso)."""
    from ..fe.elasticity import pardiso_gram_solve
    from ..fe.stress import surface_stress_operator

    facets, tooth, side = fillet(basis)
    facets = np.asarray(facets, dtype=np.int64)
    if facets.size == 0:
        raise ReducerlabError("root stress: no root-fillet facets found on the tooth model")
    facets, first = np.unique(facets, return_index=True)  # sorted, as the operator's
    tooth, side = np.asarray(tooth)[first], np.asarray(side)[first]
    ss = surface_stress_operator(basis, material, facets)
    n = len(ss.points)
    root_stress_estimate(K.shape[0], F.shape[1], n).check()
    say(f"root stress at {n} fillet nodes")
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    Kff = K[free][:, free].tocsr()
    Ff = F[free]
    out = pardiso_gram_solve(Kff, Ff)
    if out is None:
        from scipy.sparse.linalg import splu

        Uf = splu(Kff.tocsc()).solve(Ff)
        G = Ff.T @ Uf
        G = 0.5 * (G + G.T)
    else:
        G, Uf = out
    S = np.asarray(ss.operator[:, free] @ Uf).reshape(n, 6, F.shape[1])
    return G, (ss, tooth[ss.facet_of], side[ss.facet_of], S)


def load_nodes(flank, inset: float, n_u: int, n_v: int) -> tuple[Array, Array]:
    """Load-point parameters of a flank: ``n_u`` profile parameters and ``n_v`` face
    parameters, evenly spaced in arc length, ``inset`` (m) inside the flank's edges
    (measured along the mid-face profile and the mid-height face line).

    Raises
    ------
    ReducerlabError
        When the flank is too short for load bumps of radius ``inset``.
    """
    lo, hi = flank.u_range
    s = np.linspace(lo, hi, 401)
    P, _ = flank.evaluate(s, np.full_like(s, 0.5))
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    if arc[-1] <= 2.5 * inset:
        raise ReducerlabError(
            f"compliance: the flank ({arc[-1] * 1e3:.3g} mm high) is too short for load bumps "
            f"of radius {inset * 1e3:.3g} mm: use a smaller tooth element size"
        )
    u_nodes = np.interp(np.linspace(inset, arc[-1] - inset, n_u), arc, s)
    t = np.linspace(0.0, 1.0, 401)
    um = 0.5 * (lo + hi)
    P, _ = flank.evaluate(np.full_like(t, um), t)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    v_nodes = np.interp(np.linspace(inset, arc[-1] - inset, n_v), arc, t)
    return u_nodes, v_nodes


def _held_dofs(basis, mesh, cone_coordinates) -> NDArray[np.int64]:
    """DOFs of the boundary facets on the rim's base cone and on the two end walls."""
    skm = basis.mesh
    x = skm.p
    tol = 1e-6 * float(np.max(np.abs(mesh.points)))
    h = cone_coordinates(x.T, mesh.gear.cone_angle)[1]
    on = np.abs(h - mesh.blank.body) < tol
    # end walls: the extreme azimuths of the open sector (planes through the axis)
    az = np.arctan2(x[1], x[0])
    ref = np.angle(np.mean(np.exp(1j * az)))
    rel = np.angle(np.exp(1j * (az - ref)))
    for side in (rel.min(), rel.max()):
        phi = ref + side
        nrm = np.array([-math.sin(phi), math.cos(phi), 0.0])
        on |= np.abs(nrm @ x) < tol
    bf = skm.boundary_facets()
    facets = bf[np.all(on[skm.facets[:, bf]], axis=0)]
    return np.asarray(basis.get_dofs(facets=facets).all(), dtype=np.int64)


def _bump_loads(basis, skm, centres: Array, normals: Array, a: float) -> Array:
    """Load vectors (ndofs, n): unit normal force spread as ``(1 - r^2/a^2)^2`` over the
    boundary facets near each centre whose normal faces the load's normal (within 60
    deg), integrated with the facets' quadrature (all loads at once)."""
    import scipy.sparse as sp
    from scipy.spatial import cKDTree

    bf = skm.boundary_facets()
    mid = skm.p[:, skm.facets[:, bf]].mean(axis=1).T  # facet corner centroids
    near = cKDTree(mid).query_ball_point(centres, 1.5 * a)
    used = np.unique(np.concatenate([np.asarray(n, dtype=np.int64) for n in near]))
    if used.size == 0:
        raise ReducerlabError("compliance: the load points lie off the meshed flank")
    q = facet_quadrature(basis, bf[used], intorder=4)
    nf, nq = q.dx.shape
    cols = np.broadcast_to(np.arange(nf * nq).reshape(nf, nq), q.values.shape)
    vals = (q.values * q.dx).ravel()
    dim = basis.mesh.dim()
    S = [
        sp.csr_matrix(
            (vals, (np.repeat(q.dofs[c::dim, :, None], nq, axis=2).ravel(), cols.ravel())),
            shape=(basis.N, nf * nq),
        )
        for c in range(dim)
    ]
    xq = q.points.reshape(3, -1).T  # (nf nq, 3)
    nrm = q.normals.reshape(3, -1).T
    r2 = np.sum((xq[:, None, :] - centres[None, :, :]) ** 2, axis=2) / (a * a)
    facing = nrm @ normals.T > 0.5
    B = np.where((r2 < 1.0) & facing, (1.0 - r2) ** 2, 0.0)  # (nf nq, n)
    F = -sum(S[c] @ (B * normals[:, c]) for c in range(3))
    total = np.array([_force_of(F[:, j], basis, normals[j]) for j in range(F.shape[1])])
    if not np.all(total > 0):
        raise ReducerlabError("compliance: a load bump found no flank area under it")
    return F / total


class FacetQuadratureError(ReducerlabError):
    """The facet quadrature of a finite-element model does not lie on its elements (a
    mesh whose facets and elements disagree)."""


@dataclass(frozen=True)
class FacetQuadrature:
    """Quadrature on boundary facets of a vector Lagrange basis (:func:`facet_quadrature`).

    Attributes
    ----------
    points : ndarray (3, facets, nq)
        Global quadrature points (m).
    dx : ndarray (facets, nq)
        Quadrature weights times the facets' area element (m^2).
    normals : ndarray (3, facets, nq)
        Outward unit normals.
    values : ndarray (scalar functions, facets, nq)
        Values of the element's scalar shape functions there.
    dofs : ndarray (element dofs, facets)
        DOFs of the facets' elements (vector DOF ``k`` is component ``k % 3`` of
        scalar function ``k // 3``, scikit-fem's ``ElementVector`` order).
    """

    points: Array
    dx: Array
    normals: Array
    values: Array
    dofs: NDArray[np.int64]


def facet_quadrature(basis, facets: NDArray[np.int64], intorder: int = 4) -> FacetQuadrature:
    """Quadrature on the boundary ``facets`` of ``basis`` without an inverse mapping.

    scikit-fem's ``FacetBasis`` maps the reference-facet quadrature points to the global
    facet and back into each element's reference tetrahedron by Newton's method
    (``MappingIsoparametric.invF``, started at ``(0.5, 0.5, 0.5)``, clipped to the unit
    cube, tolerance 1e-12): on valid but strongly curved quadratic tetrahedra, which
    gmsh's parallel mesher produces now and then, it fails with "Newton iteration didn't
    converge". The inverse is not needed: a point of barycentric coordinates
    ``(1 - s - t, s, t)`` on a facet with corners ``f_0, f_1, f_2`` is, in the reference
    tetrahedron of the element it bounds, ``sum_a lambda_a V_{j(a)}``, with ``j(a)`` the
    element's local number of corner ``f_a`` and ``V_j`` the reference corners: exact,
    since the element's (isoparametric) map restricted to a face is the face's own
    quadratic map. The global points and the area element come from the facet's map
    (as ``FacetBasis`` has them) and are checked against the element's map at the
    reference points.

    Parameters
    ----------
    basis : skfem.Basis
        A cell basis of ``ElementVector`` of a Lagrange element on a tetrahedral mesh
        (``MeshTet`` or ``MeshTet2``).
    facets : array of int
        Boundary facet indices of ``basis.mesh``.
    intorder : int
        Degree of the facet quadrature.

    Raises
    ------
    FacetQuadratureError
        When a facet is not a face of the element that bounds it, or the element's map
        puts the quadrature points off the facet's (a corrupt mesh).
    """
    from skfem.quadrature import get_quadrature

    mesh = basis.mesh
    mapping = basis.mapping
    find = np.asarray(facets, dtype=np.int64)
    tind = mesh.f2t[0, find]
    X, W = get_quadrature(mesh.brefdom, intorder)  # (2, nq) on the reference triangle
    corners = mesh.facets[:, find]  # (3, nf)
    local = mesh.t[:, tind][:, None, :] == corners[None, :, :]  # (4, 3, nf)
    if not np.all(local.sum(axis=0) == 1):
        raise FacetQuadratureError(
            "facet quadrature: a facet is not a face of the element it bounds (corrupt mesh)"
        )
    j = np.argmax(local, axis=0)  # (3, nf): the element's local corner of each facet corner
    ref = np.vstack([np.zeros(mesh.dim()), np.eye(mesh.dim())])  # reference corners
    lam = np.vstack([1.0 - X[0] - X[1], X[0], X[1]])  # (3, nq)
    Y = np.einsum("anc,aq->cnq", ref[j], lam)  # (3, nf, nq) in the reference tetrahedron
    x = np.asarray(mapping.G(X, find=find))  # (3, nf, nq) on the facets' own map
    off = float(np.max(np.abs(np.asarray(mapping.F(Y, tind=tind)) - x))) if find.size else 0.0
    size = float(np.ptp(mesh.p, axis=1).max())
    if not off <= 1e-9 * size:
        raise FacetQuadratureError(
            f"facet quadrature: the elements put the facet points {off:.3g} m off their "
            "facets (a corrupt mesh)"
        )
    dx = np.abs(np.asarray(mapping.detDG(X, find=find))) * W[None, :]
    normals = np.asarray(mapping.normals(Y, tind, find, mesh.t2f))
    scalar = basis.elem.elem  # the scalar element of the ElementVector
    values = np.stack([scalar.lbasis(Y, i)[0] for i in range(scalar.doflocs.shape[0])])
    return FacetQuadrature(x, dx, normals, values, np.asarray(basis.element_dofs)[:, tind])


def _force_of(b: Array, basis, n: Array) -> float:
    """Resultant of a load vector along ``-n`` (N): sum of its nodal forces."""
    f = np.array([b[basis.nodal_dofs[c]].sum() + b[basis.edge_dofs[c]].sum() for c in range(3)])
    return float(-f @ n)


def _influence(K, F: Array, fixed: NDArray[np.int64], legacy: bool = False) -> Array:
    """``F^T K^-1 F`` (m/N) with the DOFs ``fixed`` held at zero (one factorisation):
    the forward substitution of PARDISO's Cholesky factor alone (``fe.pardiso_gram``);
    ``legacy``: the whole solve ``U = K^-1 F`` first, as before issue 28 (benchmarks)."""
    from ..fe.elasticity import pardiso_gram, pardiso_inverse

    n = K.shape[0]
    free = np.setdiff1d(np.arange(n), fixed)
    Kff = K[free][:, free].tocsr()
    Ff = F[free]
    if not legacy:
        G = pardiso_gram(Kff, Ff)
        if G is not None:
            return G
    inv = pardiso_inverse(Kff)
    if inv is not None:
        Uf = inv.matmat(Ff)
    else:
        from scipy.sparse.linalg import splu

        Uf = splu(Kff.tocsc()).solve(Ff)
    G = Ff.T @ Uf
    return 0.5 * (G + G.T)
