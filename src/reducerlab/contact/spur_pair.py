"""Parallel-axis involute spur gear pairs in the loaded tooth contact analysis.

Adapters of :mod:`reducerlab.geometry.spur` to the protocols of
:mod:`reducerlab.contact.flanks` and :mod:`reducerlab.contact.ltca`:

* :class:`SpurFlank`: one involute flank of tooth 0 of a :class:`SpurGear`, ``u`` in
  ``[0, 1]`` from the root form circle to the tip (linear in the roll length), ``v`` in
  ``[0, 1]`` across the face (``z = -b/2 ... b/2``), the gear's own frame (``z`` = axis),
  normals out of the material;
* :class:`SpurMeshPair`: a :class:`SpurPair` as a ``MeshPair``; the pinion is gear A,
  the wheel gear B, both loaded on flank +1 (the drive flanks for a positive pinion
  torque). Tooth pair ``k`` is pinion tooth ``k`` (tooth 0 turned by ``+2 pi k / z1``)
  against wheel tooth ``-k`` (wheel tooth 0 turned by ``-2 pi k / z2``), the spur
  convention (``SpurPair.mating_tooth``);
* :func:`spur_tooth_compliance`: the finite-element bending compliance of teeth
  ``-1, 0, 1`` of a spur gear (``contact.compliance.flank_influence`` on a five-tooth
  sector of ``fe.spur_mesh``, bore and radial cut faces held).

Units: SI (m, N, Pa, rad).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..fe.elasticity import STEEL, Material
from ..geometry.spur import SpurGear, SpurPair
from .compliance import TEETH, ToothCompliance, flank_influence, load_nodes
from .flanks import Flank, GearPose
from .modifications import PairModifications, modified

__all__ = [
    "SpurFlank",
    "SpurMeshPair",
    "fillet_facets",
    "fillet_influence",
    "held_sector_dofs",
    "model_sizes",
    "modelled_teeth",
    "spur_tooth_compliance",
]

Array = NDArray[np.float64]
Stage = Callable[[str], None]

#: Teeth meshed for the compliance: the modelled teeth -1, 0, 1 and one more on each
#: side, so that teeth -1 and 1 are full teeth with a full pitch of rim on both sides,
#: away from the held radial cut faces.
SECTOR_TEETH = 5


@dataclass(frozen=True)
class SpurFlank:
    """One involute flank of tooth 0 of a spur gear (the ``Flank`` protocol).

    Parameters
    ----------
    gear : SpurGear
    flank : {+1, -1}
        Counter-clockwise (+1) or clockwise (-1) flank of the tooth
        (:mod:`reducerlab.geometry.spur`).

    ``u`` runs along the active involute from the root form circle (0) to the tip
    circle (1), linear in the roll length; ``v`` over the face from ``z = -b/2`` (0) to
    ``b/2`` (1). :meth:`evaluate` continues the involute and the face analytically a
    little beyond ``[0, 1]`` (Newton iterates of ``contact.flanks.separations`` may step
    outside); :meth:`inside` tells the real tooth.
    """

    gear: SpurGear
    flank: int = 1
    u_range: tuple[float, float] = field(default=(0.0, 1.0), init=False)

    def __post_init__(self) -> None:
        if not isinstance(self.gear, SpurGear):
            raise ReducerlabError(f"gear: must be a SpurGear; got {type(self.gear).__name__}")
        if isinstance(self.flank, bool) or self.flank not in (1, -1):
            raise ReducerlabError(f"flank: must be +1 or -1; got {self.flank!r}")

    @property
    def teeth(self) -> int:
        """Number of teeth ``z``."""
        return self.gear.teeth

    def profile_position(self, u: Array) -> Array:
        """Roll length (m) from the root form circle at profile parameters ``u``: the
        position along the line of action by which ISO 21771 measures profile
        modifications (``contact.modifications``)."""
        g = self.gear
        return np.asarray(u, float) * (g.tip_roll - g.form_roll)

    def evaluate(self, u: Array, v: Array) -> tuple[Array, Array]:
        """Points (m) and unit outward normals, shape (n, 3), gear frame.

        Parameters
        ----------
        u, v : ndarray (n,)
            Flank parameters (dimensionless), see the class docstring.
        """
        g = self.gear
        uu = np.asarray(u, float).ravel()
        vv = np.asarray(v, float).ravel()
        if uu.shape != vv.shape:
            raise ReducerlabError(f"u, v: need the same length; got {uu.shape} and {vv.shape}")
        p2, n2 = g.involute_points(u=uu)
        if self.flank == -1:
            p2 = p2 * np.array([1.0, -1.0])
            n2 = n2 * np.array([1.0, -1.0])
        zc = g.face_width * (vv - 0.5)
        return np.column_stack([p2, zc]), np.column_stack([n2, np.zeros_like(zc)])

    def inside(self, points: Array) -> NDArray[np.bool_]:
        """Whether points (gear frame, (n, 3), m) lie within the tooth's radial extent
        (root form circle to tip circle) and face width."""
        g = self.gear
        p = np.atleast_2d(np.asarray(points, float))
        r = np.hypot(p[:, 0], p[:, 1])
        tol = 1e-9 * g.tip_radius
        radial = (r >= g.form_radius - tol) & (r <= g.tip_radius + tol)
        return radial & (np.abs(p[:, 2]) <= 0.5 * g.face_width + tol)


@dataclass(frozen=True)
class SpurMeshPair:
    """A parallel-axis spur gear pair as a ``MeshPair`` of the tooth contact analysis.

    Parameters
    ----------
    pair : SpurPair
        Pinion (gear A) and wheel (gear B) at their working centre distance.
    modifications : PairModifications, optional
        Flank modifications of the pinion (``a``) and the wheel (``b``),
        ``contact.modifications``; default none.

    The mesh position ``phi`` is the pinion's rotation (rad) of :meth:`SpurPair.pose`:
    at ``phi = 0`` flank +1 of pinion tooth 0 touches flank +1 of wheel tooth 0. Both
    loaded flanks are +1 (pinion drives, positive torque about ``+z``).
    """

    pair: SpurPair
    modifications: PairModifications = field(default_factory=PairModifications)

    def __post_init__(self) -> None:
        if not isinstance(self.pair, SpurPair):
            raise ReducerlabError(f"pair: must be a SpurPair; got {type(self.pair).__name__}")
        if not isinstance(self.modifications, PairModifications):
            raise ReducerlabError(
                "modifications: must be a PairModifications (contact.modifications); got "
                f"{type(self.modifications).__name__}"
            )

    @functools.cached_property
    def flank_a(self) -> Flank:
        """Flank +1 of the pinion (modified by ``modifications.a``)."""
        return modified(SpurFlank(self.pair.pinion, 1), self.modifications.a, "modifications.a")

    @functools.cached_property
    def flank_b(self) -> Flank:
        """Flank +1 of the wheel (modified by ``modifications.b``)."""
        return modified(SpurFlank(self.pair.wheel, 1), self.modifications.b, "modifications.b")

    @property
    def unmodified(self) -> SpurMeshPair:
        """The same pair without flank modifications."""
        if self.modifications.none:
            return self
        return replace(self, modifications=PairModifications())

    @property
    def torque_ratio(self) -> float:
        """``T_B / T_A = z2 / z1``."""
        return self.pair.wheel.teeth / self.pair.pinion.teeth

    def tooth_angles(self, k: int) -> tuple[float, float]:
        """``(2 pi k / z1, -2 pi k / z2)`` (rad): pinion tooth ``k`` meshes wheel tooth
        ``-k``."""
        return 2 * math.pi * k / self.pair.pinion.teeth, -2 * math.pi * k / self.pair.wheel.teeth

    def poses(self, phi: float) -> tuple[GearPose, GearPose]:
        """Pinion about the ``z`` axis, wheel about the parallel axis through ``(a, 0, 0)``
        (fixed frame), for the pinion rotation ``phi`` (rad)."""
        R1, R2 = self.pair.pose(float(phi))
        ez = np.array([0.0, 0.0, 1.0])
        return GearPose(R1, np.zeros(3), ez), GearPose(R2, self.pair.wheel_center, ez.copy())

    def pitch_point_position(self, k: int = 0) -> float:
        """Mesh position ``phi`` (rad) at which tooth pair ``k`` touches at the pitch
        point (roll length ``r_b1 tan a_w`` from ``T1``)."""
        p = self.pair.pinion
        aw = self.pair.working_pressure_angle
        return math.tan(aw) - aw - p.base_half_angle - k * p.pitch

    def tooth_compliances(
        self,
        *,
        material: Material = STEEL,
        grid: tuple[int, int] = (6, 9),
        tooth_size: float | None = None,
        body_size: float | None = None,
        rim: float | None = None,
        stage: Stage | None = None,
        root_stress: bool = False,
    ) -> tuple[ToothCompliance, ToothCompliance]:
        """Bending compliances of pinion and wheel (:func:`spur_tooth_compliance`), in
        the tooth pair order of this pair. When the two gears are the same, one
        finite-element model serves both (the wheel's blocks are the pinion's with the
        teeth reversed). Parameters as :func:`spur_tooth_compliance`."""
        kw = dict(material=material, grid=grid, tooth_size=tooth_size, body_size=body_size,
                  rim=rim, stage=stage, root_stress=root_stress)  # fmt: skip
        ca = spur_tooth_compliance(self.pair.pinion, 1, direction=1, **kw)
        if self.pair.wheel == self.pair.pinion:
            return ca, _reverse_teeth(ca)
        return ca, spur_tooth_compliance(self.pair.wheel, 1, direction=-1, **kw)


def _reverse_teeth(c: ToothCompliance) -> ToothCompliance:
    """The compliance with tooth block ``k`` taken from block ``-k`` (the same three teeth
    in reverse order: the wheel of a pair of two equal gears)."""
    L = len(c.u_nodes) * len(c.v_nodes)
    order = np.concatenate([np.arange(L) + c.teeth.index(-k) * L for k in c.teeth])
    fillet = None if c.fillet is None else c.fillet.reversed_teeth(c.teeth, L)
    return ToothCompliance(c.u_nodes, c.v_nodes, c.teeth, c.matrix[np.ix_(order, order)],
                           c.dofs, c.radius, fillet)  # fmt: skip


def fillet_facets(mesh, flank: int, direction: int) -> Callable:
    """``fillet(basis) -> (facets, tooth block, side)`` of a cylindrical gear's tooth
    sector ``mesh`` (``fe.spur_mesh``, ``fe.internal_mesh``; tooth 0 centred on ``+x``):
    the boundary facets between the root circle and the root form circle (the generated
    fillets and the root land; inside the root circle for an external gear, outside it
    for an internal one), not on the end faces, of the modelled teeth; a facet belongs
    to the tooth whose centre line is nearest, on the side of its polar angle (side +1
    toward the loaded ``flank``)."""
    g = mesh.gear
    lo, hi = sorted((g.root_radius, g.form_radius))

    def select(basis):
        skm = basis.mesh
        bf = skm.boundary_facets()
        P = skm.p[:, skm.facets[:, bf]]  # (3 coords, 3 corners, facets)
        r = np.hypot(P[0], P[1])
        tol = 1e-6 * g.module
        band = np.all((r >= lo - tol) & (r <= hi + tol), axis=0)
        nrm = np.cross((P[:, 1] - P[:, 0]).T, (P[:, 2] - P[:, 0]).T)
        lateral = np.abs(nrm[:, 2]) < 0.5 * np.linalg.norm(nrm, axis=1)
        c = P.mean(axis=1)
        theta = np.arctan2(c[1], c[0])
        j = np.rint(theta / g.pitch).astype(np.int64)  # gear tooth of the facet
        block = direction * j
        keep = band & lateral & np.isin(block, TEETH)
        side = np.where(theta - j * g.pitch >= 0, 1, -1) * flank
        return bf[keep], block[keep], side[keep]

    return select


def fillet_influence(gear: Any, raw, direction: int):
    """The :class:`~reducerlab.contact.rootstress.FilletInfluence` of a cylindrical
    gear's sector (``SpurGear`` or ``InternalGear``) from ``flank_influence``'s fillet
    output: radius, face position ``z`` and the tangent angle to the centre line (the
    radial line) of the node's tooth."""
    from .rootstress import FilletInfluence

    ss, tooth, side, S = raw
    p, n = ss.points, ss.normals
    centre = direction * tooth * gear.pitch  # polar angle of the tooth's centre line
    e = np.stack([np.cos(centre), np.sin(centre)], axis=1)
    nt = n[:, :2] / np.maximum(np.linalg.norm(n[:, :2], axis=1, keepdims=True), 1e-300)
    angle = np.arcsin(np.clip(np.abs(np.einsum("ij,ij->i", nt, e)), 0.0, 1.0))
    return FilletInfluence(p, n, np.asarray(tooth, np.int64), np.asarray(side, np.int64),
                           np.hypot(p[:, 0], p[:, 1]), p[:, 2].copy(), angle, S,
                           0.5 * gear.face_width - np.abs(p[:, 2]), gear.module)  # fmt: skip


