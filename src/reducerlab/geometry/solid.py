"""Closed triangulated solids of generated nutation spiral bevel gears (paper 001).

A gear is built as a *structured* surface, so that it is closed (watertight) by
construction, with no Boolean operations:

* The face is cut into ``n_face`` transverse sections at the cone distances
  ``L_0 = R_m - b/2 ... L_{n-1} = R_m + b/2``. Each section is a closed loop around the
  gear: per tooth, flank ``A`` (from the space to the tip), the top land, flank ``B``
  (tip to space) and the bottom of the following tooth space. Neighbouring sections are
  joined by quadrilaterals (two triangles each), loop point ``i`` to loop point ``i``.
* The blank body closes the loop on a plain cone (the *body cone*) offset from the pitch
  cone: below the root for the external gear, beyond the roots for the internal gear.
* The front (toe) and back (heel) end faces lie on the front and back cones
  ``L = L_0`` and ``L = L_{n-1}`` (perpendicular to the pitch cone); each joins loop
  point ``i`` to body point ``i`` radially.

Cone coordinates of a point ``p`` of the gear frame ``S_i`` (apex at 0, axis ``z_i``):
``L = z cos(delta) + r sin(delta)`` (distance along the pitch-cone generatrix),
``h = r cos(delta) - z sin(delta)`` (signed height above the pitch cone, positive away
from the axis) and the azimuth ``psi = atan2(y, x)``, with ``r = hypot(x, y)``. The
front/back cones are ``L = const``; the tip (face) and root cones of these
uniform-depth teeth are ``h = const`` (offsets of the pitch cone, not cones through the
apex: ``docs/tooth_surfaces.md``).

Flank points on a section are enveloped (``bevel_surface``) from crown points whose
spiral cone distance ``rho`` is solved for, point by point, so that the generated point
lies exactly on ``L = L_j``; the flank is trimmed exactly by the face cone (external
gear: ``h = +h_a``; internal gear: ``h = -h_a``, which removes the basic tooth's
full-round root that would otherwise be the internal gear's tip).

Tooth spaces:

* external gear: the crown gear's tooth tip (the basic profile's root region) cuts the
  space bottom. The space between two teeth is the upper envelope
  ``max(h_B(psi), h_A(psi), -h_f)`` of the two neighbouring flanks' root parts (below
  the mate's tip height ``x = -h_a``) and the root cone: at the heel the two root
  lines leave a gap (filled by the root cone), at the toe they overlap and the space
  bottom is their upper envelope (the crown tooth is the intersection of the two sides);
* internal gear: the space is the basic tooth itself down to the flank ends (profile
  ``u = 1``, the basic tooth's tip line, which has no rounding). The flank ends lie
  deeper than the nominal root cone ``h = +h_a`` (the plane top land of the generating
  tooth reaches beyond the internal gear's root cone off the pitch line). Beyond them
  the space has a root fillet: in each section an arc tangent to each flank at its end
  and to a bottom line the basic profile's clearance ``h_f - h_a`` deeper, or a full
  round where the two arcs meet first (:func:`_internal_space`). Joining the flank
  ends directly (as before issue 29) left a re-entrant corner, where the root stress
  has no converged value.

At a profile corner (the double circular-arc profile's concave/transition junction
turns by 46 deg) both one-sided envelopes are kept as two grid rows at the same profile
parameter, joined by a ruled strip; the exact swept corner surface (or the
intersection edge of the two sides) is not constructed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..kinematics.rotations import rot_z
from .bevel_surface import BevelGear, check_generation, envelope, tooth_flanks
from .profiles import BasicProfile, ProfileError
from .spiral import CrownGear

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

__all__ = [
    "Blank",
    "GearSolid",
    "SolidError",
    "TriangleMesh",
    "build_gear_solid",
    "cone_coordinates",
    "from_cone_coordinates",
    "independent_volume_estimate",
    "require_trimesh",
    "section_counts",
]

Array = NDArray[np.float64]
Progress = Callable[[int, int], None]


#: vertices of a whole-gear triangle mesh at most (``surface --export``): 4 times the
#: 28-tooth example at the finest ``--points 401``
MAX_MESH_VERTICES = 1e8
#: peak bytes per vertex of a whole-gear triangle mesh: the patterned sections, the
#: vertices and two triangles each, and their normals and export buffers (measured 620 B
#: at ``--points 101``)
MESH_BYTES = 800


class SolidError(ProfileError):
    """The gear solid cannot be built (pointed tooth, crossing flanks, bad blank...)."""


def require_trimesh() -> Any:
    """Import :mod:`trimesh` or explain how to install it (the ``cad`` extra)."""
    try:
        import trimesh
    except ImportError:  # pragma: no cover - depends on the environment
        raise SolidError(
            "trimesh is needed for mesh checks and STL/PLY export: install the 'cad' extra "
            "(pip install 'reducerlab[cad]')"
        ) from None
    return trimesh


# --------------------------------------------------------------------------- coordinates


def cone_coordinates(p: Array, delta: float) -> tuple[Array, Array, Array]:
    """``(L, h, psi)`` of points ``p`` (..., 3) of a gear with pitch cone angle ``delta``.

    ``L`` (m) along the pitch-cone generatrix, ``h`` (m) above the pitch cone (away from
    the axis), ``psi`` (rad) the azimuth about the gear axis.
    """
    r = np.hypot(p[..., 0], p[..., 1])
    z = p[..., 2]
    s, c = math.sin(delta), math.cos(delta)
    return z * c + r * s, r * c - z * s, np.arctan2(p[..., 1], p[..., 0])


def from_cone_coordinates(L: Array, h: Array, psi: Array, delta: float) -> Array:
    """Inverse of :func:`cone_coordinates`: points (..., 3) in the gear frame (m)."""
    s, c = math.sin(delta), math.cos(delta)
    r = L * s + h * c
    z = L * c - h * s
    return np.stack(np.broadcast_arrays(r * np.cos(psi), r * np.sin(psi), z), axis=-1)


def _rot_z(p: Array, angle: float) -> Array:
    """Points (..., 3) turned by ``angle`` (rad) about the gear axis ``z_i``."""
    return p @ rot_z(angle).T


def _ruled(
    L: Array, h0: Array, h1: Array, psi0: Array, psi1: Array, t: Array, delta: float
) -> Array:
    """Points (n_face, len(t), 3) at fractions ``t`` of the way from ``(h0, psi0)`` to
    ``(h1, psi1)`` in cone coordinates, on each section ``L``."""
    return from_cone_coordinates(
        L[:, None],
        h0[:, None] + (h1 - h0)[:, None] * t,
        psi0[:, None] + (psi1 - psi0)[:, None] * t,
        delta,
    )


# --------------------------------------------------------------------------- blank


@dataclass(frozen=True)
class Blank:
    """The gear blank: a conical ring bounded by four cones (all lengths in m).

    Attributes
    ----------
    front, back : float
        Cone distances ``L`` of the front (toe) and back (heel) cones, which are
        perpendicular to the pitch cone.
    face : float
        Height ``h`` of the face (tip) cone above the pitch cone: ``+h_a`` for the
        external gear, ``-h_a`` for the internal gear (its teeth point toward the axis).
    root : float
        Nominal root cone height: ``-h_f`` (external), ``+h_a`` (internal: the basic
        tooth's tip line).
    body : float
        Height of the plain body cone that closes the ring: ``root - rim`` (external) or
        ``root + rim`` (internal).
    """

    front: float
    back: float
    face: float
    root: float
    body: float

    @property
    def face_width(self) -> float:
        """``b = back - front`` (m)."""
        return self.back - self.front

    def ring_volume(self, delta: float, h0: float, h1: float) -> float:
        """Volume (m^3) of the ring ``front <= L <= back``, ``h0 <= h <= h1`` (analytic).

        ``V = 2 pi int int (L sin(delta) + h cos(delta)) dh dL`` (Pappus).
        """
        lo, hi = min(h0, h1), max(h0, h1)
        Li, Le = self.front, self.back
        return (
            2
            * math.pi
            * (
                math.sin(delta) * 0.5 * (Le**2 - Li**2) * (hi - lo)
                + math.cos(delta) * (Le - Li) * 0.5 * (hi**2 - lo**2)
            )
        )


def default_blank(
    crown: CrownGear, gear: BevelGear, rim: float | None = None, addendum: float | None = None
) -> Blank:
    """The blank of ``gear`` cut by ``crown``: face width, face/root/body cones.

    Parameters
    ----------
    crown : CrownGear
        Its face ``R_m -+ b/2`` gives the front and back cones.
    gear : BevelGear
    rim : float, optional
        Rim thickness below the nominal root cone (m); default ``2 m_n``.
    addendum : float, optional
        Tooth height above the pitch cone ``h_a`` (m), the same for both gears; default
        the basic profile's tip height (its ``x`` at ``u = 1``).
    """
    prof = crown.profile
    x_root, x_tip = prof.x_range()
    h_a = x_tip if addendum is None else float(addendum)
    t = 2.0 * prof.module if rim is None else float(rim)
    if not 0 < h_a <= x_tip * (1 + 1e-12):
        raise SolidError(
            f"blank.addendum: must lie in (0, {x_tip * 1e3:.6g} mm] (the basic tooth's "
            f"tip height); got {h_a * 1e3:.6g} mm"
        )
    if not 0 < h_a < -x_root:
        raise SolidError(
            f"blank.addendum: must be smaller than the dedendum {-x_root * 1e3:.6g} mm"
        )
    if not t > 0:
        raise SolidError(f"blank.rim: must be > 0 (m); got {t}")
    lo, hi = crown.rho_range
    if gear.kind == "external":
        return Blank(lo, hi, h_a, x_root, x_root - t)
    return Blank(lo, hi, -h_a, x_tip, x_tip + t)


# --------------------------------------------------------------------------- meshes


@dataclass(frozen=True)
class TriangleMesh:
    """A triangle mesh: ``vertices`` (n, 3) in m and ``faces`` (m, 3) vertex indices.

    Faces are oriented counter-clockwise seen from outside (outward normals).
    """

    vertices: Array
    faces: NDArray[np.int64]
    name: str = ""

    @property
    def volume(self) -> float:
        """Enclosed volume (m^3) by the divergence theorem (positive if outward)."""
        v = self.vertices[self.faces]
        return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)

    @property
    def area(self) -> float:
        """Surface area (m^2)."""
        v = self.vertices[self.faces]
        return float(
            0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1).sum()
        )

    def open_edges(self) -> int:
        """Number of edges not shared by exactly two faces with opposite directions."""
        f = self.faces
        e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        n = len(self.vertices)
        key = e[:, 0] * n + e[:, 1]
        rev = e[:, 1] * n + e[:, 0]
        _, counts = np.unique(key, return_counts=True)
        bad = int(np.count_nonzero(counts != 1))
        has_rev = np.isin(key, rev)
        return bad + int(np.count_nonzero(~has_rev))

    def to_trimesh(self) -> trimesh.Trimesh:
        """A :class:`trimesh.Trimesh` (needs the ``cad`` extra); vertices are not merged."""
        tm = require_trimesh()
        return tm.Trimesh(vertices=self.vertices, faces=self.faces, process=False)


@dataclass(frozen=True)
class GearSolid:
    """Transverse sections of a generated gear and its blank; builds closed meshes.

    Attributes
    ----------
    crown, gear, blank :
        What generated it and the blank that bounds it.
    loop : ndarray, shape (n_face, n_pitch, 3)
        One pitch of the toothed loop at each section (m, gear frame): flank ``A``
        (space end to tip end), top land, flank ``B`` (tip end to space end), space
        bottom. The next pitch is this one turned by ``-2 pi / z`` about ``z_i``.
    body : ndarray, shape (n_face, n_pitch, 3)
        Matching points of the body cone (m).
    parts : dict
        Slices of ``loop`` along its second axis: ``"A"``, ``"land"``, ``"B"``,
        ``"space"``.
    L : ndarray, shape (n_face,)
        Cone distances of the sections (m).
    max_residual : float
        Largest relative meshing residual of the flank points.
    """

    crown: CrownGear
    gear: BevelGear
    blank: Blank
    loop: Array
    body: Array
    parts: dict[str, slice]
    L: Array
    max_residual: float
    notes: tuple[str, ...] = field(default=())

    @property
    def pitch_angle(self) -> float:
        """Angular pitch ``2 pi / z`` (rad); tooth ``k`` is tooth 0 turned by ``-k`` of it."""
        return 2 * math.pi / self.gear.teeth

    def _sector_points(self) -> tuple[Array, Array]:
        """Loop and body of one tooth sector, mid-space to mid-space (n_face, n_s, 3)."""
        sp = self.parts["space"]
        n_sp = sp.stop - sp.start
        m = n_sp // 2
        prev = _rot_z(self.loop[:, sp.start + m :], self.pitch_angle)
        prev_b = _rot_z(self.body[:, sp.start + m :], self.pitch_angle)
        loop = np.concatenate([prev, self.loop[:, : sp.start + m + 1]], axis=1)
        body = np.concatenate([prev_b, self.body[:, : sp.start + m + 1]], axis=1)
        return loop, body

    def tooth_mesh(self) -> TriangleMesh:
        """Closed mesh of one tooth sector: the tooth, half of each neighbouring space,
        and its share of the rim, cut by two ruled side walls (for FE sector models)."""
        loop, body = self._sector_points()
        return _closed_mesh(loop, body, cyclic=False, name=f"{self.gear.kind} gear tooth")

    def gear_mesh_estimate(self, control: str = "--points or --tooth") -> Any:
        """The :class:`~reducerlab.budget.Estimate` of :meth:`gear_mesh`: vertices
        (``z`` copies of the section points, loop and body) and :data:`MESH_BYTES` per
        vertex, bounded by :data:`MAX_MESH_VERTICES`; check it before patterning."""
        from ..budget import Estimate

        nf, npch, _ = self.loop.shape
        vertices = 2.0 * nf * npch * self.gear.teeth
        return Estimate(
            f"surface: the whole gear's triangle mesh ({self.gear.teeth} teeth)",
            MESH_BYTES * vertices, vertices, "vertices", MAX_MESH_VERTICES, control,
        )  # fmt: skip

    def gear_mesh(self, progress: Progress | None = None) -> TriangleMesh:
        """Closed mesh of the whole gear (``z`` teeth patterned about the axis); its
        size is checked first (:meth:`gear_mesh_estimate`)."""
        self.gear_mesh_estimate().check()
        z = self.gear.teeth
        nf, npch, _ = self.loop.shape
        loop = np.empty((nf, z * npch, 3))
        body = np.empty_like(loop)
        for k in range(z):
            a = -k * self.pitch_angle
            loop[:, k * npch : (k + 1) * npch] = _rot_z(self.loop, a)
            body[:, k * npch : (k + 1) * npch] = _rot_z(self.body, a)
            if progress is not None:
                progress(k + 1, z)
        return _closed_mesh(loop, body, cyclic=True, name=f"{self.gear.kind} gear")

    def flank_points(self) -> dict[str, tuple[Array, Array]]:
        """Point clouds of the two flanks of tooth 0 on the trimmed grid.

        Returns ``{"A": (points, normals), "B": (points, normals)}``, each (n, 3), m and
        unit outward normals (estimated from the grid, oriented out of the material).
        """
        out = {}
        for key in ("A", "B"):
            s = self.parts[key]
            P = self.loop[:, s]
            n = _grid_normals(P)
            c = P.mean(axis=(0, 1))
            mid = self.body[:, s].mean(axis=(0, 1))
            # outward: away from the body cone
            if np.mean(np.einsum("ijk,k->ij", n, c - mid)) < 0:
                n = -n
            out[key] = (P.reshape(-1, 3), n.reshape(-1, 3))
        return out

    def flank_cloud(self) -> tuple[Array, Array]:
        """Both flanks of tooth 0 as one point cloud: points (n, 3), m, and unit outward
        normals (n, 3), flank A then flank B (:meth:`flank_points`)."""
        fl = self.flank_points()
        return (
            np.concatenate([fl["A"][0], fl["B"][0]]),
            np.concatenate([fl["A"][1], fl["B"][1]]),
        )


def _grid_normals(P: Array) -> Array:
    """Unit normals of a point grid (n0, n1, 3) by central differences."""
    d0 = np.gradient(P, axis=0)
    d1 = np.gradient(P, axis=1)
    n = np.cross(d0, d1)
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    return n / np.where(norm > 0, norm, 1.0)


def _quads(
    a: NDArray[np.int64], b: NDArray[np.int64], c: NDArray[np.int64], d: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Two triangles per quad ``a b c d`` (in that cyclic order)."""
    return np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)])


