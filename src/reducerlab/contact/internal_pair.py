"""Internal involute spur gear pairs (KHV drives, paper 004) in the loaded tooth contact
analysis.

Adapters to the protocols of :mod:`reducerlab.contact.flanks` and
:mod:`reducerlab.contact.ltca`:

* :class:`InternalFlank`: one involute flank of tooth 0 of an
  :class:`~reducerlab.geometry.internal_gear.InternalGear` (the ring), ``u`` in
  ``[0, 1]`` from the root form circle (outer end) to the tip circle (inner end),
  linear in the roll length, ``v`` across the face, normals out of the material;
* :class:`InternalMeshPair`: the planet (gear A, a :class:`SpurGear`) inside the ring
  (gear B) at the working centre distance, as a ``MeshPair``; :meth:`InternalMeshPair.
  from_khv` builds it from a KHV design's gears;
* :func:`internal_tooth_compliance`: the finite-element bending compliance of ring teeth
  ``-1, 0, 1`` (``contact.compliance.flank_influence`` on a five-tooth sector of
  ``fe.internal_mesh``, the rim's outer surface and the radial cut faces held).

Placement (fixed frame, SI units, rad): the planet's axis is the ``z`` axis, the ring's
axis is parallel through ``(-a', 0, 0)``; the mesh zone lies on ``+x`` (pitch point
``(r_w1, 0, 0)``). For a positive planet torque (about ``+z``) flank **+1** of the
planet drives flank **-1** of the ring (the clockwise side of a ring tooth); the drive
side line of action runs through the pitch point with direction
``e = (sin a_w, cos a_w, 0)``, tangent to the planet's base circle at
``T1 = r_b1 (cos a_w, -sin a_w)`` and to the ring's at ``T2 = T1 - a' sin(a_w) e``. A
contact point at distance ``s`` from ``T1`` has the planet roll length ``s`` and the ring
roll length ``s + a' sin a_w``. Both gears turn the same way: planet tooth ``k`` (tooth
0 turned by ``2 pi k / z1``) meets ring tooth ``k`` (tooth 0 turned by ``2 pi k / z2``).
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
from ..geometry.internal_gear import InternalGear
from ..geometry.internal_pair import inv, inv_inverse
from ..geometry.spur import SpurGear
from ..kinematics.rotations import rot_z
from .compliance import TEETH, ToothCompliance, flank_influence, load_nodes
from .flanks import Flank, GearPose
from .modifications import PairModifications, modified
from .spur_pair import (
    SpurFlank,
    fillet_facets,
    fillet_influence,
    held_sector_dofs,
    model_sizes,
    modelled_teeth,
    spur_tooth_compliance,
)

__all__ = [
    "MODELLED_PAIRS",
    "RING_DEDENDUM_CLEARANCE",
    "RING_ROOT_FILLET",
    "InternalFlank",
    "InternalMeshPair",
    "internal_tooth_compliance",
    "loaded_pairs",
    "tooth_pair_clearances",
]

Array = NDArray[np.float64]
Stage = Callable[[str], None]

#: Teeth meshed for the ring's compliance: teeth -1, 0, 1 and one more on each side.
SECTOR_TEETH = 5
#: Tip clearance coefficient ``c*`` of the ring's root: ``h_f2* = h_a* + c*`` (the
#: ISO 53 relation h_fP = h_aP + 0.25 m), docs/assumptions.md.
RING_DEDENDUM_CLEARANCE = 0.25
#: Root fillet radius coefficient of the ring, ``rho_f* = 0.25`` (ISO 53 profile C):
#: profile A's 0.38 does not fit into the narrow space root of the paper 004 ring.
RING_ROOT_FILLET = 0.25
#: tooth pairs ``-2 ... 2`` round pair 0 are modelled in the load sharing (issue 30):
#: their compliance is the block-Toeplitz extension of teeth -1, 0, 1
#: (``contact.compliance.extend_teeth``), checked against a seven-tooth sector
#: (``benchmarks/khv_sharing.py``); a pair farther round (the tips passing, pair +8 of
#: examples/khv.toml) touches tip edge on tip edge, outside the flank contact model
MODELLED_PAIRS = 2


@dataclass(frozen=True)
class InternalFlank:
    """One involute flank of tooth 0 of an internal gear (the ``Flank`` protocol).

    Parameters
    ----------
    gear : InternalGear
    flank : {+1, -1}
        Counter-clockwise (+1) or clockwise (-1) side of the tooth.

    ``u`` runs along the involute from the root form circle (0, the outer end) to the tip
    circle (1, the inner end), linear in the roll length; ``v`` over the face from
    ``z = -b/2`` (0) to ``b/2`` (1). :meth:`evaluate` continues the involute and the face
    analytically beyond ``[0, 1]``; :meth:`inside` tells the real tooth.
    """

    gear: InternalGear
    flank: int = -1
    u_range: tuple[float, float] = field(default=(0.0, 1.0), init=False)

    def __post_init__(self) -> None:
        if not isinstance(self.gear, InternalGear):
            raise ReducerlabError(f"gear: must be an InternalGear; got {type(self.gear).__name__}")
        if isinstance(self.flank, bool) or self.flank not in (1, -1):
            raise ReducerlabError(f"flank: must be +1 or -1; got {self.flank!r}")

    @property
    def teeth(self) -> int:
        """Number of teeth ``z``."""
        return self.gear.teeth

    def profile_position(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Distance (m) along the line of action from the root form circle at profile
        parameters ``u`` (the roll length by which ISO 21771 measures profile
        modifications, ``contact.modifications``)."""
        g = self.gear
        return np.asarray(u, float) * abs(g.tip_roll - g.form_roll)

    def evaluate(self, u: Array, v: Array) -> tuple[Array, Array]:
        """Points (m) and unit outward normals, shape (n, 3), gear frame.

        Parameters
        ----------
        u, v : ndarray (n,)
            Flank parameters (dimensionless), see the class docstring.
        """
        uu = np.asarray(u, float).ravel()
        vv = np.asarray(v, float).ravel()
        if uu.shape != vv.shape:
            raise ReducerlabError(f"u, v: need the same length; got {uu.shape} and {vv.shape}")
        p2, n2 = self.gear.involute_points(u=uu)
        if self.flank == -1:
            p2 = p2 * np.array([1.0, -1.0])
            n2 = n2 * np.array([1.0, -1.0])
        zc = self.gear.face_width * (vv - 0.5)
        return np.column_stack([p2, zc]), np.column_stack([n2, np.zeros_like(zc)])

    def inside(self, points: Array) -> NDArray[np.bool_]:
        """Whether points (gear frame, (n, 3), m) lie within the tooth's radial extent
        (tip circle to root form circle) and face width."""
        g = self.gear
        p = np.atleast_2d(np.asarray(points, float))
        r = np.hypot(p[:, 0], p[:, 1])
        tol = 1e-9 * g.root_radius
        radial = (r >= g.tip_radius - tol) & (r <= g.form_radius + tol)
        return radial & (np.abs(p[:, 2]) <= 0.5 * g.face_width + tol)