def held_sector_dofs(basis, mesh, radius: float, what: str) -> NDArray[np.int64]:
    """DOFs of a gear sector's boundary facets on the cylinder of ``radius`` (m: a spur
    gear's bore, an internal gear's outer rim) and on its two radial cut faces
    (``mesh.cut_angles``): the supports of the tooth models. ``what`` names the
    cylinder in the error."""
    skm = basis.mesh
    x = skm.p
    tol = 1e-6 * mesh.gear.module
    on = np.abs(np.hypot(x[0], x[1]) - radius) <= tol
    cut = np.zeros_like(on)
    for phi in mesh.cut_angles:
        nrm = np.array([-math.sin(phi), math.cos(phi), 0.0])
        e = np.array([math.cos(phi), math.sin(phi), 0.0])
        cut |= (np.abs(nrm @ x) <= tol) & (e @ x > 0)
    bf = skm.boundary_facets()
    corners = skm.facets[:, bf]
    facets = bf[np.all(on[corners], axis=0) | np.all(cut[corners], axis=0)]
    if facets.size == 0:
        raise ReducerlabError(f"compliance: no {what} or cut-face facets found to hold")
    return np.asarray(basis.get_dofs(facets=facets).all(), dtype=np.int64)


def _held_dofs(basis, mesh) -> NDArray[np.int64]:
    """DOFs of the boundary facets on the bore cylinder and the two radial cut faces."""
    return held_sector_dofs(basis, mesh, mesh.inner_radius, "bore")


