"""What the loaded contact analysis needs to know of a design's gear pair.

``contact_analysis`` (``analysis.contact``) and ``te_sweep`` (``analysis.te_sweep``)
run the same loaded tooth contact analysis (``contact.ltca``) on two kinds of pair:

* a **nutation** pair (``nutation`` designs with ``[surface]``, papers 001 and 000): the
  external bevel gear (A) against the nutating internal gear (B), both crown-generated
  (``contact.flanks.NutationPair``); the mesh lever of the lumped model is
  ``a_y r_mB = cos(beta) cos(alpha_n) r_mB`` (paper 000 Eq. 2-4), the TE length is
  taken at B's mean radius ``r_mB``;
* a **spur** pair (``gear_pair`` designs with ``mesh.face_width``): the pinion (A)
  against the wheel (B) (``contact.spur_pair.SpurMeshPair``); the lever of the mesh's
  line of action on the wheel is its base radius ``r_b2`` (the lumped ``gear_pair``
  model's mesh, ``drives.gear_pair``: ``delta = ... + r_bg rz_g``), and the TE is
  taken along the line of action, ``r_b2 psi`` (the usual linear TE of spur gears).

:func:`pair_setup` answers both as one :class:`PairSetup`: the mesh pair, its load
radius, mesh cycle, levers, mesh frequency and how to build and estimate its
finite-element tooth compliance. Material: the design's ``[material]`` where it has
one, else steel (``fe.elasticity.STEEL``, E = 206 GPa, nu = 0.29, ISO 6336-1's
``E_st``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..budget import Estimate
from ..design import Design
from ..errors import ReducerlabError

__all__ = [
    "PairSetup",
    "check_misalignment",
    "contact_pair",
    "pair_setup",
    "spur_compliance_estimate",
]

Stage = Callable[[str], None]


@dataclass(frozen=True)
class PairSetup:
    """One gear pair of a design, as the loaded contact analysis sees it.

    Attributes
    ----------
    mesh_pair : MeshPair
        ``contact.flanks.NutationPair``, ``contact.spur_pair.SpurMeshPair`` or
        ``contact.internal_pair.InternalMeshPair`` (KHV: planet A, ring B).
    kind : {"nutation", "spur", "internal"}
    module : float
        Normal module (m).
    material : fe.Material
    E_star : float
        Combined modulus of the two gears (Pa).
    load_radius : float
        Radius of gear A on which its torque gives the tangential force (m):
        the external gear's mean radius, the pinion's reference pitch radius.
    pitch : float
        Mesh cycle: gear A's angular pitch ``2 pi / z_A`` (rad).
    start : float
        Gear A's rotation at position 0 (rad): tooth pair 0 at mid-mesh (nutation:
        its mean pitch point on the pitch line; spur: at the pitch point; internal:
        half a base pitch before the middle of the path of contact, so that over the
        cycle pair 0 runs through the middle and only pairs -1, 0, 1 mesh while
        ``eps_alpha < 2``: the KHV pair's pitch point lies in its second double-contact
        zone, 1.18 of 1.23 base pitches from the path's start, where pair -2 meshes
        within a pitch, issue 30).
    arm : float
        Lever of the lumped model's mesh on gear B (m): ``k = T_B / (arm^2 psi)``.
    te_radius : float
        Radius on gear B at which the rotation ``psi`` is given as a length (m).
    mesh_frequency : float
        Tooth-mesh frequency at the design's operating speed (Hz); 0 at rest.
    profile : str
        Tooth profile (``involute`` for spur gears).
    teeth : (int, int)
        Teeth of gears A and B.
    gears : (str, str)
        Names of gears A and B in the design.
    """

    mesh_pair: Any
    kind: str
    module: float
    material: Any
    E_star: float
    load_radius: float
    pitch: float
    start: float
    arm: float
    te_radius: float
    mesh_frequency: float
    profile: str
    teeth: tuple[int, int]
    gears: tuple[str, str]

    def compliance_estimate(self, tooth_size: float | None, root_stress: bool = False) -> Estimate:
        """The work and memory of both gears' finite-element tooth models (of the
        unmodified teeth: the modifications do not change the compliance), with the
        fillet stress influence when ``root_stress``."""
        if self.kind == "spur":
            p = self.mesh_pair.pair
            gear = max((p.pinion, p.wheel), key=lambda g: g.tip_radius)
            return spur_compliance_estimate(gear, tooth_size)
        if self.kind == "internal":
            return _internal_estimate(self.mesh_pair, tooth_size, root_stress)
        from ..contact.compliance import compliance_estimate

        return compliance_estimate(self.mesh_pair.unmodified, tooth_size, root_stress=root_stress)

    def compliances(
        self, tooth_size: float | None, say: Stage, pool: Any, root_stress: bool = False
    ) -> tuple[Any, Any]:
        """Both gears' tooth compliances (gear A, gear B): nutation pairs at once on
        ``pool`` where memory allows (``analysis.contact_workers``); spur pairs in this
        process, one finite-element model when pinion and wheel are equal; with the
        fillet stress influence when ``root_stress`` (``contact.rootstress``)."""
        if self.kind == "internal":
            say("finite-element compliance of the planet's and the ring's teeth")
            return self.mesh_pair.unmodified.tooth_compliances(
                material=self.material, tooth_size=tooth_size, stage=say,
                root_stress=root_stress,
            )  # fmt: skip
        if self.kind == "spur":
            say("finite-element compliance of the pinion's and the wheel's teeth")
            return self.mesh_pair.unmodified.tooth_compliances(
                material=self.material, tooth_size=tooth_size, stage=say,
                root_stress=root_stress,
            )  # fmt: skip
        from .contact_workers import tooth_compliances

        return tooth_compliances(
            self.mesh_pair.unmodified, self.material, tooth_size, say, pool, root_stress
        )


def contact_pair(design: Any, pair: int = 1, *, profile: str | None = None,
                 misalignment: Any = None, flank: int = 1,
                 modifications: Any = None) -> Any:  # fmt: skip
    """The :class:`~reducerlab.contact.flanks.NutationPair` of pair ``pair`` (1 or 2):
    its external gear (2 or 4) and its nutating internal gear (1 or 3), with the flank
    modifications ``modifications`` (``contact.modifications.PairModifications``;
    default the design's, ``analysis.flank_modifications.design_modifications``)."""
    from ..contact.flanks import Misalignment, NutationPair
    from .flank_modifications import with_modifications

    if not (isinstance(design, Design) and design.has_tooth_surfaces):
        raise ReducerlabError(
            "surface: the design has no [surface] table (profile, face_width), which the "
            "contact analysis needs to generate the teeth; see examples/nutation_surface.toml"
        )
    pairs = design.gear_count // 2
    if isinstance(pair, bool) or pair not in range(1, pairs + 1):
        raise ReducerlabError(
            f"pair: must be 1..{pairs} for a {design.sides}-sided drive; got {pair!r}"
        )
    misalignment = misalignment or Misalignment()
    check_misalignment(misalignment, design.surface_module(2 * pair))
    crown, ext = design.tooth_generation(2 * pair, profile)
    _, internal = design.tooth_generation(2 * pair - 1, profile)
    plain = NutationPair(crown, ext, internal, flank, misalignment)
    return with_modifications(plain, design, pair, modifications)


#: the command-line option of each length of a misalignment
_MISALIGNMENT_OPTIONS = {"axial_a": "--axial-external", "axial_b": "--axial-internal",
                         "offset": "--offset"}  # fmt: skip


def check_misalignment(misalignment: Any, module: float) -> None:
    """Refuse a misalignment whose shifts are not assembly errors.

    Each shift (``axial_a``, ``axial_b``, ``offset``, m) must lie within one normal
    module ``module`` (m) of the nominal place, as the shaft angle's error lies within
    2 deg (:class:`~reducerlab.contact.flanks.Misalignment`): a shift of a whole module
    moves the flanks by about the working depth of the teeth (2 modules) times the sine
    of the pitch cone or pressure angle, so beyond it the teeth are out of mesh or
    driven into one another, and the contact grid would search whole flanks for minutes.

    Raises
    ------
    ReducerlabError
        Naming the field, its option, the shift and the bound.
    """
    for name, option in _MISALIGNMENT_OPTIONS.items():
        v = getattr(misalignment, name)
        if abs(v) > module:
            raise ReducerlabError(
                f"misalignment.{name} ({option}): must be within +-{module * 1e3:.4g} mm (one "
                "normal module: an assembly error; a larger shift takes the teeth out of mesh "
                f"or into one another); got {v * 1e3:.4g} mm"
            )


def _material(design: Any) -> Any:
    """The design's ``[material]`` as an ``fe.Material``, else steel."""
    from ..fe import Material
    from ..fe.elasticity import STEEL

    mat = getattr(design, "material", None)
    if mat is None:
        return STEEL
    # the gear_pair's and khv's [material] (the rating's) has no density: the contact is
    # static, so the density only fills the FE material
    return Material(mat.youngs_modulus, mat.poisson_ratio, getattr(mat, "density", STEEL.rho))


def pair_setup(
    design: Any,
    pair: int = 1,
    *,
    profile: str | None = None,
    misalignment: Any = None,
    modifications: Any = None,
) -> PairSetup:
    """The :class:`PairSetup` of pair ``pair`` of ``design`` (a nutation design with
    ``[surface]``, or a ``gear_pair`` design with ``mesh.face_width``), with the flank
    modifications ``modifications`` (``contact.modifications.PairModifications``;
    default the design's, ``analysis.flank_modifications``).

    Raises
    ------
    ReducerlabError
        A design without tooth geometry, a pair number out of range, a profile other
        than involute or a misalignment for a spur pair (named by field).
    """
    from ..contact.halfspace import combined_modulus
    from ..drives.gear_pair import GearPairDesign

    if isinstance(design, GearPairDesign):
        return _spur_setup(design, pair, profile, misalignment, modifications)
    if getattr(design, "type", None) == "khv":
        return _internal_setup(design, pair, profile, misalignment, modifications)
    mp = contact_pair(design, pair, profile=profile, misalignment=misalignment,
                      modifications=modifications)  # fmt: skip
    material = _material(design)
    E_star = combined_modulus(material.E, material.nu, material.E, material.nu)
    external = getattr(design, f"gear{2 * pair}")
    internal = getattr(design, f"gear{2 * pair - 1}")
    a_y = math.cos(design.helix_angle) * math.cos(design.normal_pressure_angle)
    kin = design.kinematics()
    f_mesh = list(kin.mesh_frequencies(design.operating_speed).values())[pair - 1]
    return PairSetup(
        mp, "nutation", mp.crown.profile.module, material, E_star, external.mean_radius,
        2 * math.pi / mp.external.teeth, 0.0, a_y * internal.mean_radius,
        internal.mean_radius, float(f_mesh), profile or design.surface.profile,
        (mp.external.teeth, mp.internal.teeth), (f"gear{2 * pair}", f"gear{2 * pair - 1}"),
    )  # fmt: skip


def _spur_setup(
    design: Any, pair: int, profile: str | None, misalignment: Any, modifications: Any
) -> PairSetup:
    from ..contact.halfspace import combined_modulus
    from .flank_modifications import spur_mesh_pair

    if isinstance(pair, bool) or pair != 1:
        raise ReducerlabError(f"pair: a gear_pair design has one pair (1); got {pair!r}")
    if profile not in (None, "involute"):
        raise ReducerlabError(
            f"profile: a gear_pair design has involute teeth (ISO 53 rack); got {profile!r}"
        )
    if misalignment is not None:
        raise ReducerlabError(
            "misalignment: not available for a spur gear_pair (the parallel-axis pair is "
            "analysed at its nominal centre distance)"
        )
    mp = spur_mesh_pair(design, modifications)  # DesignError naming the field
    sp = mp.pair
    material = _material(design)
    E_star = combined_modulus(material.E, material.nu, material.E, material.nu)
    speed = design.operating_speed
    f_mesh = design.kinematics().mesh_frequencies(speed)["mesh"] if speed else 0.0
    return PairSetup(
        mp, "spur", design.mesh.module, material, E_star, sp.pinion.reference_radius,
        sp.pinion.pitch, mp.pitch_point_position(0), sp.wheel.base_radius,
        sp.wheel.base_radius, float(f_mesh), "involute",
        (sp.pinion.teeth, sp.wheel.teeth), ("pinion", "gear"),
    )  # fmt: skip


def _internal_setup(
    design: Any, pair: int, profile: str | None, misalignment: Any, modifications: Any
) -> PairSetup:
    """The KHV drive's internal pair: planet = gear A, ring = gear B (issue 29/30)."""
    from ..contact.halfspace import combined_modulus
    from .flank_modifications import khv_mesh_pair

    if isinstance(pair, bool) or pair != 1:
        raise ReducerlabError(f"pair: a khv design has one internal pair (1); got {pair!r}")
    if profile not in (None, "involute"):
        raise ReducerlabError(f"profile: a khv design has involute teeth; got {profile!r}")
    if misalignment is not None:
        raise ReducerlabError(
            "misalignment: not available for the KHV internal pair (analysed at its "
            "zero-backlash centre distance)"
        )
    mp = khv_mesh_pair(design, modifications)
    s_a, s_e = mp.path_of_contact
    start = mp.position_of(0.5 * (s_a + s_e) - 0.5 * mp.base_pitch)
    material = _material(design)
    E_star = combined_modulus(material.E, material.nu, material.E, material.nu)
    speed = design.operating_speed
    f_mesh = sum(design.kinematics().mesh_frequencies(speed).values()) if speed else 0.0
    return PairSetup(
        mp, "internal", design.gears.module, material, E_star, mp.planet.reference_radius,
        mp.planet.pitch, start, mp.ring.base_radius,
        mp.ring.base_radius, float(f_mesh), "involute",
        (mp.planet.teeth, mp.ring.teeth), ("planet V", "ring K"),
    )  # fmt: skip


def _internal_estimate(mp: Any, tooth_size: float | None, root_stress: bool = False) -> Estimate:
    """The larger of the planet's and the ring's FE tooth models (the ring's sector is
    the larger body: its rim); ``root_stress``: the ring's dense columns twice (the
    displacements of the loads too)."""
    from ..contact.compliance import TEETH
    from ..contact.spur_pair import SECTOR_TEETH, model_sizes
    from ..fe.gear_mesh import MeshSizes
    from ..fe.internal_mesh import internal_sector_estimate

    n_u, n_v, ts, bs = model_sizes((6, 9), mp.ring.module, tooth_size, None)
    ring = internal_sector_estimate(
        mp.ring, SECTOR_TEETH, None, MeshSizes(ts, bs),
        dense_columns=len(TEETH) * n_u * n_v * (2 if root_stress else 1),
        what=f"contact: the tooth compliance of the ring (z = {mp.ring.teeth})",
    )  # fmt: skip
    planet = spur_compliance_estimate(mp.planet, tooth_size)
    return max((ring, planet), key=lambda e: e.memory)


def spur_compliance_estimate(gear: Any, tooth_size: float | None = None) -> Estimate:
    """The tetrahedra, DOFs and memory of the finite-element tooth model of a spur gear
    (``contact.spur_pair.spur_tooth_compliance``: a sector of ``SECTOR_TEETH`` teeth on
    a rim of 3.5 m, tooth elements ``tooth_size`` (default 0.3 m) graded to ``m`` one
    tooth depth below the root circle), from the volumes in cubes of the local element
    size and the constants of ``fe.gear_mesh.mesh_estimate`` (milliseconds).
    Work: DOFs, bounded by ``fe.gear_mesh.MAX_DOFS``."""
    from ..contact.compliance import TEETH
    from ..contact.spur_pair import SECTOR_TEETH
    from ..fe.gear_mesh import BYTES_PER_DOF, MAX_DOFS, NODES_PER_TET, TETS_PER_CUBE

    m = gear.module
    a = 0.3 * m if tooth_size is None else float(tooth_size)
    if not (math.isfinite(a) and a > 0):
        raise ReducerlabError(f"tooth_size: must be a length > 0 (m); got {tooth_size!r}")
    b = max(m, a)
    share = SECTOR_TEETH / gear.teeth
    rf, ra = gear.root_radius, gear.tip_radius
    depth = ra - rf
    cubes = math.pi * (ra**2 - rf**2) * gear.face_width * share / a**3
    edges = np.linspace(max(rf - 3.5 * m, 0.05 * rf), rf, 33)
    for r0, r1 in itertools.pairwise(edges):
        s = a + (b - a) * min(1.0, (rf - 0.5 * (r0 + r1)) / depth)
        cubes += math.pi * (r1**2 - r0**2) * gear.face_width * share / s**3
    dofs = 3.0 * NODES_PER_TET * TETS_PER_CUBE * cubes
    memory = BYTES_PER_DOF * dofs + 3 * 8.0 * dofs * len(TEETH) * 6 * 9
    return Estimate(
        f"contact: the tooth compliance of the spur gear (z = {gear.teeth}): a mesh of about "
        f"{TETS_PER_CUBE * cubes:.3g} quadratic tetrahedra ({a * 1e3:.3g} mm in the teeth)",
        memory, dofs, "DOFs", MAX_DOFS, "the tooth element size (--tooth-size, tooth_size=)",
    )  # fmt: skip
