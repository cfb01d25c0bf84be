"""Where the bodies of a drive's lumped model sit: the layout that mode-shape figures
draw the bodies at (issue 32).

A :class:`Place` puts one body of the model (or a fixed member that has no DOFs, drawn
still) in the drive: its centre, its axis, the circles it is drawn as and a label. A
:class:`DriveLayout` holds the places of every body and turns DOF values into rigid
motions of the bodies (:meth:`DriveLayout.motion`), read as :mod:`reducerlab.model.dofs`
defines the kinds:

* ``x, y, z`` translate the body's centre along the drive's x, y, z (m) (the frame of
  the builders' lines of action, the nutating gear's included);
* ``rx, ry`` tilt it about its own transverse axes through its centre (rad): the
  drive's x and y laid onto its plane (:meth:`Place.frame`; the nutating gear's tilts
  about the nutation centre, ``drives.nutation_specs.TiltSupport``);
* ``rz`` turns it about its own axis (rad), ``u`` by ``u / r`` with the DOF's radius.

A model read in a rotating frame (the cycloid-ball drive's frame of the eccentric, a
nutation drive's ``rotating_frame``) is drawn in that frame. Each drive type's places
come from its design (pitch radii, centre distance, eccentricity, nutation angle, cone
distances), registered in ``drives.DRIVES``; any other body gets a place on the drive's
axis (:func:`complete`): a lumped model's bodies are spaced along z, at their ``u``
radius or 0.1 m.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from ..model import Model
    from .cycloid_ball import CycloidBallDesign
    from .gear_pair import GearPairDesign
    from .khv import KHVDesign
    from .nutation import NutationDesign

__all__ = [
    "DEFAULT_RADIUS",
    "DriveLayout",
    "Place",
    "complete",
    "cycloid_ball_places",
    "gear_pair_places",
    "khv_places",
    "nutation_places",
    "rotation",
]

#: Drawing radius (m) of a body whose size nothing in the model or design gives.
DEFAULT_RADIUS = 0.1

Z = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Place:
    """One body at its place in the drive.

    Parameters
    ----------
    body : str
        The model's body name (a body without DOFs is a fixed member, drawn still).
    centre : tuple of float
        Centre (m): the point its translations move and its tilts turn about.
    axis : tuple of float
        Direction of its own axis (normalised here), about which ``rz`` / ``u`` turn it.
    radius : float
        Drawing radius (m), > 0: its pitch circle where it has one.
    label : str
        Name shown in figures.
    rings : tuple of (float, float)
        Circles drawn for the body as ``(offset along the axis from the centre (m),
        radius (m))``; by default one circle of ``radius`` at the centre. The nutating
        gear of a nutation drive has its toothed rings at its cone distances.
    carrier : str, optional
        A body whose turn about its own axis carries this body's centre around (the
        KHV drive's planet on its carrier).
    """

    body: str
    centre: tuple[float, float, float]
    axis: tuple[float, float, float]
    radius: float
    label: str = ""
    rings: tuple[tuple[float, float], ...] = ()
    carrier: str | None = None

    def __post_init__(self) -> None:
        a = np.asarray(self.axis, float)
        norm = float(np.linalg.norm(a))
        if a.shape != (3,) or not np.isfinite(norm) or norm == 0.0:
            raise ReducerlabError(f"place of {self.body!r}: axis must be a non-zero 3-vector")
        if np.asarray(self.centre, float).shape != (3,):
            raise ReducerlabError(f"place of {self.body!r}: centre must be a 3-vector (m)")
        if not (self.radius > 0 and math.isfinite(self.radius)):
            raise ReducerlabError(f"place of {self.body!r}: radius must be > 0 m")
        object.__setattr__(self, "axis", tuple(float(x) / norm for x in a))
        object.__setattr__(self, "centre", tuple(float(x) for x in self.centre))
        object.__setattr__(self, "rings", tuple(self.rings) or ((0.0, float(self.radius)),))
        object.__setattr__(self, "label", self.label or self.body.replace("_", " "))

    def frame(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Orthonormal ``(e1, e2, axis)``: ``e1`` the drive's x laid onto the body's
        plane (y where the axis is along x)."""
        a = np.asarray(self.axis)
        ref = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = ref - (ref @ a) * a
        e1 /= np.linalg.norm(e1)
        return e1, np.cross(a, e1), a


def rotation(axis: Sequence[float], angle: float) -> NDArray[np.float64]:
    """Rotation matrix of ``angle`` (rad) about the unit vector ``axis`` (Rodrigues)."""
    k = np.asarray(axis, float)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)