def modelled_teeth(teeth: Sequence[int], root_stress: bool) -> tuple[int, ...]:
    """The teeth of a cylindrical gear's tooth model, ``-n ... n`` with ``n`` in 1..3
    (on a sector of ``2 n + 3`` teeth); other than ``-1, 0, 1`` without ``root_stress``
    (``contact.compliance.extend_teeth`` is checked on ``-2 ... 2``, issue 30).

    Raises
    ------
    ReducerlabError
        Naming ``teeth`` or ``root_stress`` and the rule.
    """
    try:
        modelled = tuple(int(k) for k in teeth)
    except (TypeError, ValueError):
        raise ReducerlabError(f"teeth: must be integers -n ... n; got {teeth!r}") from None
    n_side = max(modelled, default=0)
    if modelled != tuple(range(-n_side, n_side + 1)) or not 1 <= n_side <= 3:
        raise ReducerlabError(f"teeth: must be -n ... n with n in 1..3; got {teeth!r}")
    if root_stress and modelled != TEETH:
        raise ReducerlabError(f"root_stress: with teeth {TEETH} only; got {teeth!r}")
    return modelled


def model_sizes(
    grid: tuple[int, int], module: float, tooth_size: float | None, body_size: float | None
) -> tuple[int, int, float, float]:
    """The checked load grid ``(n_u, n_v)`` and element sizes ``(tooth, body)`` (m) of a
    cylindrical gear's tooth model: defaults ``0.3 m`` and ``m``, the body never finer
    than the teeth.

    Raises
    ------
    ReducerlabError
        Naming ``grid``, ``tooth_size`` or ``body_size`` and the rule.
    """
    try:
        n_u, n_v = (int(g) for g in grid)
    except (TypeError, ValueError):
        raise ReducerlabError(f"grid: must be two integers (n_u, n_v); got {grid!r}") from None
    if n_u < 2 or n_v < 2:
        raise ReducerlabError(f"grid: needs at least 2 x 2 load points; got {grid!r}")
    m = module
    sizes = {"tooth_size": 0.3 * m, "body_size": 1.0 * m}
    for name, val in (("tooth_size", tooth_size), ("body_size", body_size)):
        if val is None:
            continue
        if (
            isinstance(val, bool)
            or not isinstance(val, int | float)
            or not (math.isfinite(val) and val > 0)
        ):
            raise ReducerlabError(f"{name}: must be a length > 0 (m); got {val!r}")
        sizes[name] = float(val)
    ts, bs = sizes["tooth_size"], max(sizes["body_size"], sizes["tooth_size"])
    return n_u, n_v, ts, bs