def _closed_mesh(loop: Array, body: Array, cyclic: bool, name: str) -> TriangleMesh:
    """Close loops (n_face, n, 3) and body points into one oriented triangle mesh."""
    nf, n, _ = loop.shape
    V = np.concatenate([loop.reshape(-1, 3), body.reshape(-1, 3)])
    off = nf * n
    j = np.arange(nf - 1)[:, None]
    i = np.arange(n if cyclic else n - 1)[None, :]
    i1 = (i + 1) % n
    t = lambda jj, ii: (jj * n + ii).ravel()  # noqa: E731
    b = lambda jj, ii: (off + jj * n + ii).ravel()  # noqa: E731
    Jb, Ib, Ib1 = np.broadcast_arrays(j, i, i1)
    faces = [
        _quads(t(Jb, Ib), t(Jb, Ib1), t(Jb + 1, Ib1), t(Jb + 1, Ib)),  # toothed surface
        _quads(b(Jb, Ib), b(Jb + 1, Ib), b(Jb + 1, Ib1), b(Jb, Ib1)),  # body cone
    ]
    ii, ii1 = i.ravel(), i1.ravel()
    first, last = np.zeros_like(ii), np.full_like(ii, nf - 1)
    faces.append(_quads(t(first, ii), b(first, ii), b(first, ii1), t(first, ii1)))  # front
    faces.append(_quads(t(last, ii), t(last, ii1), b(last, ii1), b(last, ii)))  # back
    if not cyclic:
        jj = np.arange(nf - 1)
        z0, zl = np.zeros_like(jj), np.full_like(jj, n - 1)
        faces.append(_quads(t(jj, z0), t(jj + 1, z0), b(jj + 1, z0), b(jj, z0)))
        faces.append(_quads(t(jj, zl), b(jj, zl), b(jj + 1, zl), t(jj + 1, zl)))
    F = np.concatenate(faces).astype(np.int64)
    mesh = TriangleMesh(V, F, name)
    if mesh.volume < 0:
        mesh = TriangleMesh(V, F[:, ::-1].copy(), name)
    return mesh