@dataclass(frozen=True)
class InternalMeshPair:
    """A planet (external spur gear, gear A) inside a ring (internal gear, gear B) as a
    ``MeshPair`` of the tooth contact analysis (module docstring for the frames).

    Parameters
    ----------
    planet : SpurGear
        Gear A, with its profile shift ``x1``.
    ring : InternalGear
        Gear B, with its profile shift ``x2``; the same module and pressure angle.
    center_distance : float, optional
        Working centre distance ``a'`` (m); default the zero-backlash distance
        ``a' = m (z2 - z1) cos a / (2 cos a')``,
        ``inv a' = inv a + 2 (x2 - x1) tan a / (z2 - z1)`` (as
        :class:`~reducerlab.geometry.InternalGearPair`).
    modifications : PairModifications, optional
        Flank modifications of the planet (``a``) and the ring (``b``),
        ``contact.modifications``; default none.

    The mesh position ``phi`` is the planet's rotation (rad); the ring turns by
    ``phi2 = phase + phi z1 / z2``, the phase chosen so that at ``phi = 0`` flank +1 of
    planet tooth 0 touches flank -1 of ring tooth 0 (conjugate involutes, zero backlash
    on the drive side).

    Raises
    ------
    ReducerlabError
        Gears of different module or pressure angle, ``z2 - z1 < 1``, a centre distance
        below the zero-backlash one, a tip that meets the mating flank below its root
        form circle (involute interference), or a contact ratio below 1.
    """

    planet: SpurGear
    ring: InternalGear
    center_distance: float | None = None
    modifications: PairModifications = field(default_factory=PairModifications)

    def __post_init__(self) -> None:
        if not isinstance(self.modifications, PairModifications):
            raise ReducerlabError(
                "modifications: must be a PairModifications (contact.modifications); got "
                f"{type(self.modifications).__name__}"
            )
        if not isinstance(self.planet, SpurGear):
            raise ReducerlabError(f"planet: must be a SpurGear; got {type(self.planet).__name__}")
        if not isinstance(self.ring, InternalGear):
            raise ReducerlabError(f"ring: must be an InternalGear; got {type(self.ring).__name__}")
        p, r = self.planet, self.ring
        if not math.isclose(p.module, r.module, rel_tol=1e-12):
            raise ReducerlabError(f"ring.module: {r.module!r} m differs from the planet's")
        if not math.isclose(p.pressure_angle, r.pressure_angle, rel_tol=1e-12):
            raise ReducerlabError("ring.pressure_angle: differs from the planet's")
        if r.teeth <= p.teeth:
            raise ReducerlabError(f"ring.teeth: must exceed the planet's {p.teeth}; got {r.teeth}")
        a = self.center_distance
        if a is not None:
            if (
                isinstance(a, bool)
                or not isinstance(a, int | float)
                or not (math.isfinite(a) and a > r.base_radius - p.base_radius)
            ):
                raise ReducerlabError(
                    f"center_distance: must exceed r_b2 - r_b1 = "
                    f"{r.base_radius - p.base_radius:.6g} m; got {a!r}"
                )
            if a < self.zero_backlash_distance * (1 - 1e-12):
                raise ReducerlabError(
                    f"center_distance: {a:.9g} m is below the zero-backlash distance "
                    f"{self.zero_backlash_distance:.9g} m: the teeth would interfere"
                )
        s_a, s_e = self.path_of_contact
        if s_a < p.form_roll * (1 - 1e-12):
            raise ReducerlabError(
                "ring: its tip meets the planet below the planet's root form circle "
                f"(roll {s_a:.6g} < {p.form_roll:.6g} m): involute interference"
            )
        if s_e + self.line_of_centres_roll > r.form_roll * (1 + 1e-12):
            raise ReducerlabError(
                "planet: its tip meets the ring beyond the ring's root form circle (roll "
                f"{s_e + self.line_of_centres_roll:.6g} > {r.form_roll:.6g} m): involute "
                "interference"
            )
        if self.contact_ratio < 1.0:
            raise ReducerlabError(
                f"center_distance: the transverse contact ratio {self.contact_ratio:.4f} is below 1"
            )

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_khv(cls, gears: Any) -> InternalMeshPair:
        """The pair of a KHV design's gears (``drives.khv.Gears``, or a ``KHVDesign``
        whose ``gears`` it takes): planet ``SpurGear(z1, m, b, alpha, x1, h_a*)`` on the
        ISO 53 generating rack (dedendum 1.25 m, root fillet 0.38 m); ring
        ``InternalGear(z2, m, b, alpha, x2, h_a*)`` with the dedendum
        ``h_a* + RING_DEDENDUM_CLEARANCE`` and the root fillet ``RING_ROOT_FILLET``
        (docs/assumptions.md); zero-backlash centre distance."""
        g = getattr(gears, "gears", gears)
        for name in ("planet_teeth", "ring_teeth", "module", "face_width", "x1", "shift2"):
            if not hasattr(g, name):
                raise ReducerlabError(f"gears: a KHV design's gears need {name!r}")
        planet = SpurGear(int(g.planet_teeth), float(g.module), float(g.face_width),
                          pressure_angle=float(g.pressure_angle), shift=float(g.x1),
                          addendum=float(g.addendum))  # fmt: skip
        ring = InternalGear(int(g.ring_teeth), float(g.module), float(g.face_width),
                            pressure_angle=float(g.pressure_angle), shift=float(g.shift2),
                            addendum=float(g.addendum),
                            dedendum=float(g.addendum) + RING_DEDENDUM_CLEARANCE,
                            root_fillet=RING_ROOT_FILLET)  # fmt: skip
        return cls(planet, ring)

    # ------------------------------------------------------------------ geometry
    @property
    def zero_backlash_pressure_angle(self) -> float:
        """``a'`` of the zero-backlash mesh (rad):
        ``inv a' = inv a + 2 (x2 - x1) tan a / (z2 - z1)``."""
        p, r = self.planet, self.ring
        a = p.pressure_angle
        return inv_inverse(inv(a) + 2 * (r.shift - p.shift) * math.tan(a) / (r.teeth - p.teeth))

    @property
    def zero_backlash_distance(self) -> float:
        """``m (z2 - z1) cos a / (2 cos a')`` (m)."""
        p, r = self.planet, self.ring
        return (p.module * (r.teeth - p.teeth) * math.cos(p.pressure_angle)
                / (2 * math.cos(self.zero_backlash_pressure_angle)))  # fmt: skip

    @property
    def a(self) -> float:
        """Working centre distance (m)."""
        return self.zero_backlash_distance if self.center_distance is None else self.center_distance

    @property
    def working_pressure_angle(self) -> float:
        """``cos a_w = (r_b2 - r_b1) / a'`` (rad)."""
        return math.acos((self.ring.base_radius - self.planet.base_radius) / self.a)

    @property
    def line_of_centres_roll(self) -> float:
        """``a' sin a_w = T2 T1`` (m): the ring's roll length at ``T1``."""
        return self.a * math.sin(self.working_pressure_angle)

    @property
    def base_pitch(self) -> float:
        """``p_b = pi m cos a`` (m)."""
        return self.planet.base_pitch

    @property
    def path_of_contact(self) -> tuple[float, float]:
        """Distances from ``T1`` (m) where the contact starts (``A``: the ring's tip,
        ``xi_a2 - a' sin a_w``) and ends (``E``: the planet's tip, ``xi_a1``)."""
        return self.ring.tip_roll - self.line_of_centres_roll, self.planet.tip_roll

    @property
    def contact_ratio(self) -> float:
        """``eps_alpha = (xi_a1 - xi_a2 + a' sin a_w) / p_b`` (ISO 21771, internal)."""
        s_a, s_e = self.path_of_contact
        return (s_e - s_a) / self.base_pitch

    @property
    def working_pitch_radii(self) -> tuple[float, float]:
        """``r_w = r_b / cos a_w`` (m) of planet and ring."""
        c = math.cos(self.working_pressure_angle)
        return self.planet.base_radius / c, self.ring.base_radius / c

    @property
    def ring_center(self) -> Array:
        """``(-a', 0, 0)`` (m)."""
        return np.array([-self.a, 0.0, 0.0])

    def contact_roll(self, phi: float, tooth: int = 0) -> float:
        """Drive-side contact of tooth pair ``tooth`` at ``phi``: distance from ``T1``
        along the line of action (m), ``r_b1 (psi_b1 + phi + 2 pi k / z1 + a_w)``."""
        p = self.planet
        return p.base_radius * (p.base_half_angle + phi + tooth * p.pitch
                                + self.working_pressure_angle)  # fmt: skip

    def ring_angle(self, phi: float) -> float:
        """Ring rotation (rad) at the planet rotation ``phi``: the ring roll length of the
        contact, ``r_b2 (phi2 - tau_b2 + a_w)``, equals the planet's plus ``a' sin a_w``."""
        aw = self.working_pressure_angle
        s = self.contact_roll(phi) + self.line_of_centres_roll
        return s / self.ring.base_radius + self.ring.base_half_angle - aw

    def pitch_point_position(self, k: int = 0) -> float:
        """``phi`` (rad) at which tooth pair ``k`` touches at the pitch point."""
        p = self.planet
        aw = self.working_pressure_angle
        return math.tan(aw) - aw - p.base_half_angle - k * p.pitch

    def position_of(self, roll: float, k: int = 0) -> float:
        """``phi`` (rad) at which tooth pair ``k`` touches at distance ``roll`` (m) from
        ``T1``."""
        p = self.planet
        return (roll / p.base_radius - p.base_half_angle - self.working_pressure_angle
                - k * p.pitch)  # fmt: skip

    # ------------------------------------------------------------------ MeshPair protocol
    @functools.cached_property
    def flank_a(self) -> Flank:
        """Flank +1 of the planet (modified by ``modifications.a``)."""
        return modified(SpurFlank(self.planet, 1), self.modifications.a, "modifications.a")

    @functools.cached_property
    def flank_b(self) -> Flank:
        """Flank -1 of the ring (modified by ``modifications.b``)."""
        return modified(InternalFlank(self.ring, -1), self.modifications.b, "modifications.b")

    @property
    def unmodified(self) -> InternalMeshPair:
        """The same pair without flank modifications (the tooth compliance's pair)."""
        if self.modifications.none:
            return self
        return replace(self, modifications=PairModifications())

    @property
    def torque_ratio(self) -> float:
        """``T_B / T_A = z2 / z1``."""
        return self.ring.teeth / self.planet.teeth

    def tooth_angles(self, k: int) -> tuple[float, float]:
        """``(2 pi k / z1, 2 pi k / z2)`` (rad): planet tooth ``k`` meets ring tooth
        ``k``."""
        return 2 * math.pi * k / self.planet.teeth, 2 * math.pi * k / self.ring.teeth

    def poses(self, phi: float) -> tuple[GearPose, GearPose]:
        """Planet about the ``z`` axis, ring about the parallel axis through
        ``(-a', 0, 0)``, for the planet rotation ``phi`` (rad)."""
        phi = float(phi)
        if not math.isfinite(phi):
            raise ReducerlabError(f"phi: must be a finite angle; got {phi!r}")
        ez = np.array([0.0, 0.0, 1.0])
        return (GearPose(rot_z(phi), np.zeros(3), ez),
                GearPose(rot_z(self.ring_angle(phi)), self.ring_center, ez.copy()))  # fmt: skip

    # ------------------------------------------------------------------ compliance
    def tooth_compliances(
        self,
        *,
        material: Material = STEEL,
        grid: tuple[int, int] = (6, 9),
        tooth_size: float | None = None,
        body_size: float | None = None,
        planet_rim: float | None = None,
        ring_rim: float | None = None,
        stage: Stage | None = None,
        root_stress: bool = False,
    ) -> tuple[ToothCompliance, ToothCompliance]:
        """Bending compliances of planet (:func:`~reducerlab.contact.spur_pair.
        spur_tooth_compliance`, bore held) and ring (:func:`internal_tooth_compliance`,
        outer surface held), in this pair's tooth order (both ``direction = +1``); with
        ``root_stress`` each with its root-fillet stress influence."""
        kw = dict(material=material, grid=grid, tooth_size=tooth_size, body_size=body_size,
                  stage=stage, root_stress=root_stress)  # fmt: skip
        ca = spur_tooth_compliance(self.planet, 1, direction=1, rim=planet_rim, **kw)
        cb = internal_tooth_compliance(self.ring, -1, direction=1, rim=ring_rim, **kw)
        return ca, cb