def spur_tooth_compliance(
    gear: SpurGear,
    flank: int = 1,
    *,
    material: Material = STEEL,
    grid: tuple[int, int] = (6, 9),
    tooth_size: float | None = None,
    body_size: float | None = None,
    rim: float | None = None,
    direction: int = 1,
    stage: Stage | None = None,
    root_stress: bool = False,
    teeth: Sequence[int] = TEETH,
) -> ToothCompliance:
    """Finite-element bending compliance of teeth ``-1, 0, 1`` of a spur gear.

    A sector of five teeth (``fe.spur_mesh.mesh_spur_sector``; teeth ``-2 ... 2``, so
    the modelled teeth ``-1, 0, 1`` are full teeth with rim on both sides) is held on its
    bore and its two radial cut faces. ``n_u x n_v`` load points on the flank of each
    modelled tooth, inset by the bump radius ``a = 2 tooth_size`` from the flank's edges
    (the rule of ``contact.compliance.fe_tooth_compliance``), give the influence
    coefficients of ``contact.compliance.flank_influence`` (local half-space part
    removed).

    Parameters
    ----------
    gear : SpurGear
    flank : {+1, -1}
        The loaded flank.
    material : Material
        Young's modulus (Pa) and Poisson's ratio.
    grid : (int, int)
        Load points along the profile and across the face on each tooth (>= 2 each).
    tooth_size, body_size : float, optional
        Element sizes (m) on the teeth and one tooth depth below the root circle;
        default ``0.3 m`` and ``m``.
    rim : float, optional
        Rim thickness below the root circle (m); default ``3.5 m`` (ISO 6336-1's solid
        gear, ``s_R >= 3.5 m_n``).
    direction : {+1, -1}
        Tooth block ``k`` of the result is gear tooth ``direction * k`` (tooth 0 turned
        by ``direction 2 pi k / z``): +1 for the pinion (gear A) and -1 for the wheel
        (gear B) of a :class:`SpurMeshPair`, whose tooth pair ``k`` is pinion tooth
        ``k`` against wheel tooth ``-k``.
    stage : callable, optional
        ``stage(text)`` at each step (progress display).
    root_stress : bool
        Also the stress influence of every load bump at the root-fillet nodes of the
        three teeth (``contact.rootstress``; the same factorisation, one backward
        substitution more; about ``24 dofs x loads`` bytes more at the peak).
    teeth : sequence of int
        The modelled teeth, ``-n ... n`` (default ``-1, 0, 1``), on a sector of ``2 n +
        3`` teeth (:func:`modelled_teeth`); ``-2 ... 2`` on seven checks
        ``contact.compliance.extend_teeth`` (``benchmarks/khv_sharing.py``).

    Returns
    -------
    ToothCompliance
        Teeth ``(-1, 0, 1)``, flank parameters ``(u, v)`` of :class:`SpurFlank`,
        influence coefficients in m/N; with ``root_stress`` its ``fillet``.

    Raises
    ------
    ReducerlabError
        A bad argument (named), or a flank too short for the load bumps.
    """
    from ..fe.gear_mesh import MeshSizes
    from ..fe.spur_mesh import mesh_spur_sector

    if not isinstance(gear, SpurGear):
        raise ReducerlabError(f"gear: must be a SpurGear; got {type(gear).__name__}")
    if isinstance(flank, bool) or flank not in (1, -1):
        raise ReducerlabError(f"flank: must be +1 or -1; got {flank!r}")
    if isinstance(direction, bool) or direction not in (1, -1):
        raise ReducerlabError(f"direction: must be +1 or -1; got {direction!r}")
    if not isinstance(material, Material):
        raise ReducerlabError(f"material: must be a Material; got {type(material).__name__}")
    if not isinstance(root_stress, bool):
        raise ReducerlabError(f"root_stress: must be True or False; got {root_stress!r}")
    modelled = modelled_teeth(teeth, root_stress)
    sector = len(modelled) + 2
    if gear.teeth <= sector:
        raise ReducerlabError(
            f"gear: the compliance model needs more than {sector} teeth; got {gear.teeth}"
        )
    n_u, n_v, ts, bs = model_sizes(grid, gear.module, tooth_size, body_size)
    say = stage or (lambda _s: None)
    a = 2.0 * ts  # bump radius: two tooth elements
    sflank = SpurFlank(gear, flank)
    u_nodes, v_nodes = load_nodes(sflank, a, n_u, n_v)
    say(f"meshing a {sector}-tooth sector")
    mesh = mesh_spur_sector(gear, sector, rim=rim, sizes=MeshSizes(ts, bs))
    uu, vv = np.meshgrid(u_nodes, v_nodes, indexing="ij")
    P0, N0 = sflank.evaluate(uu.ravel(), vv.ravel())
    angles = [direction * gear.pitch * k for k in modelled]
    fillet = fillet_facets(mesh, flank, direction) if root_stress else None
    out = flank_influence(mesh.skfem(), lambda basis: _held_dofs(basis, mesh), P0, N0,
                          angles, a, material, stage=say, name=f"spur gear (z = {gear.teeth})",
                          fillet=fillet)  # fmt: skip
    inf = fillet_influence(gear, out[2], direction) if root_stress else None
    return ToothCompliance(u_nodes, v_nodes, modelled, out[0], out[1], a, inf)