@dataclass(frozen=True)
class DriveLayout:
    """The places of a model's bodies and the radii of its ``u`` DOFs.

    Parameters
    ----------
    places : tuple of Place
        One per body of the model, then any fixed members.
    u_radius : mapping of str to float
        Radius (m) of each body's ``u`` DOF (``u = r rz``).
    name : str
        The drive (figure titles).
    """

    places: tuple[Place, ...]
    u_radius: Mapping[str, float] = field(default_factory=dict)
    name: str = ""

    def __getitem__(self, body: str) -> Place:
        for p in self.places:
            if p.body == body:
                return p
        raise KeyError(body)

    @property
    def bodies(self) -> list[str]:
        """Body names in drawing order."""
        return [p.body for p in self.places]

    @property
    def size(self) -> float:
        """Largest extent (m) of the drawn circles along x, y or z: the drive's size."""
        pts = []
        for p in self.places:
            e1, e2, a = p.frame()
            c = np.asarray(p.centre)
            for off, r in p.rings:
                for v in (e1, -e1, e2, -e2):
                    pts.append(c + off * a + r * v)
        pts_a = np.array(pts)
        return float(np.max(pts_a.max(axis=0) - pts_a.min(axis=0)))

    def motion(
        self, values: Mapping[str, float], scale: float = 1.0
    ) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
        """Rigid motion of every body for DOF values (``"body.kind"`` → SI value).

        Parameters
        ----------
        values : mapping of str to float
            DOF values (m, rad); a missing DOF is 0.
        scale : float
            Factor on every value (the drawn amplitude).

        Returns
        -------
        dict
            body → ``(translation (3,) m, rotation (3, 3))``: a point ``p`` of the body
            goes to ``c + t + R (p - c)`` with ``c`` its centre at rest (the carrier's
            turn included in ``t``).
        """
        out = {}
        for p in self.places:

            def q(kind: str, body: str = p.body) -> float:
                return scale * float(values.get(f"{body}.{kind}", 0.0))

            twist = q("rz") + q("u") / self.u_radius.get(p.body, 1.0)
            e1, e2, a = p.frame()
            R = rotation(e1, q("rx")) @ rotation(e2, q("ry")) @ rotation(a, twist)
            t = np.array([q("x"), q("y"), q("z")])
            if p.carrier is not None:
                car = self[p.carrier]
                turn = q("rz", car.body) + q("u", car.body) / self.u_radius.get(car.body, 1.0)
                arm = np.asarray(p.centre) - np.asarray(car.centre)
                t = t + rotation(car.axis, turn) @ arm - arm
            out[p.body] = (t, R)
        return out


def complete(places: Sequence[Place], model: Model, name: str = "") -> DriveLayout:
    """The layout of ``model``: the given places, and a place on the drive's axis for
    every body of the model without one (spaced along z beyond the others, at its ``u``
    radius, else the largest given radius, else :data:`DEFAULT_RADIUS`).

    Raises
    ------
    ReducerlabError
        A body placed twice.
    """
    seen = [p.body for p in places]
    if len(set(seen)) != len(seen):
        raise ReducerlabError(f"drive layout: a body placed twice in {seen}")
    u_radius = {d.body: float(d.radius) for d in model.dofs if d.kind == "u" and d.radius}
    bodies = list(dict.fromkeys(d.body for d in model.dofs))
    missing = [b for b in bodies if b not in seen]
    out = list(places)
    if missing:
        given = [p.radius for p in places] + list(u_radius.values())
        default = max(given) if given else DEFAULT_RADIUS
        z0 = max((p.centre[2] for p in places), default=-2.5 * default) + 2.5 * default
        for k, b in enumerate(missing):
            r = u_radius.get(b, default)
            out.append(Place(b, (0.0, 0.0, z0 + 2.5 * default * k), Z, r))
    # the model's bodies first, in the model's order, then the fixed members
    order = {b: i for i, b in enumerate(bodies)}
    out.sort(key=lambda p: order.get(p.body, len(order)))
    return DriveLayout(tuple(out), u_radius, name or model.name)


def gear_pair_places(design: GearPairDesign) -> list[Place]:
    """Pinion at the origin, gear on +x at the reference centre distance ``m (z1 + z2)
    / 2`` (the builder's line of action has the gear on +x), both at their pitch radii."""
    r = design.pitch_radii()
    a = r["pinion"] + r["gear"]
    return [
        Place("pinion", (0.0, 0.0, 0.0), Z, r["pinion"], f"pinion z{design.pinion.teeth}"),
        Place("gear", (a, 0.0, 0.0), Z, r["gear"], f"gear z{design.gear.teeth}"),
    ]


