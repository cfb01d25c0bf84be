"""A design's flank modifications as the contact analysis takes them.

:func:`design_modifications` reads a gear pair's ``modifications`` tables and the
``flank_modifications`` switch of a nutation (``[surface]``), spur gear pair (``[mesh]``)
or KHV design (``[gears]``) and returns the
:class:`~reducerlab.contact.modifications.PairModifications` of the pair's two loaded
flanks: a gear's own table as given, else the default crowned layout
(:func:`~reducerlab.contact.modifications.crowned_layout`) at the design load when the
switch says ``"crowned"``, else none. :func:`spur_mesh_pair` and :func:`khv_mesh_pair`
are the spur and KHV designs' mesh pairs with them.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ..contact.modifications import (
    NONE,
    FlankCoordinates,
    FlankModification,
    PairModifications,
    crowned_layout,
    profile_corners,
    profile_transition,
)
from ..design import Design
from ..errors import DesignError, ReducerlabError

__all__ = [
    "checked",
    "design_force",
    "design_modifications",
    "khv_mesh_pair",
    "pair_fields",
    "spur_mesh_pair",
    "with_modifications",
]


def pair_fields(design: Design, pair: int = 1) -> tuple[str, str, str]:
    """The design fields of pair ``pair``'s modifications: gear A's table, gear B's table
    and the layout switch (dotted paths).

    Raises
    ------
    ReducerlabError
        A drive without tooth flanks, or a pair it does not have.
    """
    kind = getattr(design, "type", None)
    if kind == "nutation":
        return (f"gear{2 * pair}.modifications", f"gear{2 * pair - 1}.modifications",
                "surface.flank_modifications")  # fmt: skip
    if kind == "gear_pair" and pair == 1:
        return "pinion.modifications", "gear.modifications", "mesh.flank_modifications"
    if kind == "khv" and pair == 1:
        return ("gears.planet_modifications", "gears.ring_modifications",
                "gears.flank_modifications")  # fmt: skip
    raise ReducerlabError(
        f"modifications: a {kind} design has no gear pair {pair} with tooth flanks"
    )


def _at(design: Any, path: str) -> Any:
    node = design
    for key in path.split("."):
        node = None if node is None else getattr(node, key, None)
    return node


def design_force(design: Design, pair: int = 1) -> tuple[float, float]:
    """The tangential force ``F_t`` (N) of pair ``pair`` at the design load and its face
    width ``b`` (m): what the crowned layout is sized by.

    ``F_t`` is the torque on gear A over its pitch radius: a nutation pair's external
    gear from the torque flow at its mean radius, a spur pinion's or a KHV planet's from
    the output torque (``Design.operating_point``) at the gear's reference radius.

    Raises
    ------
    DesignError
        The design has no load (naming its load fields) or no face width.
    """
    kind = getattr(design, "type", None)
    point = design.operating_point()
    if not point.loaded:
        fields = " or ".join(design.load_fields)
        raise DesignError(
            f'{pair_fields(design, pair)[2]} = "crowned": the layout is sized by the design '
            f"load; give {fields} (or the gears' own modifications tables)"
        )
    if kind == "nutation":
        from .torque_flow import torque_flow

        mesh = torque_flow(design).meshes[f"mesh{pair}"]
        radius = getattr(design, f"gear{2 * pair}").mean_radius
        return abs(mesh.external_torque) / radius, design.surface.face_width
    if kind == "gear_pair":
        if design.mesh.face_width is None:
            raise DesignError('mesh.flank_modifications = "crowned": needs mesh.face_width')
        return abs(point.output_torque) / design.pitch_radii()["gear"], design.mesh.face_width
    radius = design.gears.module * design.gears.planet_teeth / 2.0
    return abs(point.output_torque) / radius, design.gears.face_width


def design_modifications(
    design: Design, pair: int, flank_a: Any, flank_b: Any
) -> PairModifications:
    """The modifications of pair ``pair``'s loaded flanks from the design fields.

    Parameters
    ----------
    design : NutationDesign, GearPairDesign or KHVDesign
    pair : int
        The gear pair (1 or 2 of a double-sided nutation drive; 1 otherwise).
    flank_a, flank_b : Flank
        The pair's unmodified loaded flanks (``contact.flanks.Flank``): the crowned
        layout's tip relief length is a share of each active profile.

    Returns
    -------
    PairModifications
        Gear A's and gear B's: its own table, else the crowned layout where the switch
        asks for it, else none.
    """
    field_a, field_b, switch = pair_fields(design, pair)
    specs = [_at(design, field_a), _at(design, field_b)]
    mods: list[FlankModification] = [NONE if s is None else s.value() for s in specs]
    if _at(design, switch) == "crowned" and any(s is None for s in specs):
        force, face = design_force(design, pair)
        profiles = [FlankCoordinates.of(f).profile for f in (flank_a, flank_b)]
        corners = (bool(profile_corners(flank_a)), bool(profile_corners(flank_b)))
        pieces = tuple(profile_transition(f) is not None for f in (flank_a, flank_b))
        layout = crowned_layout(force, face, *profiles, corners=corners, transitions=pieces)
        mods = [layout.a if specs[0] is None else mods[0],
                layout.b if specs[1] is None else mods[1]]  # fmt: skip
    return PairModifications(*mods)


def spur_mesh_pair(design: Design, modifications: PairModifications | None = None) -> Any:
    """The :class:`~reducerlab.contact.spur_pair.SpurMeshPair` of a ``gear_pair`` design
    with its flank modifications (``modifications``, default the design's: pinion = A,
    gear = B).

    Raises
    ------
    ReducerlabError
        Not a gear pair design, or a relief longer than its flank (naming the field).
    """
    from ..contact.spur_pair import SpurMeshPair

    if getattr(design, "type", None) != "gear_pair":
        raise ReducerlabError("design: spur_mesh_pair needs a gear_pair design")
    return with_modifications(SpurMeshPair(design.spur_pair()), design, 1, modifications)


def khv_mesh_pair(design: Design, modifications: PairModifications | None = None) -> Any:
    """The :class:`~reducerlab.contact.internal_pair.InternalMeshPair` of a ``khv``
    design (planet = A, ring = B) with its flank modifications (``modifications``,
    default the design's ``[gears]`` fields).

    Raises
    ------
    ReducerlabError
        Not a KHV design, or a relief longer than its flank (naming the field).
    """
    from ..contact.internal_pair import InternalMeshPair

    if getattr(design, "type", None) != "khv":
        raise ReducerlabError("design: khv_mesh_pair needs a khv design")
    return with_modifications(InternalMeshPair.from_khv(design), design, 1, modifications)


def with_modifications(
    plain: Any, design: Design, pair: int, modifications: PairModifications | None = None
) -> Any:
    """The unmodified mesh pair ``plain`` (a dataclass with a ``modifications`` field:
    ``NutationPair``, ``SpurMeshPair``) with ``modifications``, default the design's
    (:func:`design_modifications`); a relief longer than its flank refused in the
    design's field names."""
    if modifications is None:
        modifications = design_modifications(design, pair, plain.flank_a, plain.flank_b)
    if modifications.none:
        return plain
    return checked(replace(plain, modifications=modifications), design, pair)


def checked(mesh_pair: Any, design: Design, pair: int) -> Any:
    """``mesh_pair`` after building its modified flanks, with a relief longer than its
    flank refused in the design's field names (``gear2.modifications.tip_relief_length:
    ...``)."""
    names = pair_fields(design, pair)[:2]
    for side, name in zip(("a", "b"), names, strict=True):
        try:
            getattr(mesh_pair, f"flank_{side}")
        except ReducerlabError as e:
            raise DesignError(str(e).replace(f"modifications.{side}", name, 1)) from None
    return mesh_pair
