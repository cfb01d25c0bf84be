"""Flank modifications (micro-geometry) as ease-off along the flank normal.

A modification removes material from a conjugate flank: the modified flank is
``P' = P - e(u, v) n`` (``n`` the outward unit normal of the unmodified flank, ``e`` the
ease-off in m). The tooth contact analysis sees it through the flank's ``evaluate``
(:class:`ModifiedFlank` wraps any flank of the ``contact.flanks.Flank`` protocol), so the
unloaded separation (TCA) and the loaded contact (LTCA) both include it, for the nutation
bevel pairs, the spur pairs and any other pair whose flanks follow the protocol.

The ease-off law (:class:`FlankModification`, ISO 21771:2007 §9 and ISO 1328-1:2013
terminology) is written in physical coordinates on the flank:

* ``s`` along the profile from the root end of the active flank (``u = u_lo``) to the
  tip (``u = u_hi``), total ``L_alpha``: the roll length where the flank defines one
  (an involute flank's ``profile_position``: ISO 21771 measures profile modifications
  along the line of action), otherwise the arc length along the profile at mid-face;
* ``w`` along the face from ``v = 0`` (toe of a bevel gear, ``z = -b/2`` of a spur gear)
  to ``v = 1``, total ``L_beta``: the arc length along the face at mid-profile.

With ``x = s - L_alpha/2`` and ``y = w - L_beta/2`` (from the middle of the flank):

* lead crowning ``C_beta (2 y / L_beta)^2`` (``C_beta`` at both ends of the face),
* profile crowning ``C_alpha (2 x / L_alpha)^2``,
* tip relief ``C_a t / L_Ca`` (linear) or ``C_a (t / L_Ca)^2`` (parabolic),
  ``t = s - (L_alpha - L_Ca) > 0``: ``C_a`` at the tip, 0 where the relief starts,
* root relief ``C_f r / L_Cf`` or ``C_f (r / L_Cf)^2``, ``r = L_Cf - s > 0``,
* lead slope ``f_Hbeta y / L_beta`` and profile slope ``f_Halpha x / L_alpha`` (signed:
  positive removes material towards ``v = 1`` and towards the tip).

The ease-off is applied along the unmodified normal and the normal is kept: the
modification tilts the true normal by its slope (``C / L``, about 1e-3 rad), which moves
the separation by the square of that angle (1e-6 relative) and the levers of the TCA by
about 1e-3 relative (``docs/assumptions.md``). The tooth compliance (finite elements)
does not depend on the micro-geometry: a modification changes the flank by micrometres,
the tooth by nothing a finite-element model of 0.3 m_n elements resolves; so one
compliance build serves every modification (``contact_analysis(..., compliance=,
modifications=)``).

Units: SI (m, N).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

__all__ = [
    "CORNER_SHARE",
    "CROWNED_APPROACH",
    "C_GAMMA",
    "MAX_AMOUNT",
    "NONE",
    "TRANSITION",
    "TRANSITION_SHARE",
    "FlankCoordinates",
    "FlankModification",
    "ModifiedFlank",
    "PairModifications",
    "crowned_layout",
    "modified",
    "profile_corners",
    "profile_transition",
]

Array = NDArray[np.float64]

#: Mesh stiffness per face width of solid steel spur gears, ISO 6336-1:2006 §9.2 (the
#: mean value of Method C, c_gamma = 20 N/(mm um)), N/m per m of face width (Pa)
C_GAMMA = 20e9

#: Largest amount of one modification (m): micro-geometry, not a change of the tooth
MAX_AMOUNT = 0.2e-3

#: Share of the active profile (roll length or arc length) over which the crowned
#: layout relieves each tip: the long relief of ISO/TS 6336-20 (from the tip to the
#: single contact point, ``(eps_alpha - 1) p_b`` of the path ``g_alpha = eps_alpha
#: p_b``) for a transverse contact ratio of about 1.65
TIP_SHARE = 0.4

#: Loaded approach of the crowned layout's contact at its design load, in units of
#: ``delta = F_t / (b c_gamma)``: on a foundation of stiffness ``c_gamma`` per face width
#: a line contact with the pair's parabolic crown ``C = 2 delta`` (``(2y/b)^2``) carries
#: ``F = (2/3) c_gamma b A^(3/2) / C^(1/2)`` at the approach ``A`` while its loaded length
#: ``b sqrt(A / C)`` is shorter than the face; ``F = c_gamma b delta`` gives
#: ``A = (3 / sqrt 2)^(2/3) delta = 1.651 delta`` (loaded length 0.91 b). The tip relief
#: must clear this approach, not ``delta`` (the uncrowned mesh's): a tooth entering
#: mesh meets the others' approach at its tip
CROWNED_APPROACH = (3.0 / math.sqrt(2.0)) ** (2.0 / 3.0)

#: Share of the active profile over which the crowned layout's corner relief runs out on
#: each side of a profile corner (the double arc's, docs/assumptions.md): 0.41 mm on the
#: nutation example (m_n 2 mm), 2-4 Hertz half-widths of its contact
CORNER_SHARE = 0.1

#: Share of the active profile over which the crowned layout's transition relief runs out
#: beyond each end of the double arc's transition arc (docs/assumptions.md): 0.61 mm on
#: the nutation example; shorter (10 %) left the peak pressure of the patches beside it
#: 2-6 % grid-dependent
TRANSITION_SHARE = 0.15

#: Name of the basic profile's piece that the transition relief covers (the double arc's
#: transition arc, ``DoubleCircularArcProfile.segment_names``)
TRANSITION = "transition"

#: Points of the tables mapping flank parameters to profile and face positions
TABLE = 201

_AMOUNTS = (
    "lead_crowning",
    "profile_crowning",
    "tip_relief",
    "root_relief",
    "corner_relief",
    "transition_relief",
)
_LENGTHS = ("tip_relief_length", "root_relief_length")
_SLOPES = ("lead_slope", "profile_slope")


@dataclass(frozen=True)
class FlankModification:
    """Modifications of one flank (ISO 21771 §9 names), an immutable value.

    Attributes
    ----------
    lead_crowning : float
        ``C_beta`` (m), >= 0: ease-off at each end of the face relative to its middle.
    profile_crowning : float
        ``C_alpha`` (m), >= 0: ease-off at each end of the active profile relative to its
        middle.
    tip_relief, tip_relief_length : float
        ``C_a`` (m) at the tip and the length ``L_Ca`` (m, along the profile: roll length
        of an involute) over which it runs out; ``L_Ca > 0`` when ``C_a > 0``.
    root_relief, root_relief_length : float
        ``C_f`` (m) at the root end of the active flank and its length ``L_Cf`` (m).
    relief_shape : {"linear", "parabolic"}
        Course of tip and root relief over their lengths.
    lead_slope, profile_slope : float
        Helix and profile slope deviations ``f_Hbeta``, ``f_Halpha`` (m, signed): the
        difference of ease-off between the ends of the face (``v = 1`` minus ``v = 0``)
        and of the profile (tip minus root end).
    corner_relief, corner_relief_length : float
        ``C_c`` (m) at a corner of the basic profile (``BasicProfile.corners``: the
        double arc's concave/transition joint) and the length ``L_Cc`` (m, along the
        profile) over which it runs out on each side of the corner, in
        ``relief_shape``; ``L_Cc > 0`` when ``C_c > 0``. Only for a flank whose profile
        has a corner.
    transition_relief, transition_relief_length : float
        ``C_t`` (m) held over the whole transition piece of the basic profile (the double
        arc's transition arc, from its corner with the concave arc to its curvature jump
        into the convex arc) and the length ``L_Ct`` (m, along the profile) over which
        it runs out beyond each end, cubically whatever ``relief_shape`` says (slope and
        curvature continuous where it meets the working arcs); ``L_Ct > 0`` when
        ``C_t > 0``. Only for a flank whose profile has a transition piece. Where it
        overlaps the corner relief the larger of the two is removed.
    """

    lead_crowning: float = 0.0
    profile_crowning: float = 0.0
    tip_relief: float = 0.0
    tip_relief_length: float = 0.0
    root_relief: float = 0.0
    root_relief_length: float = 0.0
    relief_shape: Literal["linear", "parabolic"] = "linear"
    lead_slope: float = 0.0
    profile_slope: float = 0.0
    corner_relief: float = 0.0
    corner_relief_length: float = 0.0
    transition_relief: float = 0.0
    transition_relief_length: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name == "relief_shape":
                continue
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                raise ReducerlabError(f"{f.name}: must be a finite length (m); got {v!r}")
            object.__setattr__(self, f.name, float(v))
            if f.name in _SLOPES:
                if abs(v) > MAX_AMOUNT:
                    raise ReducerlabError(
                        f"{f.name}: must be within +-{MAX_AMOUNT * 1e3:g} mm (micro-geometry); "
                        f"got {v * 1e3:.4g} mm"
                    )
            elif v < 0:
                raise ReducerlabError(f"{f.name}: must be >= 0 (m); got {v!r}")
            elif f.name in _AMOUNTS and v > MAX_AMOUNT:
                raise ReducerlabError(
                    f"{f.name}: must be at most {MAX_AMOUNT * 1e3:g} mm (micro-geometry); "
                    f"got {v * 1e3:.4g} mm"
                )
        if self.relief_shape not in ("linear", "parabolic"):
            raise ReducerlabError(
                f'relief_shape: must be "linear" or "parabolic"; got {self.relief_shape!r}'
            )
        for amount, length in (("tip_relief", "tip_relief_length"),
                               ("root_relief", "root_relief_length"),
                               ("corner_relief", "corner_relief_length"),
                               ("transition_relief", "transition_relief_length")):  # fmt: skip
            if getattr(self, amount) > 0 and getattr(self, length) <= 0:
                raise ReducerlabError(
                    f"{length}: must be > 0 (m) with {amount} = "
                    f"{getattr(self, amount) * 1e6:.4g} um"
                )

    @property
    def none(self) -> bool:
        """Whether the flank is unmodified."""
        return not any(getattr(self, n) for n in (*_AMOUNTS, *_SLOPES))

    def ease_off(
        self,
        s: Array,
        w: Array,
        profile: float,
        face: float,
        corners: tuple[float, ...] = (),
        transition: tuple[float, float] | None = None,
    ) -> Array:
        """Material removed (m) at profile position ``s`` and face position ``w`` (m).

        Parameters
        ----------
        s, w : ndarray
            Positions along the profile from the root end of the active flank and along
            the face from ``v = 0`` (m); beyond the flank the law continues.
        profile, face : float
            ``L_alpha`` and ``L_beta``: lengths of the active profile and of the face (m).
        corners : tuple of float
            Profile positions ``s_c`` (m) of the profile's corners: the corner relief
            ``C_c (1 - |s - s_c| / L_Cc)`` (linear) or its square (parabolic) within
            ``L_Cc`` of each (the larger where two overlap).
        transition : tuple of float, optional
            Profile positions ``(s_0, s_1)`` (m) of the ends of the transition piece: the
            transition relief is ``C_t`` for ``s_0 <= s <= s_1`` and
            ``C_t (1 - d / L_Ct)^3`` at a distance ``d`` beyond either end, 0 beyond
            ``L_Ct`` (cubic: no curvature jump where it ends, inside the loaded patches
            beside the arc); with a corner relief the larger of the two counts.
        """
        s = np.asarray(s, float)
        w = np.asarray(w, float)
        x = s - 0.5 * profile
        y = w - 0.5 * face
        e = self.lead_crowning * (2.0 * y / face) ** 2 + self.lead_slope * y / face
        e = e + self.profile_crowning * (2.0 * x / profile) ** 2
        e = e + self.profile_slope * x / profile
        power = 1.0 if self.relief_shape == "linear" else 2.0
        if self.tip_relief > 0:
            t = np.maximum(s - (profile - self.tip_relief_length), 0.0)
            e = e + self.tip_relief * (t / self.tip_relief_length) ** power
        if self.root_relief > 0:
            r = np.maximum(self.root_relief_length - s, 0.0)
            e = e + self.root_relief * (r / self.root_relief_length) ** power
        joint = np.zeros_like(s)
        if self.corner_relief > 0:
            near = np.zeros_like(s)
            for sc in corners:
                near = np.maximum(near, 1.0 - np.abs(s - sc) / self.corner_relief_length)
            joint = self.corner_relief * near**power
        if self.transition_relief > 0 and transition is not None:
            s0, s1 = min(transition), max(transition)
            d = np.maximum(np.maximum(s0 - s, s - s1), 0.0)
            near = np.maximum(1.0 - d / self.transition_relief_length, 0.0)
            joint = np.maximum(joint, self.transition_relief * near**3)
        return e + joint

    def check_lengths(self, profile: float, where: str = "") -> None:
        """Refuse relief lengths beyond the active profile ``profile`` (m), and a tip and
        a root relief that overlap.

        Raises
        ------
        ReducerlabError
            Naming the field (prefixed with ``where``) and the profile length.
        """
        pre = f"{where}." if where else ""
        for name in _LENGTHS:
            v = getattr(self, name)
            if v > profile * (1 + 1e-12):
                raise ReducerlabError(
                    f"{pre}{name}: {v * 1e3:.4g} mm runs beyond the flank: the active profile "
                    f"is {profile * 1e3:.4g} mm long"
                )
        if self.corner_relief_length > 0.5 * profile * (1 + 1e-12):
            raise ReducerlabError(
                f"{pre}corner_relief_length: {self.corner_relief_length * 1e3:.4g} mm on each "
                f"side of the corner is more than half the active profile "
                f"({profile * 1e3:.4g} mm)"
            )
        if self.transition_relief_length > 0.5 * profile * (1 + 1e-12):
            raise ReducerlabError(
                f"{pre}transition_relief_length: {self.transition_relief_length * 1e3:.4g} mm "
                f"beyond each end of the transition is more than half the active profile "
                f"({profile * 1e3:.4g} mm)"
            )
        both = (self.tip_relief > 0) and (self.root_relief > 0)
        if both and self.tip_relief_length + self.root_relief_length > profile * (1 + 1e-12):
            raise ReducerlabError(
                f"{pre}tip_relief_length + root_relief_length: "
                f"{(self.tip_relief_length + self.root_relief_length) * 1e3:.4g} mm overlap on "
                f"an active profile of {profile * 1e3:.4g} mm"
            )

    def scaled(self, factor: float) -> FlankModification:
        """All amounts times ``factor`` (lengths and shape kept)."""
        kw = {n: factor * getattr(self, n) for n in (*_AMOUNTS, *_SLOPES)}
        return replace(self, **kw)


#: No modification
NONE = FlankModification()


@dataclass(frozen=True)
class PairModifications:
    """Modifications of both flanks of a gear pair: ``a`` on gear A's loaded flank, ``b``
    on gear B's (the ``MeshPair`` order: the external gear of a nutation pair, the pinion
    of a spur pair, the planet of a KHV pair is A). Where the flanks touch with opposite
    normals their ease-offs add up in the separation."""

    a: FlankModification = NONE
    b: FlankModification = NONE

    def __post_init__(self) -> None:
        for name in ("a", "b"):
            if not isinstance(getattr(self, name), FlankModification):
                raise ReducerlabError(
                    f"modifications.{name}: must be a FlankModification; got "
                    f"{type(getattr(self, name)).__name__}"
                )

    @property
    def none(self) -> bool:
        """Whether neither flank is modified."""
        return self.a.none and self.b.none

    def to_dict(self) -> dict[str, Any]:
        """The amounts (m) and shapes of both flanks, for result attributes."""
        return {side: {f.name: getattr(getattr(self, side), f.name)
                       for f in fields(FlankModification)} for side in ("a", "b")}  # fmt: skip


def _interp(x: Array, xp: Array, fp: Array) -> Array:
    """Piecewise linear ``fp(xp)`` at ``x``, continued linearly beyond both ends."""
    y = np.interp(x, xp, fp)
    lo = x < xp[0]
    hi = x > xp[-1]
    if np.any(lo):
        y[lo] = fp[0] + (x[lo] - xp[0]) * (fp[1] - fp[0]) / (xp[1] - xp[0])
    if np.any(hi):
        y[hi] = fp[-1] + (x[hi] - xp[-1]) * (fp[-1] - fp[-2]) / (xp[-1] - xp[-2])
    return y


@dataclass(frozen=True, eq=False)
class FlankCoordinates:
    """Physical positions on a flank: tables from the flank parameters to the profile
    position ``s`` and the face position ``w`` (m), and the active flank's lengths.

    Attributes
    ----------
    u, s : ndarray
        Profile parameter and the position along the profile (m), measured from the root
        end of the active flank (the part of the mid-face profile on the real tooth,
        ``Flank.inside``) towards the tip.
    v, w : ndarray
        Face parameter and the position along the face from its first end (m).
    profile, face : float
        ``L_alpha``, ``L_beta``: lengths of the active profile and of the face (m).
    """

    u: Array
    s: Array
    v: Array
    w: Array
    profile: float
    face: float

    @classmethod
    def of(cls, flank: Any) -> FlankCoordinates:
        """The coordinates of any flank of the ``Flank`` protocol.

        The profile is measured by the flank's ``profile_position(u)`` (m) where it has
        one (the roll length of an involute), else by the arc length along the profile
        at mid-face; the face by the arc length at the middle of the active profile. The
        tip is at ``u_hi`` (the protocol's ``u`` runs from root to tip) unless the flank
        says ``tip_end = -1`` (a bevel flank of an internal gear, whose generating crown
        profile runs from its tip to its root).
        """
        lo, hi = flank.u_range
        u = np.linspace(lo, hi, TABLE)
        P, _ = flank.evaluate(u, np.full(TABLE, 0.5))
        on = np.flatnonzero(flank.inside(P))
        if on.size < 2:
            raise ReducerlabError("flank: its mid-face profile is not on the tooth")
        pos = getattr(flank, "profile_position", None)
        if pos is not None:
            sigma = np.asarray(pos(u), float)
        else:
            sigma = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
        tip = getattr(flank, "tip_end", 1)
        a, b = sigma[on[0]], sigma[on[-1]]
        s = sigma - a if tip == 1 else b - sigma
        if tip != 1:
            u, s = u[::-1], s[::-1]
        v = np.linspace(0.0, 1.0, TABLE)
        u_mid = float(np.interp(0.5 * (b - a), s, u))
        Q, _ = flank.evaluate(np.full(TABLE, u_mid), v)
        w = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Q, axis=0), axis=1))])
        if not (np.all(np.diff(s) > 0) and np.all(np.diff(w) > 0)):
            raise ReducerlabError("flank: its profile or face positions do not increase")
        return cls(u, s, v, w, float(b - a), float(w[-1]))

    def positions(self, u: Array, v: Array) -> tuple[Array, Array]:
        """Profile and face positions ``s, w`` (m) of flank parameters ``u, v`` (linear
        between the table's points, continued beyond them)."""
        uu = np.asarray(u, float).ravel()
        vv = np.asarray(v, float).ravel()
        # with the tip at u_lo the table runs backwards in u
        forward = self.u[0] < self.u[-1]
        s = _interp(uu, self.u, self.s) if forward else _interp(-uu, -self.u, self.s)
        return s, _interp(vv, self.v, self.w)


@dataclass(frozen=True)
class ModifiedFlank:
    """A flank with a modification: the ``Flank`` protocol of ``contact.flanks``.

    Parameters
    ----------
    flank : Flank
        The unmodified flank (any object of the protocol: ``teeth``, ``u_range``,
        ``evaluate``, ``inside``; see :meth:`FlankCoordinates.of` for how its profile
        and face are measured).
    modification : FlankModification
    where : str
        Name of the modification in error messages (a design field path).

    Other attributes of the wrapped flank (a bevel flank's ``crown``, ``gear``, ...)
    are reached through this one.
    """

    flank: Any
    modification: FlankModification
    where: str = field(default="", compare=False)
    coordinates: FlankCoordinates = field(init=False, repr=False, compare=False)
    corner_positions: tuple[float, ...] = field(init=False, repr=False, compare=False)
    transition_positions: tuple[float, float] | None = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.modification, FlankModification):
            raise ReducerlabError(
                f"modification: must be a FlankModification; got {type(self.modification).__name__}"
            )
        c = FlankCoordinates.of(self.flank)
        object.__setattr__(self, "coordinates", c)
        self.modification.check_lengths(c.profile, self.where)
        at = profile_corners(self.flank)
        corners = tuple(float(x) for x in c.positions(np.array(at), np.full(len(at), 0.5))[0])
        if self.modification.corner_relief > 0 and not corners:
            pre = f"{self.where}." if self.where else ""
            raise ReducerlabError(
                f"{pre}corner_relief: the flank's profile has no corner (only a profile "
                "with one, the double arc's, takes a corner relief)"
            )
        object.__setattr__(self, "corner_positions", corners)
        piece = profile_transition(self.flank)
        ends = None
        if piece is not None:
            s_ends = c.positions(np.array(piece), np.full(2, 0.5))[0]
            ends = (float(s_ends[0]), float(s_ends[1]))
        if self.modification.transition_relief > 0 and ends is None:
            pre = f"{self.where}." if self.where else ""
            raise ReducerlabError(
                f"{pre}transition_relief: the flank's profile has no transition piece on its "
                "active flank (only a profile with one, the double arc's, takes a "
                "transition relief)"
            )
        object.__setattr__(self, "transition_positions", ends)

    def __getattr__(self, name: str) -> Any:
        # only for attributes not found on the wrapper itself; never during unpickling
        # (before the fields exist) or for private and special names
        if name.startswith("_") or "flank" not in self.__dict__:
            raise AttributeError(name)
        return getattr(self.__dict__["flank"], name)

    @property
    def teeth(self) -> int:
        """Number of teeth of the gear."""
        return self.flank.teeth

    @property
    def u_range(self) -> tuple[float, float]:
        """The wrapped flank's profile parameter range."""
        return self.flank.u_range

    def ease_off(self, u: Array, v: Array) -> Array:
        """Material removed (m) at flank parameters ``u, v``."""
        c = self.coordinates
        s, w = c.positions(u, v)
        return self.modification.ease_off(
            s, w, c.profile, c.face, self.corner_positions, self.transition_positions
        )

    def evaluate(self, u: Array, v: Array) -> tuple[Array, Array]:
        """Points of the modified flank (m) and the unmodified unit outward normals,
        shape (n, 3), gear frame."""
        P, N = self.flank.evaluate(u, v)
        e = self.ease_off(u, v)
        return P - e[:, None] * N, N

    def inside(self, points: Array) -> NDArray[np.bool_]:
        """Whether points lie on the gear's real tooth (the wrapped flank's blank)."""
        return self.flank.inside(points)


def profile_corners(flank: Any) -> tuple[float, ...]:
    """Profile parameters ``u`` of the corners of a flank's basic profile inside its
    ``u_range`` (``BasicProfile.corners`` of a bevel flank's generating crown, whose
    parameter is the flank's ``u``); none for a flank without one (an involute)."""
    prof = getattr(getattr(flank, "crown", None), "profile", None)
    lo, hi = flank.u_range
    return tuple(float(u) for u in getattr(prof, "corners", ()) if lo < u < hi)


def profile_transition(flank: Any) -> tuple[float, float] | None:
    """Profile parameters ``(u_0, u_1)`` of the ends of a flank's transition piece
    (the basic profile's segment named :data:`TRANSITION`: the double arc's transition
    arc, from its corner with the concave arc to its curvature jump into the convex
    arc), clipped to the flank's ``u_range``; ``None`` for a profile without one (an
    involute) or where the piece lies outside the flank."""
    prof = getattr(getattr(flank, "crown", None), "profile", None)
    names = tuple(getattr(prof, "segment_names", ()))
    if TRANSITION not in names:
        return None
    i = names.index(TRANSITION)
    edges = (0.0, *prof.breaks, 1.0)
    lo, hi = flank.u_range
    u0, u1 = max(edges[i], lo), min(edges[i + 1], hi)
    return (float(u0), float(u1)) if u0 < u1 else None


def modified(flank: Any, modification: FlankModification | None, where: str = "") -> Any:
    """``flank`` with ``modification`` (a :class:`ModifiedFlank`), or ``flank`` itself
    when there is none."""
    if modification is None or modification.none:
        return flank
    return ModifiedFlank(flank, modification, where)


def crowned_layout(
    force: float,
    face_width: float,
    profile_a: float,
    profile_b: float,
    *,
    stiffness: float = C_GAMMA,
    corners: tuple[bool, bool] = (False, False),
    transitions: tuple[bool, bool] = (False, False),
) -> PairModifications:
    """The default crowned layout of a gear pair at its design load.

    With ``delta = F_t / (b c_gamma)``, the mesh deflection at the design load (ISO
    6336-1 §9: ``c_gamma`` per face width; ISO/TS 6336-20's effective tip relief
    ``C_eff = K_A F_t / (b c_gamma)`` with ``K_A = 1``):

    * lead crowning ``C_beta = 2 delta`` for the pair, half on each flank: on a
      foundation of stiffness ``c_gamma`` a parabolic crown of ``1.5 delta`` just spans
      the face at the design load; ``2 delta`` loads ``0.91 b`` and keeps the load off
      both face ends (``docs/contact.md``);
    * tip relief ``C_a = CROWNED_APPROACH delta = 1.651 delta`` on each flank: the
      approach of the crowned contact at the design load (:data:`CROWNED_APPROACH`;
      ISO/TS 6336-20's ``C_eff = delta`` is the uncrowned mesh's, and left 4-7 % of a
      crowned nutation pair's load on the tips, ``docs/contact.md``), parabolic (no
      kink in the flank, so no pressure spike where the relief starts), over the outer
      :data:`TIP_SHARE` of its active profile (ISO/TS 6336-20's long relief);
    * no profile crowning, no root relief (each tip relief relieves the mating root);
    * on a flank whose profile has a corner (``corners``; the double arc's 46 deg
      concave/transition joint), a corner relief of the same amount as the tip relief,
      parabolic, over :data:`CORNER_SHARE` of the active profile on each side: the
      corner is an edge in the contact path, and like a tip it must clear the approach;
    * on a flank whose profile has a transition piece (``transitions``; the double
      arc's transition arc, from the corner to the transition/convex curvature jump), a
      transition relief of the same amount held over the whole piece and running out
      cubically over :data:`TRANSITION_SHARE` of the active profile beyond each end:
      the double arc's working profiles are its convex and concave arcs, and the
      small-radius transition arc would otherwise carry narrow contacts at the
      curvature jump whose peak pressure no affordable grid resolves
      (``docs/contact.md``).

    Parameters
    ----------
    force : float
        ``F_t``: tangential force at the design load (N), > 0.
    face_width : float
        ``b`` (m), > 0.
    profile_a, profile_b : float
        Lengths of the active profiles of both flanks (m) (``FlankCoordinates.profile``).
    stiffness : float
        ``c_gamma`` (N/m per m of face width); default :data:`C_GAMMA`.
    corners : tuple of bool
        Whether flank A's and flank B's profiles have a corner.
    transitions : tuple of bool
        Whether flank A's and flank B's profiles have a transition piece.
    """
    for name, v in (("force", force), ("face_width", face_width), ("profile_a", profile_a),
                    ("profile_b", profile_b), ("stiffness", stiffness)):  # fmt: skip
        if (
            isinstance(v, bool)
            or not isinstance(v, int | float)
            or not (math.isfinite(v) and v > 0)
        ):
            raise ReducerlabError(f"{name}: must be a number > 0; got {v!r}")
    delta = force / (face_width * stiffness)
    if delta > MAX_AMOUNT:
        raise ReducerlabError(
            f"force: {force:.4g} N on a {face_width * 1e3:.4g} mm face deflects the mesh by "
            f"{delta * 1e6:.4g} um (F_t / (b c_gamma)), more than micro-geometry "
            f"({MAX_AMOUNT * 1e3:g} mm) can relieve"
        )
    tip = CROWNED_APPROACH * delta
    if tip > MAX_AMOUNT:
        raise ReducerlabError(
            f"force: {force:.4g} N on a {face_width * 1e3:.4g} mm face needs a tip relief of "
            f"{tip * 1e6:.4g} um (1.651 F_t / (b c_gamma)), more than micro-geometry "
            f"({MAX_AMOUNT * 1e3:g} mm)"
        )
    for name, pair in (("corners", corners), ("transitions", transitions)):
        if not (isinstance(pair, tuple) and len(pair) == 2):
            raise ReducerlabError(f"{name}: must be a pair of booleans; got {pair!r}")
    return PairModifications(*(
        FlankModification(lead_crowning=delta, tip_relief=tip,
                          tip_relief_length=TIP_SHARE * length, relief_shape="parabolic",
                          corner_relief=tip if corner else 0.0,
                          corner_relief_length=CORNER_SHARE * length if corner else 0.0,
                          transition_relief=tip if piece else 0.0,
                          transition_relief_length=TRANSITION_SHARE * length if piece else 0.0)
        for length, corner, piece in zip((profile_a, profile_b), corners, transitions,
                                         strict=True)
    ))  # fmt: skip