def _held_dofs(basis, mesh) -> NDArray[np.int64]:
    """DOFs of the boundary facets on the rim's outer cylinder and the two cut faces."""
    return held_sector_dofs(basis, mesh, mesh.outer_radius, "rim")


def internal_tooth_compliance(
    gear: InternalGear,
    flank: int = -1,
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
    """Finite-element bending compliance of teeth ``-1, 0, 1`` of an internal gear.

    A sector of five teeth (``fe.internal_mesh.mesh_internal_sector``, teeth
    ``-2 ... 2``) is held on its rim's outer cylinder and its two radial cut faces;
    ``n_u x n_v`` load points on the flank of each modelled tooth, inset by the bump
    radius ``a = 2 tooth_size`` from the flank's edges, give the influence coefficients of
    ``contact.compliance.flank_influence`` (local half-space part removed), as
    :func:`~reducerlab.contact.spur_pair.spur_tooth_compliance` does for external gears.
    The work and memory are estimated first (``fe.internal_mesh.
    internal_sector_estimate``) and refused beyond their bounds.

    Parameters
    ----------
    gear : InternalGear
    flank : {+1, -1}
        The loaded flank (-1: driven by a planet with a positive torque).
    material : Material
    grid : (int, int)
        Load points along the profile and across the face on each tooth (>= 2 each).
    tooth_size, body_size : float, optional
        Element sizes (m) on the teeth and one tooth depth outside the root circle;
        default ``0.3 m`` and ``m``.
    rim : float, optional
        Rim thickness outside the root circle (m); default ``3.5 m``.
    direction : {+1, -1}
        Tooth block ``k`` is gear tooth ``direction * k``: +1 for the ring of an
        :class:`InternalMeshPair`.
    stage : callable, optional
        ``stage(text)`` at each step.
    root_stress : bool
        Also the stress influence of every load bump at the root-fillet nodes of the
        three teeth (``contact.rootstress``): the boundary facets between the root form
        circle and the root circle (outside the form circle: the ring's fillets and root
        land), side +1 the loaded flank's fillet (its tension side); the same
        factorisation, one backward substitution more, the dense columns counted twice
        in the estimate.
    teeth : sequence of int
        The modelled teeth, ``-n ... n`` (default ``-1, 0, 1``), on a sector of ``2 n +
        3`` teeth: ``-2 ... 2`` on seven checks ``contact.compliance.extend_teeth``
        (``benchmarks/khv_sharing.py``); without ``root_stress``.

    Returns
    -------
    ToothCompliance
        Teeth ``(-1, 0, 1)``, flank parameters of :class:`InternalFlank`, m/N; with
        ``root_stress`` its ``fillet``.

    Raises
    ------
    ReducerlabError
        A bad argument (named), a flank too short for the load bumps, or a model
        beyond the memory or DOF bound (``BudgetError``).
    """
    from ..fe.gear_mesh import MeshSizes
    from ..fe.internal_mesh import internal_sector_estimate, mesh_internal_sector

    if not isinstance(gear, InternalGear):
        raise ReducerlabError(f"gear: must be an InternalGear; got {type(gear).__name__}")
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
    n_u, n_v, ts, bs = model_sizes(grid, gear.module, tooth_size, body_size)
    mesh_sizes = MeshSizes(ts, bs)
    columns = len(modelled) * n_u * n_v * (2 if root_stress else 1)
    internal_sector_estimate(
        gear, sector, rim, mesh_sizes, dense_columns=columns,
        what=f"contact: the tooth compliance of the internal gear (z = {gear.teeth})",
    ).check()  # fmt: skip
    say = stage or (lambda _s: None)
    a = 2.0 * ts  # bump radius: two tooth elements
    iflank = InternalFlank(gear, flank)
    u_nodes, v_nodes = load_nodes(iflank, a, n_u, n_v)
    say(f"meshing a {sector}-tooth internal sector")
    mesh = mesh_internal_sector(gear, sector, rim=rim, sizes=mesh_sizes)
    uu, vv = np.meshgrid(u_nodes, v_nodes, indexing="ij")
    P0, N0 = iflank.evaluate(uu.ravel(), vv.ravel())
    angles = [direction * gear.pitch * k for k in modelled]
    fillet = fillet_facets(mesh, flank, direction) if root_stress else None
    out = flank_influence(mesh.skfem(), lambda basis: _held_dofs(basis, mesh), P0, N0,
                          angles, a, material, stage=say,
                          name=f"internal gear (z = {gear.teeth})", fillet=fillet)  # fmt: skip
    inf = fillet_influence(gear, out[2], direction) if root_stress else None
    return ToothCompliance(u_nodes, v_nodes, modelled, out[0], out[1], a, inf)


def tooth_pair_clearances(
    pair: InternalMeshPair,
    teeth: Sequence[int],
    positions: int = 24,
    points: int = 401,
    v: float = 0.5,
    rolls: Sequence[float] | None = None,
) -> tuple[Array, Array]:
    """Unloaded drive-flank clearances of tooth pairs ``teeth`` over one mesh cycle
    (issue 30): how far the ring must turn, from the conjugate position of pair 0,
    before planet tooth ``k`` touches ring tooth ``k`` on the drive flanks.

    At each of ``positions`` mesh positions (pair 0's contact stepped by ``p_b /
    positions`` from the path's start ``A``), ``points`` points of the planet's drive
    flank at face parameter ``v`` are traced to the ring's drive flank
    (:func:`~reducerlab.contact.flanks.separations`: distance ``t`` along the planet's
    normal and its lever ``lam`` for a ring rotation); the ring rotation that closes a
    point is ``t / lam`` to first order (``lam`` of the sign of the loaded contact's,
    pair 0's), repeated with the ring turned by it until the step is below 1e-6 of the
    rotation; the pair's clearance is the smallest over its points, as arc length
    ``r_b2 psi`` on the ring's base circle (m; the transmission-error unit of the
    contact analysis). ``inf`` where no point of the pair faces the other's flank.
    Rigid teeth, the pair's flank modifications included; the coast flanks (in contact
    at zero backlash) are not looked at. ``rolls`` (m from ``T1``, pair 0's contact)
    gives the positions instead of ``positions``.

    Returns
    -------
    rolls : ndarray, shape (positions,)
        Pair 0's contact, distance from ``T1`` along the line of action (m).
    clearance : ndarray, shape (positions, len(teeth))
        ``r_b2 psi_k`` (m).
    """
    from .flanks import separations

    if isinstance(positions, bool) or not isinstance(positions, int) or not 1 <= positions <= 720:
        raise ReducerlabError(f"positions: must be an integer in [1, 720]; got {positions!r}")
    if isinstance(points, bool) or not isinstance(points, int) or not 3 <= points <= 20001:
        raise ReducerlabError(f"points: must be an integer in [3, 20001]; got {points!r}")
    ks = [int(k) for k in teeth]
    if not ks or any(abs(k) > pair.planet.teeth for k in ks):
        raise ReducerlabError(
            f"teeth: give tooth pairs within +-{pair.planet.teeth}; got {list(teeth)!r}"
        )
    s_a, s_e = pair.path_of_contact
    if rolls is None:
        rolls = s_a + pair.base_pitch * np.arange(positions) / positions
    else:
        rolls = np.atleast_1d(np.asarray(rolls, float))
        if rolls.ndim != 1 or not rolls.size or not np.all(np.isfinite(rolls)):
            raise ReducerlabError("rolls: must be a 1-D array of finite distances (m)")
    u = np.linspace(0.0, 1.0, points)
    vv = np.full_like(u, float(v))
    mid = separations(pair, pair.position_of(0.5 * (s_a + s_e)), 0, [0.5], [float(v)])
    sign = float(np.sign(mid.lever[0]))

    def closing(p: Any, phi: float, k: int) -> float:
        s = separations(p, phi, k, u, vv)
        lam = sign * s.lever
        ok = np.isfinite(s.distance) & (lam > 0)
        return float(np.min(s.distance[ok] / lam[ok])) if ok.any() else math.inf

    out = np.full((len(rolls), len(ks)), np.inf)
    for i, r in enumerate(rolls):
        phi = pair.position_of(float(r))
        for j, k in enumerate(ks):
            psi = closing(pair, phi, k)
            for _ in range(8):  # 2-4 steps
                if not math.isfinite(psi) or psi == 0.0:
                    break
                step = closing(_RingTurned(pair, sign * psi), phi, k)
                if not math.isfinite(step):
                    break
                psi += step
                if abs(step) <= 1e-6 * abs(psi) + 1e-15:
                    break
            out[i, j] = psi * pair.ring.base_radius
    return rolls, out


def loaded_pairs(
    teeth: Sequence[int],
    clearance: Array,
    approach: float,
    margin: float = 1.25,
    modelled: int = MODELLED_PAIRS,
) -> tuple[int, ...]:
    """The tooth pairs a load sharing analysis must examine (issue 30): pair 0 and every
    pair whose least unloaded clearance over the mesh cycle (:func:`tooth_pair_clearances`,
    ``r_b2 psi``, m) lies below ``margin`` times the loaded approach ``approach`` (the
    largest loaded transmission error ``r_b2 (psi_0 + psi)`` of the largest torque, m).

    Rigid teeth carry load on pair ``k`` only once the ring has turned through its
    clearance; the elastic teeth add their bending under the neighbours' loads, a
    fraction of the approach (``margin`` covers it, as ``contact.ltca.MARGIN`` does for
    the contact grid).

    Raises
    ------
    ReducerlabError
        A pair that would close beyond ``+-modelled`` (named with its clearance and the
        approach), which the analysis cannot model: never dropped silently.
    """
    c = np.asarray(clearance, float)
    ks = [int(k) for k in teeth]
    if c.ndim != 2 or c.shape[1] != len(ks):
        raise ReducerlabError(f"clearance: needs one column per tooth pair; got {c.shape}")
    if not (math.isfinite(approach) and approach >= 0):
        raise ReducerlabError(f"approach: must be a length >= 0 (m); got {approach!r}")
    if not (math.isfinite(margin) and margin >= 1):
        raise ReducerlabError(f"margin: must be a factor >= 1; got {margin!r}")
    least = np.min(np.where(np.isfinite(c), c, np.inf), axis=0)
    chosen = {0} | {k for k, m in zip(ks, least, strict=True) if m < margin * approach}
    far = sorted(k for k in chosen if abs(k) > modelled)
    if far:
        k = far[0]
        c_k = float(least[ks.index(k)])
        if c_k <= 0:
            raise ReducerlabError(
                f"design: tooth pair {k:+d} overlaps the ring's drive flank by "
                f"{-c_k * 1e6:.3g} um unloaded (rigid teeth: an interference of the tips "
                f"passing), beyond the pairs -{modelled} ... {modelled} the load sharing "
                "models; change the shift coefficients or the tooth numbers"
            )
        raise ReducerlabError(
            f"torques: at the largest torque the teeth approach by {approach * 1e6:.3g} um; "
            f"tooth pair {k:+d} is only {c_k * 1e6:.3g} um apart (within the "
            f"margin x{margin:g}) and would close, but the load sharing models pairs "
            f"-{modelled} ... {modelled} only (beyond: tip edge on tip edge, outside the "
            "flank contact model); lower the largest torque"
        )
    return tuple(sorted(chosen))


class _RingTurned:
    """``pair`` with the ring turned by ``psi`` (rad) further about its axis (the
    tooth angles of gear B shifted; everything else delegated)."""

    def __init__(self, pair: InternalMeshPair, psi: float) -> None:
        self._pair, self._psi = pair, psi

    def __getattr__(self, name: str) -> Any:
        return getattr(self._pair, name)

    def tooth_angles(self, k: int) -> tuple[float, float]:
        a, b = self._pair.tooth_angles(k)
        return a, b + self._psi