def cycloid_ball_places(design: CycloidBallDesign) -> list[Place]:
    """Paper 003 Fig. 1 in the frame of the eccentric (line of centres along x): the
    input shaft on the axis, the planetary disc on the eccentric (``x = e``), the centre
    disc and the end cover disc coaxial on either side; discs at their groove pitch
    radii, the shaft drawn at a third of the centre disc's."""
    e = design.eccentricity
    r2 = design.pitch_radius(design.centre_disc.lobes)
    r3 = design.pitch_radius(design.planetary_disc.lobes)
    gap = 0.6 * r3
    return [
        Place(
            "input_shaft", (0.0, 0.0, -2 * gap), Z, r2 / 3, f"input shaft (e = {e * 1e3:.3g} mm)"
        ),
        Place("centre_disc", (0.0, 0.0, -gap), Z, r2, "centre disc"),
        Place("planetary_disc", (e, 0.0, 0.0), Z, r3, "planetary disc"),
        Place("end_cover_disc", (0.0, 0.0, gap), Z, r3, "end cover disc"),
    ]


def khv_places(design: KHVDesign) -> list[Place]:
    """Paper 004's KHV drive: the drive shaft and the carrier on the axis, the planet on
    the carrier's crank at the working centre distance ``a'`` (+x), carried round by
    the carrier's turn, the fixed ring around it (drawn still), the load on the axis."""
    pair = design.gears.pair()
    a, rV, rK = pair.centre_distance, pair.pitch_radius(1), pair.pitch_radius(2)
    gap = 0.5 * rV
    return [
        Place("drive", (0.0, 0.0, -2 * gap), Z, 0.3 * rV, "drive shaft D"),
        Place("carrier", (0.0, 0.0, -gap), Z, 0.3 * rV, f"carrier H (a' = {a * 1e3:.3g} mm)"),
        Place(
            "planet",
            (a, 0.0, 0.0),
            Z,
            rV,
            f"planet V z{design.gears.planet_teeth}",
            carrier="carrier",
        ),
        Place("ring", (0.0, 0.0, 0.0), Z, rK, f"ring K z{design.gears.ring_teeth} (fixed)"),
        Place("load", (0.0, 0.0, 2 * gap), Z, 0.3 * rV, "load L"),
    ]


def nutation_places(design: NutationDesign) -> list[Place]:
    """Paper 000's nutation drive about its nutation centre (the origin, the common apex
    of the pitch cones): the fixed gear 2 on -z and (double-sided) the output gear 4 on
    +z at their mean cone distances ``R cos(delta)``, the nutating body 13 tilted by the
    nutation angle about y (its axis ``(sin theta, 0, cos theta)``) with gear 1 facing
    gear 2 and gear 3 facing gear 4: its pitch circles touch theirs at +x and -x. The
    drive is drawn as the mesh frame sees it, at input crank angle 0 (the nutating
    gear's axis precesses about z with the crank)."""
    th = design.theta
    cones = design.cones(th)
    dist = design.cone_distances(th)
    double = design.sides == "double"
    dn1, dc2 = cones[0]
    g1, g2 = design.gear1, design.gear2
    axis13 = (math.sin(th), 0.0, math.cos(th))
    rings = [(-dist[0] * math.cos(dn1), g1.mean_radius)]
    out = [
        Place(
            "g2",
            (0.0, 0.0, -dist[1] * math.cos(dc2)),
            Z,
            g2.mean_radius,
            f"gear 2 z{g2.teeth} (fixed)",
        )
    ]
    if double:
        g3, g4 = design.gear3, design.gear4
        assert g3 is not None and g4 is not None  # the design's validator
        dn3, dc4 = cones[1]
        rings.append((dist[2] * math.cos(dn3), g3.mean_radius))
        out.append(
            Place(
                "g4",
                (0.0, 0.0, dist[3] * math.cos(dc4)),
                Z,
                g4.mean_radius,
                f"gear 4 z{g4.teeth} (output)",
            )
        )
    label = "nutating gear 1" + ("-3" if double else "") + f" ({math.degrees(th):.3g}°)"
    out.append(
        Place("g13", (0.0, 0.0, 0.0), axis13, max(r for _, r in rings), label, rings=tuple(rings))
    )
    return out