# --------------------------------------------------------------------------- flanks


@dataclass(frozen=True)
class _Flank:
    """Enveloping of one crown flank onto sections ``L`` (private helper)."""

    crown: CrownGear
    gear: BevelGear
    flank: int
    tooth: float

    def at(self, u: Array, L: Array) -> tuple[Array, Array, Array]:
        """Points on the sections: (points (..., 3), normals, residual) at broadcast
        ``u`` and ``L``. ``u`` below a profile corner by one ulp picks the lower piece."""
        u, L = np.broadcast_arrays(np.asarray(u, float), np.asarray(L, float))
        shape = u.shape
        uf, Lf = u.ravel(), L.ravel()
        delta = self.gear.cone_angle
        R = self.crown.mean_cone_distance

        def gen(rho: Array) -> tuple[Array, Array, Array, Array]:
            rC, nC = self.crown.points(uf, rho, self.flank, self.tooth)
            p, n, _, res, _ = envelope(rC, nC, self.gear)
            return p, n, res, cone_coordinates(p, delta)[0]

        rho = Lf.copy()
        p, n, res, Lp = gen(rho)
        h = 1e-6 * R
        slope = (gen(rho + h)[3] - Lp) / h
        for _ in range(60):
            err = Lp - Lf
            if np.all(np.abs(err) <= 1e-13 * R):
                break
            rho = rho - err / slope
            p, n, res, Lp = gen(rho)
        else:  # pragma: no cover - the chord iteration contracts by ~1e-2 per step
            raise SolidError("solid: could not place flank points on the transverse sections")
        if not np.all(np.abs(res) <= 1e-9):
            raise SolidError(
                "solid: the meshing equation has no solution near the pitch line for some "
                "section points (face width too large for this gear?)"
            )
        return p.reshape(*shape, 3), n.reshape(*shape, 3), np.abs(res).reshape(shape)

    def h_at(self, u: Array, L: Array) -> Array:
        return cone_coordinates(self.at(u, L)[0], self.gear.cone_angle)[1]

    def trim(self, L: Array, target: float, lo: float, hi: float) -> Array:
        """Profile parameter where the flank reaches ``h = target`` on each section
        (bisection; where the flank does not reach it, the nearer end)."""
        a = np.full(L.shape, lo)
        b = np.full(L.shape, hi)
        ga = self.h_at(a, L) - target
        gb = self.h_at(b, L) - target
        ok = np.sign(ga) != np.sign(gb)
        for _ in range(52):
            m = 0.5 * (a + b)
            gm = self.h_at(m, L) - target
            same = np.sign(gm) == np.sign(ga)
            a, ga = np.where(same, m, a), np.where(same, gm, ga)
            b = np.where(same, b, m)
        u = 0.5 * (a + b)
        return np.where(ok, u, np.where(np.abs(ga) < np.abs(gb), lo, hi))


