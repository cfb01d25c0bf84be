"""The gear bodies of a nutation design taken together (paper 000 §4): the element sizes
of a body's mesh from the sizes a user gives, and the finite-element modes of every gear
body as the component modes that the resonance check compares with the excitations and
the system modes (paper 000 Table 5)."""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping
from typing import Any

from ..fe.gear_mesh import MeshSizes
from .body_modal import body_estimate, body_modal
from .components import ComponentModes

__all__ = ["body_inputs", "body_mesh_sizes", "contact_inputs", "gear_body_modes"]


def body_inputs(design: Mapping[str, Any], attrs: Mapping[str, Any]) -> list[str] | None:
    """The design fields that one gear body's modes depend on (the rule of ``body-modal``
    results in :data:`reducerlab.inputs.RULES`): the drive type and sides, the tooth
    generation of the gear's pair (teeth and mean radii of both gears, helix and
    pressure angles, the nutation angle, or every gear's teeth and mean radius where the
    angle follows from them), the ``[surface]`` table, the ``[material]`` and the gear's
    own ``[gearN.blank]``. None (the whole design) for a result of another drive type or
    without a gear number.

    Parameters
    ----------
    design : mapping
        The design's SI dump.
    attrs : mapping
        The result's attributes (``gear``).
    """
    gear = attrs.get("gear")
    try:
        gear = int(gear)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None
    if design.get("type") != "nutation" or gear not in range(1, 5):
        return None
    return [*_pair_generation(design, (gear + 1) // 2), f"gear{gear}.blank"]


def _pair_generation(design: Mapping[str, Any], pair: int) -> list[str]:
    """The fields that generate pair ``pair``'s teeth: type and sides, helix, pressure
    and nutation angles, ``[surface]``, the elastic constants and density of
    ``[material]`` (not its rating limits), and the teeth and mean radii of both gears
    (of every gear where the nutation angle follows from them)."""
    free = design.get("nutation_angle") is None and design.get("sides") == "double"
    gears = range(1, 5) if free else (2 * pair - 1, 2 * pair)
    return [
        "type", "sides", "helix_angle", "normal_pressure_angle", "nutation_angle",
        "surface", "material.youngs_modulus", "material.poisson_ratio", "material.density",
        *(f"gear{k}.{f}" for k in gears for f in ("teeth", "mean_radius")),
    ]  # fmt: skip


def contact_inputs(design: Mapping[str, Any], attrs: Mapping[str, Any]) -> list[str] | None:
    """The design fields a loaded-contact result of one gear pair depends on (the rule
    of ``contact`` results in :data:`reducerlab.inputs.RULES`): the tooth generation of
    the pair (as for :func:`body_inputs`, without the blanks: the tooth compliance
    models hold teeth and rim only), the ``[surface]`` table and the ``[material]``,
    the pair's flank modifications (and the design load when the crowned layout is on).
    Not the masses, supports, meshes or speeds: a changed damping or stiffness of the
    lumped model does not make the contact of the same teeth another result. The load,
    grid and misalignment are the result's own attributes. A KHV design's internal pair:
    ``[gears]`` and ``[material]`` (and the load with a crowned layout). A ``gear_pair``:
    each gear's ``teeth``, ``shift`` and ``modifications``, ``[mesh]``'s tooth geometry
    (module, pressure angle, face width, rack, ``flank_modifications``) and
    ``[material]`` (and the load with a crowned layout). None (the whole
    design) for a result of another drive type or without a pair number.

    Parameters
    ----------
    design : mapping
        The design's SI dump.
    attrs : mapping
        The result's attributes (``pair``).
    """
    try:
        pair = int(attrs.get("pair"))  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None
    if design.get("type") == "khv" and pair == 1:
        # the internal pair's teeth, modifications and material ([gears], [material]);
        # a crowned layout is sized by the design load (the output torque, or the
        # output power at the speed)
        mods = []
        if (design.get("gears") or {}).get("flank_modifications") == "crowned":
            mods = ["load_torque", "output_power", "input_speed"]
        return ["gears", "material", *mods]
    if design.get("type") == "gear_pair" and pair == 1:
        # the spur pair's teeth (drives.gear_pair.GearPairDesign.spur_pair), their
        # modifications and material; the crowned layout's load (a torque, or a power
        # at the speed)
        mesh = design.get("mesh") or {}
        mods = []
        if mesh.get("flank_modifications") == "crowned":
            mods = ["operating.torque", "operating.power", "operating.speed"]
        each = ("teeth", "shift", "modifications")
        gears = [f"{g}.{f}" for g in ("pinion", "gear") for f in each]
        rack = ("module", "pressure_angle", "face_width", "addendum", "dedendum", "root_fillet",
                "flank_modifications")  # fmt: skip
        return [*gears, *(f"mesh.{f}" for f in rack), "material", *mods]
    if design.get("type") != "nutation" or pair not in (1, 2):
        return None
    # the flank modifications: each gear's table, and the design load that sizes the
    # crowned layout (surface.flank_modifications is in [surface])
    mods = [f"gear{k}.modifications" for k in (2 * pair - 1, 2 * pair)]
    if (design.get("surface") or {}).get("flank_modifications") == "crowned":
        mods += ["output_torque", "output_power"]
    return [*_pair_generation(design, pair), *mods]


def body_mesh_sizes(
    design: Any, gear: int, tooth: float | None = None, body: float | None = None
) -> MeshSizes | None:
    """The element sizes of gear ``gear``'s mesh with the sizes given (m), or None for
    the default mesh when neither is given.

    A size not given is the default (:meth:`~reducerlab.fe.gear_mesh.MeshSizes.default`
    of the gear's normal module m_n: ``0.6 m_n`` in the teeth, ``1.5 m_n`` in the
    blank); a default blank size is never finer than the teeth.

    Parameters
    ----------
    design : NutationDesign
        A design with tooth surfaces (``[surface]`` table).
    gear : int
        The gear, 1..``design.gear_count``.
    tooth, body : float, optional
        Element size in the teeth and in the blank (m).

    Returns
    -------
    MeshSizes or None
    """
    if tooth is None and body is None:
        return None
    crown, _ = design.tooth_generation(gear)
    default = MeshSizes.default(crown.profile.module)
    t = default.tooth if tooth is None else tooth
    b = default.body if body is None else body
    return MeshSizes(t, max(b, t) if body is None else b)


def gear_body_modes(
    design: Any, skip: Collection[str] = (), stage: Callable[[str], None] | None = None
) -> list[ComponentModes]:
    """The free-free modes of every gear body of ``design`` (default mesh, no
    convergence study), as :class:`~reducerlab.analysis.components.ComponentModes`
    labelled ``"gear N"``.

    Parameters
    ----------
    design : NutationDesign
        A design with tooth surfaces (see
        :func:`~reducerlab.analysis.body_modal.check_bodies`).
    skip : collection of str
        Labels of the gears whose modes are given already (``"gear 2"``): not computed.
    stage : callable, optional
        ``stage(description)`` at each stage of each gear (``"gear 1: meshing"``).

    Returns
    -------
    list of ComponentModes
        One per gear computed, in gear order.
    """
    gears = [g for g in range(1, design.gear_count + 1) if f"gear {g}" not in skip]
    for g in gears:  # every body's budget before the first is meshed
        body_estimate(design, g).check()
    out = []
    for g in gears:
        say = None if stage is None else (lambda s, g=g: stage(f"gear {g}: {s}"))
        res = body_modal(design, g, convergence=False, stage=say)
        out.append(ComponentModes.from_body_modal(res))
    return out