def _corners(profile: BasicProfile, lo: float, hi: float) -> list[tuple[float, bool]]:
    """Breaks of the profile strictly inside ``(lo, hi)``, each with "is a corner"."""
    out = []
    for bk in getattr(profile, "breaks", ()):
        if lo + 1e-9 < bk < hi - 1e-9:
            below = profile.evaluate(np.array([np.nextafter(bk, -1.0)]), 1)
            above = profile.evaluate(np.array([bk]), 1)
            cos = below.nx[0] * above.nx[0] + below.ny[0] * above.ny[0]
            out.append((bk, cos < 1 - 1e-8))
    return out


def _row_grid(
    profile: BasicProfile,
    u_lo: Array,
    u_hi: Array,
    n: int,
    window: tuple[float, float],
    counts: NDArray[np.int64] | None = None,
) -> tuple[Array, NDArray[np.int64]]:
    """Profile parameters (n_rows, n_face) from ``u_lo`` to ``u_hi`` on every section.

    Profile breaks inside ``window`` (a range every section covers) are grid rows on
    all sections (corners twice: one ulp below, then at the break); the rows between
    are spread linearly, ``counts`` per piece (default: in proportion to the pieces'
    parameter lengths on the mean section). Returns the rows and the counts.
    """
    brk = _corners(profile, *window)
    inner = [b for b, _ in brk]
    if counts is None:
        edges = np.array([float(np.mean(u_lo)), *inner, float(np.mean(u_hi))])
        frac = np.abs(np.diff(edges)) / abs(edges[-1] - edges[0])
        counts = np.maximum(2, np.round(frac * (n - 1)).astype(np.int64) + 1)
    rows = []
    edges_lo = [u_lo, *[np.full_like(u_lo, b) for b in inner]]
    edges_hi = [*[np.full_like(u_lo, b) for b in inner], u_hi]
    for k, (a, b, c) in enumerate(zip(edges_lo, edges_hi, counts, strict=True)):
        seg = a[None, :] + (b - a)[None, :] * np.linspace(0.0, 1.0, int(c))[:, None]
        if k < len(inner) and brk[k][1]:
            seg[-1] = np.nextafter(seg[-1], -1.0)  # lower side of the corner
            rows.append(seg)
        else:
            rows.append(seg[:-1] if k < len(inner) else seg)
    return np.concatenate(rows, axis=0), counts


def _unwrap_to(psi: Array, ref: Array) -> Array:
    """``psi`` shifted by multiples of 2 pi to lie within pi of ``ref``."""
    return ref + np.angle(np.exp(1j * (psi - ref)))


def section_counts(points: int) -> dict[str, int]:
    """The section grid of a solid drawn with ``points`` grid points across the profile
    and along the face: ``n_profile``, ``n_face``, ``n_land`` (a fifth of them, at least
    1) and ``n_space`` (half of them, odd, at least 3), as :func:`build_gear_solid`
    takes them."""
    return {
        "n_profile": points,
        "n_face": points,
        "n_land": max(1, points // 5),
        "n_space": max(3, points // 2) | 1,
    }


def build_gear_solid(
    crown: CrownGear,
    gear: BevelGear,
    n_profile: int = 15,
    n_face: int = 11,
    n_land: int = 3,
    n_space: int = 7,
    blank: Blank | None = None,
    rim: float | None = None,
    progress: Progress | None = None,
) -> GearSolid:
    """Sections of the gear generated by ``crown`` and bounded by its blank.

    Parameters
    ----------
    crown : CrownGear
    gear : BevelGear
    n_profile : int
        Grid rows along each trimmed flank (profile corners add one row each).
    n_face : int
        Transverse sections across the face width (>= 2).
    n_land, n_space : int
        Interior points across the top land and across the space bottom.
    blank : Blank, optional
        Default :func:`default_blank` with ``rim``.
    rim : float, optional
        Rim thickness (m) of the default blank.
    progress : callable, optional
        ``progress(done, total)`` after each stage.

    Raises
    ------
    SolidError
        Pointed teeth, flanks of neighbouring teeth crossing above the root, a rim that
        does not clear the tooth spaces, or section points without an envelope.
    """
    grid = (n_profile, n_face, n_land, n_space)
    if (
        any(isinstance(n, bool) or not isinstance(n, (int, np.integer)) for n in grid)
        or n_profile < 3
        or n_face < 2
        or n_land < 1
        or n_space < 1
    ):
        raise SolidError(
            "solid grid: needs integers n_profile >= 3, n_face >= 2, n_land >= 1, "
            "n_space >= 1; got "
            f"{n_profile}, {n_face}, {n_land}, {n_space}"
        )
    check_generation(crown, gear)
    bl = default_blank(crown, gear, rim) if blank is None else blank
    prof = crown.profile
    delta = gear.cone_angle
    ext = gear.kind == "external"
    total = 6
    done = 0

    def tick() -> None:
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    L = np.linspace(bl.front, bl.back, n_face)
    (fa, ta), (fb, tb) = tooth_flanks(gear)
    A = _Flank(crown, gear, fa, ta)
    B = _Flank(crown, gear, fb, tb)
    u_p = prof.pitch_parameter()
    notes: list[str] = []
    # --- flank ranges: tip end trimmed by the face cone, space end
    if ext:
        tip_a, tip_b = A.trim(L, bl.face, u_p, 1.0), B.trim(L, bl.face, u_p, 1.0)
        # the space bottom takes over below the mate's tip height x = -h_a
        split = _profile_param_at(prof, -abs(bl.face))
        space_a, space_b = np.full_like(L, split), np.full_like(L, split)
    else:
        tip_a, tip_b = A.trim(L, bl.face, 0.0, u_p), B.trim(L, bl.face, 0.0, u_p)
        space_a, space_b = np.ones_like(L), np.ones_like(L)
    tick()
    lo_a, hi_a = np.minimum(tip_a, space_a), np.maximum(tip_a, space_a)
    lo_b, hi_b = np.minimum(tip_b, space_b), np.maximum(tip_b, space_b)
    window = (
        float(max(lo_a.max(), lo_b.max())),
        float(min(hi_a.min(), hi_b.min())),
    )
    UA, counts = _row_grid(prof, lo_a, hi_a, n_profile, window)
    UB, _ = _row_grid(prof, lo_b, hi_b, n_profile, window, counts)
    PA, _, rA = A.at(UA, L[None, :])
    PB, _, rB = B.at(UB, L[None, :])
    tick()
    # orient: A from the space end to the tip end, B from the tip end to the space end
    if ext:
        PA_loop, PB_loop = PA, PB[::-1]
    else:
        PA_loop, PB_loop = PA[::-1], PB
    PA_loop = np.swapaxes(PA_loop, 0, 1)  # (n_face, rows, 3)
    PB_loop = np.swapaxes(PB_loop, 0, 1)
    _, ha, pa = cone_coordinates(PA_loop, delta)
    _, hb, pb = cone_coordinates(PB_loop, delta)
    # --- top land on the face cone
    psi_at = pa[:, -1]
    psi_bt = _unwrap_to(pb[:, 0], psi_at)
    h_at, h_bt = ha[:, -1], hb[:, 0]
    width = (psi_at - psi_bt) * (L * math.sin(delta) + bl.face * math.cos(delta))
    pitch_dir = np.sign(np.median(_unwrap_to(pb[:, -1], pa[:, 0]) - pa[:, 0]))
    if np.any(width * pitch_dir >= 0):
        raise SolidError(
            "solid: pointed tooth: the flanks meet below the face cone "
            f"(h = {bl.face * 1e3:.4g} mm); lower the addendum or change the profile"
        )
    t = np.arange(1, n_land + 1) / (n_land + 1)
    land = _ruled(L, h_at, h_bt, psi_at, psi_bt, t, delta)
    tick()
    # --- tooth space between B (tooth 0) and A of the next tooth (turned by -2 pi / z)
    pitch = 2 * math.pi / gear.teeth
    ang = -pitch
    psi_b0 = pb[:, -1]
    psi_a1 = _unwrap_to(pa[:, 0] + ang, psi_b0)
    if np.any((psi_a1 - psi_b0) * pitch_dir <= 0):
        raise SolidError(
            "solid: the flanks of neighbouring teeth cross above the space bottom; reduce "
            "the face width or the module"
        )
    if ext:
        space = _external_space(A, B, L, split, psi_b0, psi_a1, bl.root, n_space, ang, delta)
    else:
        space = _internal_space(A, B, L, PB_loop[:, -1], _rot_z(PA_loop[:, 0], ang),
                                n_space, ang, delta, _root_clearance(prof))  # fmt: skip
    tick()
    loop = np.concatenate([PA_loop, land, PB_loop, space], axis=1)
    n_a, n_l, n_b = PA_loop.shape[1], land.shape[1], PB_loop.shape[1]
    parts = {
        "A": slice(0, n_a),
        "land": slice(n_a, n_a + n_l),
        "B": slice(n_a + n_l, n_a + n_l + n_b),
        "space": slice(n_a + n_l + n_b, loop.shape[1]),
    }
    # --- body cone: the loop's azimuths, made strictly monotone along the loop (steps
    # that turn back, or nearly so, are raised to a floor and the pitch rescaled)
    Ll, hl, pl = cone_coordinates(loop, delta)
    pw = np.unwrap(np.concatenate([pl, pl[:, :1] + ang], axis=1), axis=1) * pitch_dir
    steps = np.maximum(np.diff(pw, axis=1), 0.05 * pitch / loop.shape[1])
    steps *= pitch / steps.sum(axis=1, keepdims=True)
    pu = pw[:, :1] + np.concatenate([np.zeros((len(L), 1)), np.cumsum(steps, 1)[:, :-1]], 1)
    pu = pu * pitch_dir
    if ext and np.any(hl < bl.body):
        raise SolidError("solid: the body cone cuts the tooth spaces; increase the rim")
    if not ext and np.any(hl > bl.body):
        raise SolidError(
            f"blank.rim: the body cone h = {bl.body * 1e3:.4g} mm does not clear the tooth "
            f"spaces (deepest at h = {hl.max() * 1e3:.4g} mm); increase the rim"
        )
    back = np.diff(np.unwrap(pl, axis=1) * pitch_dir, axis=1)
    if np.any(back < 0):
        r_back = (Ll[:, 1:] * math.sin(delta) + hl[:, 1:] * math.cos(delta)) * back
        notes.append(
            "a transverse section turns back in azimuth by up to "
            f"{-r_back.min() * 1e6:.3g} um (a profile corner or an overhanging flank): the "
            "end faces overlap there by that much"
        )
    body = from_cone_coordinates(Ll, np.full_like(hl, bl.body), pu, delta)
    tick()
    res = float(max(rA.max(), rB.max()))
    solid = GearSolid(crown, gear, bl, loop, body, parts, L, res, tuple(notes))
    tick()
    return solid


def _profile_param_at(profile: BasicProfile, x: float) -> float:
    """Profile parameter ``u`` of the flank at height ``x`` (m)."""
    from scipy.optimize import brentq

    f = lambda u: float(profile.evaluate(np.array([u]), 1).x[0]) - x  # noqa: E731
    if f(0.0) > 0 or f(1.0) < 0:
        raise SolidError(f"solid: the profile does not reach height {x * 1e3:.4g} mm")
    return brentq(f, 0.0, 1.0, xtol=1e-14)


def _external_space(
    A: _Flank,
    B: _Flank,
    L: Array,
    split: float,
    psi_b0: Array,
    psi_a1: Array,
    h_root: float,
    n: int,
    ang: float,
    delta: float,
) -> Array:
    """Space bottom of the external gear: ``max(h_B, h_A(next tooth), root cone)``."""
    nd = 64
    u = np.linspace(0.0, split, nd)[:, None]
    PB, _, _ = B.at(u, L[None, :])
    PA, _, _ = A.at(u, L[None, :])
    _, hB, sB = cone_coordinates(PB, delta)
    _, hA, sA = cone_coordinates(_rot_z(PA, ang), delta)
    sB = _unwrap_to(sB, psi_b0[None, :])
    sA = _unwrap_to(sA, psi_b0[None, :])
    sgn = np.sign(np.median(psi_a1 - psi_b0))
    t = 0.5 * (1 - np.cos(np.pi * np.arange(1, n + 1) / (n + 1)))
    out_h = np.empty((len(L), n))
    out_p = psi_b0[:, None] + (psi_a1 - psi_b0)[:, None] * t
    for j in range(len(L)):
        q = out_p[j] * sgn
        h = np.full(n, h_root)
        for s, hh in ((sB[:, j] * sgn, hB[:, j]), (sA[:, j] * sgn, hA[:, j])):
            ds = np.diff(s)
            if not (np.all(ds > 0) or np.all(ds < 0)):
                raise SolidError(
                    "solid: the root part of a flank folds over in a transverse section "
                    "(undercut in the root); the space bottom cannot be built"
                )
            inside = (q >= s.min()) & (q <= s.max())
            order = np.argsort(s)
            val = np.interp(q, s[order], hh[order])
            h = np.where(inside, np.maximum(h, val), h)
        out_h[j] = h
    return from_cone_coordinates(L[:, None], out_h, out_p, delta)


def _root_clearance(profile: BasicProfile) -> float:
    """Depth (m) by which the internal gear's tooth space reaches beyond the flank ends:
    the external gear's clearance ``h_f - h_a`` of the basic profile (ISO 53: 0.25 m_n,
    GB/T 12759: 0.2 m_n), at least 0.1 m_n."""
    x_root, x_tip = profile.x_range()
    return max(-x_root - x_tip, 0.1 * profile.module)


def _root_fillet(Pb: Array, nb: Array, Pa: Array, na: Array, clearance: float) -> Array:
    """Dense path (2k, 2) in section coordinates ``(h, v)`` (``h`` deeper positive) from
    the flank end ``Pb`` round a fillet, along the bottom, round the other fillet to
    ``Pa``; ``nb``, ``na``: unit normals of the flanks at their ends, into the space.

    Each fillet circle is tangent to its flank at the end (centre ``P + rho n``) and to
    the bottom line ``h = H``: ``rho = (H - h_P) / (1 + n_h)``, with ``H`` the deeper end
    plus ``clearance``, or lower where the two circles would pass each other (their
    centres' ``v`` is linear in ``H``: solved for equal ``v``, a full-round root)."""
    if nb[0] >= 1 - 1e-9 or na[0] >= 1 - 1e-9:  # pragma: no cover - flank along the bottom
        raise SolidError("solid: the internal gear's flank ends point into the root")
    kb, ka = nb[1] / (1.0 + nb[0]), na[1] / (1.0 + na[0])
    H = max(Pb[0], Pa[0]) + clearance
    if Pb[1] + (H - Pb[0]) * kb > Pa[1] + (H - Pa[0]) * ka:
        H = (Pa[1] - Pb[1] + kb * Pb[0] - ka * Pa[0]) / (kb - ka)
        if max(Pb[0], Pa[0]) >= H:
            raise SolidError(
                "solid: no root fillet fits the internal gear's tooth space (its flank "
                "ends are too close); change the profile"
            )
    rb, ra = (H - Pb[0]) / (1.0 + nb[0]), (H - Pa[0]) / (1.0 + na[0])
    cb, ca = Pb + rb * nb, Pa + ra * na
    k = 400
    # angles in (h, v) from the centres: 0 is the bottom's tangent point (+h)
    sb = np.linspace(math.atan2(*(Pb - cb)[::-1]), 0.0, k)
    sa = np.linspace(0.0, math.atan2(*(Pa - ca)[::-1]), k)
    return np.concatenate([
        np.stack([cb[0] + rb * np.cos(sb), cb[1] + rb * np.sin(sb)], 1),
        np.stack([ca[0] + ra * np.cos(sa), ca[1] + ra * np.sin(sa)], 1),
    ])  # fmt: skip


def _internal_space(
    A: _Flank,
    B: _Flank,
    L: Array,
    end_b: Array,
    end_a: Array,
    n: int,
    ang: float,
    delta: float,
    clearance: float,
) -> Array:
    """Space bottom of the internal gear: a root fillet from each flank end to a bottom
    line ``clearance`` beyond the deeper flank end (n_face, n, 3).

    The internal gear's tooth space is the basic tooth, whose tip end (profile ``u = 1``)
    has no rounding: joining the two flank ends directly leaves a re-entrant corner in
    the root (tangent turn 65 deg for the involute of paper 001), where the elastic
    stress is singular. A cutter gives the root a fillet instead. In each transverse
    section, in the coordinates ``(h, v)`` with ``v = psi R cos(beta)`` (``R`` the
    radius of the flank end, ``beta`` the local spiral angle of the flank-end line, so
    that ``v`` measures across the tooth as the normal section does), a circle tangent
    to each flank at its end (the flank's tangent there from the envelope) touches the
    bottom line ``h = h_end,max + clearance``; where the two circles would pass each
    other the bottom is raised until they meet (a full-round root). The fillet-bottom-
    fillet path is sampled at ``n`` points evenly by arc length. The flanks themselves,
    and so the contact, are unchanged; the space is deeper than before by
    ``clearance``."""
    eps = 1e-4
    _, hb, pb = cone_coordinates(end_b, delta)
    _, ha, pa = cone_coordinates(end_a, delta)
    sgn_pitch = float(np.sign(np.median(np.angle(np.exp(1j * (pa - pb))))))
    near_b, _, _ = B.at(np.full_like(L, 1.0 - eps), L)
    near_a, _, _ = A.at(np.full_like(L, 1.0 - eps), L)
    _, hnb, pnb = cone_coordinates(near_b, delta)
    _, hna, pna = cone_coordinates(_rot_z(near_a, ang), delta)
    pa = _unwrap_to(pa, pb)
    pnb, pna = _unwrap_to(pnb, pb), _unwrap_to(pna, pb)
    R = L * math.sin(delta) + 0.5 * (ha + hb) * math.cos(delta)
    # local spiral angle of the flank-end line: tan(beta) = R dpsi/dL (n_face >= 2)
    tanb = R * np.gradient(np.unwrap(0.5 * (pa + pb)), L)
    scale = R / np.sqrt(1.0 + tanb**2) * sgn_pitch  # v = (psi - psi_b) * scale
    out_h = np.empty((len(L), n))
    out_p = np.empty((len(L), n))
    for j in range(len(L)):
        ends = []
        for h0, p0, h1, p1, inward in ((hb, pb, hnb, pnb, 1.0), (ha, pa, hna, pna, -1.0)):
            P = np.array([h0[j], (p0[j] - pb[j]) * scale[j]])
            t = P - np.array([h1[j], (p1[j] - pb[j]) * scale[j]])
            t /= np.hypot(*t)
            nrm = np.array([-t[1], t[0]])
            if nrm[1] * inward < 0:  # into the space: toward the other flank end
                nrm = -nrm
            ends.append((P, nrm))
        path = _root_fillet(*ends[0], *ends[1], clearance)
        seg = np.hypot(*np.diff(path, axis=0).T)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        q = s[-1] * np.arange(1, n + 1) / (n + 1)
        out_h[j] = np.interp(q, s, path[:, 0])
        out_p[j] = pb[j] + np.interp(q, s, path[:, 1]) / scale[j]
    return from_cone_coordinates(L[:, None], out_h, out_p, delta)


# --------------------------------------------------------------------------- estimate


def _tooth_area(
    profile: BasicProfile, x_lo: float, x_hi: float, n: int = 4001
) -> tuple[float, float]:
    """Area (m^2) and first moment about the pitch line ``int x dA`` (m^3) of the basic
    tooth ``T`` between the heights ``x_lo`` and ``x_hi`` (normal section)."""
    u0 = _profile_param_at(profile, x_lo)
    u1 = _profile_param_at(profile, x_hi)
    u = np.linspace(u0, u1, n)
    p = profile.evaluate(u, 1)
    # closed polygon: +1 flank up, across the top, -1 flank down, across the bottom
    x = np.concatenate([p.x, p.x[::-1]])
    y = np.concatenate([p.y, -p.y[::-1]])
    xs, ys = np.roll(x, -1), np.roll(y, -1)
    cr = y * xs - ys * x  # shoelace in the (y, x) plane
    area = 0.5 * cr.sum()
    mom = (cr * (x + xs)).sum() / 6.0
    return abs(area), mom * np.sign(area)


def _root_fillet_area(profile: BasicProfile) -> tuple[float, float]:
    """Area (m^2) and first moment about the pitch line (m^3) of the internal gear's
    root-fillet space beyond the basic tooth's tip line, in the normal section: the
    fillet path of :func:`_root_fillet` from the basic profile's two flank ends (a
    construction in the profile plane, independent of the generated sections)."""
    p = profile.evaluate(np.array([1.0]), 1)
    x, y, nx, ny = float(p.x[0]), float(p.y[0]), float(p.nx[0]), float(p.ny[0])
    # (h, v) = (x, y); into the space (the basic tooth) is against T's outward normal
    path = _root_fillet(np.array([x, -y]), np.array([-nx, ny]), np.array([x, y]),
                        np.array([-nx, -ny]), _root_clearance(profile))  # fmt: skip
    xs = np.concatenate([[x], path[:, 0], [x]])
    ys = np.concatenate([[-y], path[:, 1], [y]])
    xn, yn = np.roll(xs, -1), np.roll(ys, -1)
    cr = ys * xn - yn * xs
    area = 0.5 * cr.sum()
    return abs(area), float((cr * (xs + xn)).sum() / 6.0) * float(np.sign(area))


def independent_volume_estimate(solid: GearSolid) -> dict[str, float]:
    """Volume of the gear from the blank and the basic tooth, without the mesh (m^3).

    ``V = V_ring + z V_tooth`` (external) or ``V_ring + z V_tooth`` with the internal
    gear's tooth the space of the basic tooth ``T``. ``V_ring`` is the conical ring
    between the body cone and the nominal root cone (analytic, :meth:`Blank.ring_volume`);
    the tooth volume sweeps the normal section of ``T`` (area ``A``, first moment ``Q``
    about the pitch line, between the root and face heights) along the tooth line, whose
    length is ``b / cos(beta)`` for a logarithmic spiral, with the first-order cone
    correction ``r / r_pitch = 1 + h / (L tan(delta))``:

    ``V_tooth = (A b + Q ln(L_e / L_i) / tan(delta)) / cos(beta)``.

    The internal gear's spaces also lose the root fillets beyond the basic tooth's tip
    line (:func:`_root_fillet_area`, normal section). Neglected: the difference between
    the generated (conjugate) tooth and ``T`` (for the internal gear, its flank ends lie
    up to 0.15 m_n deeper than ``T``'s tip line).
    """
    bl, g, c = solid.blank, solid.gear, solid.crown
    prof = c.profile
    delta = g.cone_angle
    h_a = abs(bl.face)
    if g.kind == "external":
        A, Q = _tooth_area(prof, bl.root, h_a)
    else:
        AT, QT = _tooth_area(prof, -h_a, h_a)
        AF, QF = _root_fillet_area(prof)
        A, Q = prof.pitch * 2 * h_a - AT - AF, -QT - QF
    ring = bl.ring_volume(delta, bl.body, bl.root)
    cb = math.cos(c.spiral_angle)
    tooth = (A * bl.face_width + Q * math.log(bl.back / bl.front) / math.tan(delta)) / cb
    return {"ring": ring, "tooth": tooth, "total": ring + g.teeth * tooth}
