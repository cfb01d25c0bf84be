"""Quality tetrahedral meshes of generated bevel gears (issue 14, paper 000 §4).

The gear is rebuilt as an OpenCASCADE solid inside gmsh and meshed by gmsh's
tetrahedral mesher; nothing is tessellated by hand:

1. **Tooth space.** One tooth space is a loft (``addThruSections``) through closed
   wires on the transverse sections ``L = const``: flank ``B`` of tooth 0 (tip to root),
   the space bottom, flank ``A`` of tooth 1 (root to tip), each an interpolating spline
   through the enveloped points of :func:`~reducerlab.geometry.solid.build_gear_solid`,
   closed above the face cone; the loft is cubic across the sections. The sections
   reach ``ext`` beyond the toe and the heel (the crown gear is widened by ``2 ext``)
   so that the cut passes cleanly through the end faces. The sector solid built from
   them is kept (BREP text, by a key of these numbers) for the next mesh of the same
   gear in the process.
2. **Sector.** The blank ring (front/back cones, face cone, body cone ``rim`` beyond the
   root, :func:`~reducerlab.geometry.solid.default_blank`) is revolved over one angular
   pitch ``2 pi / z``; the three tooth spaces that can meet it are cut away; the blank
   features (web, hub, bore: :class:`BlankFeatures`) are fused on.
3. **Periodic mesh.** The two side walls of the sector are made periodic (the second is
   the first turned by one pitch), the sector is meshed with a size field (``tooth``
   size in the tooth band, growing to ``body`` size one tooth depth below the root), and
   the ``z`` rotated copies are joined on their matching walls: a conforming mesh of the
   whole gear, every tooth meshed identically. Curved quadratic elements that fold (a
   mid-edge node moved onto a sharply turning surface: Jacobian ratio below
   :data:`~reducerlab.fe.quality.MIN_JACOBIAN_RATIO`) get straight edges first
   (:func:`~reducerlab.fe.quality.mend_curved_tets`), or the mesh is refused.

Lengths are metres at the interface (gmsh works in millimetres inside).
"""

from __future__ import annotations

import contextlib
import dataclasses
import itertools
import math
import signal
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..budget import Estimate
from ..errors import ReducerlabError
from ..geometry.bevel_surface import BevelGear
from ..geometry.solid import Blank, build_gear_solid, cone_coordinates, default_blank
from ..geometry.spiral import CrownGear

__all__ = [
    "BlankFeatures",
    "GearBodyMesh",
    "MeshError",
    "MeshSizes",
    "check_blank",
    "check_sizes",
    "element_density",
    "gmsh_session",
    "mesh_estimate",
    "mesh_gear",
    "sector_walls",
    "store_solids",
    "stored_solids",
    "tet_options",
]

Array = NDArray[np.float64]
Stage = Callable[[str], None]
MM = 1e3  # gmsh works in mm
#: gmsh's 10-node tetrahedron numbers its last two edges (2-3, 1-3) the other way round
#: from VTK/meshio/scikit-fem (1-3, 2-3).
GMSH_TO_VTK = np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])


class MeshError(ReducerlabError):
    """The gear body cannot be meshed (unmeshable solid, mesh too coarse, ...)."""


@dataclass(frozen=True)
class BlankFeatures:
    """Web, hub and bore of a gear blank (m); none of them: the rim ring alone.

    Paper 000 does not give its blanks (``docs/assumptions.md``). The web is a plate
    perpendicular to the gear axis at the heel (large) end: under the rim for an external
    gear, behind the heel, clear of the tooth ends, for an internal gear. The hub is a
    cylinder around the bore, centred on the web.

    Attributes
    ----------
    bore : float or None
        Bore diameter (m). None: no web, the rim ring is the whole body.
    web : float
        Web thickness along the axis (m).
    hub : float
        Hub outer diameter (m), > ``bore``.
    hub_length : float
        Hub length along the axis (m), >= ``web``.
    """

    bore: float | None = None
    web: float = 0.0
    hub: float = 0.0
    hub_length: float = 0.0

    def __post_init__(self) -> None:
        if self.bore is None:
            return
        for name in ("bore", "web", "hub", "hub_length"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise MeshError(f"blank.{name}: must be a length > 0, got {v!r}")
        if not self.hub > self.bore:
            raise MeshError(
                f"blank.hub: the hub diameter {self.hub * 1e3:.5g} mm must exceed the bore "
                f"{self.bore * 1e3:.5g} mm"
            )
        if not self.hub_length >= self.web:
            raise MeshError(
                f"blank.hub_length: {self.hub_length * 1e3:.5g} mm must be >= the web "
                f"thickness {self.web * 1e3:.5g} mm"
            )

    @classmethod
    def default(cls, bore: float | None, rim: float, face_width: float) -> BlankFeatures:
        """Web ``1.5 rim`` thick, hub ``1.6 bore`` across and ``max(2 web, b)`` long
        (proportions of forged gear blanks; ``docs/assumptions.md``)."""
        if bore is None:
            return cls()
        web = 1.5 * rim
        return cls(bore, web, 1.6 * bore, max(2 * web, face_width))


#: The root band of a bevel gear's mesh refined to ``MeshSizes.fillet``: from
#: ``FILLET_BAND[0]`` m_n below the root cone to ``FILLET_BAND[1]`` m_n above it (the
#: tooth spaces' bottoms and fillets up to the active flanks' root-side edges, 0.375 m_n
#: above the root cone on the nutation gears), graded back to the tooth size over
#: ``FILLET_GRADING`` m_n on either side (docs/assumptions.md; a band of 0.25 / 0.65 /
#: 0.5 m_n gave the same root stress to 0.4 % at 1.4x these DOFs).
FILLET_BAND = (0.1, 0.45)
FILLET_GRADING = 0.3


@dataclass(frozen=True)
class MeshSizes:
    """Target element sizes (m): ``tooth`` in the tooth band, ``body`` in the blank;
    ``fillet`` (optional, bevel gears' :func:`mesh_gear` only) in the root band
    (:data:`FILLET_BAND`), at most ``tooth`` (equal: no refinement)."""

    tooth: float
    body: float
    fillet: float | None = None

    def __post_init__(self) -> None:
        for name in ("tooth", "body"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise MeshError(f"mesh size {name}: must be a length > 0, got {v!r}")
        f = self.fillet
        if f is not None and not (
            isinstance(f, int | float) and not isinstance(f, bool) and math.isfinite(f)
            and 0 < f <= self.tooth
        ):  # fmt: skip
            raise MeshError(
                f"mesh size fillet: must be a length > 0 and at most the tooth size "
                f"{self.tooth!r} m, got {f!r}"
            )

    def local(self, below_root: Array, module: float, depth: float) -> Array:
        """The element size (m) of :func:`mesh_gear`'s size field at heights
        ``below_root`` (m, positive into the blank, negative into the teeth) from the root
        cone: ``tooth`` in the teeth, growing linearly to ``body`` one tooth ``depth``
        (m) into the blank; with ``fillet``, at most ``fillet`` in the root band
        (:data:`FILLET_BAND`, in modules ``module``), growing from there by ``tooth -
        fillet`` per :data:`FILLET_GRADING` modules (so the tooth size after one grading
        length, and not capping the coarser rim beyond)."""
        d = np.asarray(below_root, dtype=float)
        a, b = self.tooth, self.body
        s = a + (b - a) * np.clip(d / depth, 0.0, 1.0)
        if self.fillet is not None and self.fillet < a:
            lo, hi = FILLET_BAND
            e = np.maximum(np.maximum(d - lo * module, -d - hi * module), 0.0)
            # growing on at the same rate beyond the grading: the plain rule takes over
            s = np.minimum(s, self.fillet + (a - self.fillet) * e / (FILLET_GRADING * module))
        return s

    @classmethod
    def default(cls, module: float, level: int = 0) -> MeshSizes:
        """The default mesh, ``tooth = 0.6 m_n``, ``body = 1.5 m_n``, halved ``level``
        times (the convergence study refines it once, ``level = 1``)."""
        f = 0.5**level
        return cls(0.6 * module * f, 1.5 * module * f)

    def refined(self, factor: float = 0.5) -> MeshSizes:
        """All sizes times ``factor``."""
        f = None if self.fillet is None else self.fillet * factor
        return MeshSizes(self.tooth * factor, self.body * factor, f)


@dataclass(frozen=True)
class GearBodyMesh:
    """A conforming quadratic tetrahedral mesh of a whole gear.

    Attributes
    ----------
    points : ndarray (n, 3)
        Vertices (m), gear frame (apex at the origin, axis ``z``).
    tets : ndarray (m, 10)
        Quadratic tetrahedra (corners, then the mid-edge nodes of edges 0-1, 1-2, 0-2,
        0-3, 1-3, 2-3: VTK/meshio order), positively oriented; the mid-edge nodes lie on
        the curved surfaces (except on the edges of elements straightened because the
        curved element folded, ``fe.quality``).
    gear : BevelGear
    blank : Blank
        The ring's cones (cone distances and heights, m).
    features : BlankFeatures
    sizes : MeshSizes
    bore_radius : float or None
        Radius of the bore (m) when the blank has one.
    mount_z : float
        Axial position (m) of the mounting face: the web's outer face, or the heel end of
        the ring without a web.
    sector_tets : int
        Tetrahedra per tooth sector.
    """

    points: Array
    tets: NDArray[np.int64]
    gear: BevelGear
    blank: Blank
    features: BlankFeatures
    sizes: MeshSizes
    bore_radius: float | None
    mount_z: float
    sector_tets: int

    @property
    def volume(self) -> float:
        """Volume of the straight-sided tetrahedra (m^3; the curved mesh holds a little
        more)."""
        p = self.points[self.tets[:, :4]]
        d = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
        return float(d.sum() / 6.0)

    @property
    def corners(self) -> NDArray[np.int64]:
        """Indices of the points that are tetrahedron corners (not mid-edge nodes)."""
        return np.unique(self.tets[:, :4])

    def skfem(self) -> Any:
        """The mesh as a :class:`skfem.MeshTet2` (quadratic, curved geometry)."""
        import meshio
        from skfem.io.meshio import from_meshio

        return from_meshio(meshio.Mesh(self.points, [("tetra10", self.tets)]))


def tet_options(gmsh: Any) -> None:
    """Meshing options of the gear sectors: sizes from the background field only,
    Frontal-Delaunay surfaces, HXT tetrahedra, optimised."""
    for name, value in (
        ("Mesh.MeshSizeExtendFromBoundary", 0),
        ("Mesh.MeshSizeFromPoints", 0),
        ("Mesh.MeshSizeFromCurvature", 0),
        ("Mesh.Algorithm", 6),
        ("Mesh.Algorithm3D", 10),
        ("Mesh.Optimize", 1),
    ):
        gmsh.option.setNumber(name, value)


@contextlib.contextmanager
def gmsh_session() -> Iterator[Any]:
    """A gmsh session, initialised quietly (no config files, no terminal output) and
    finalised on exit; the ``gmsh`` module is what the ``with`` statement binds.

    Raises
    ------
    MeshError
        When the caller already has gmsh initialised.
    """
    import gmsh

    if gmsh.isInitialized():  # pragma: no cover - a caller's own gmsh session
        raise MeshError("gmsh is already initialised by the caller: finalise it first")
    pipe = signal.getsignal(signal.SIGPIPE) if hasattr(signal, "SIGPIPE") else None
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    if pipe is not None and threading.current_thread() is threading.main_thread():
        # gmsh sets SIGPIPE back to its default action (end the process): Python ignores
        # it and raises BrokenPipeError instead, which the worker pools rely on (a pipe
        # to a worker that died, analysis/contact_workers.py)
        signal.signal(signal.SIGPIPE, pipe)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.Verbosity", 1)
        yield gmsh
    finally:
        gmsh.finalize()


def _rot(p: Array, a: float) -> Array:
    c, s = math.cos(a), math.sin(a)
    return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1], p[..., 2]], -1)


def _rz(L: float, h: float, delta: float) -> tuple[float, float]:
    """``(r, z)`` of cone coordinates ``(L, h)``."""
    s, c = math.sin(delta), math.cos(delta)
    return L * s + h * c, L * c - h * s


def _turns(p: Array) -> Array:
    """Turning angles (deg) of polylines ``p`` (..., n, 3) at their interior points."""
    d = np.diff(p, axis=-2)
    u = d / np.linalg.norm(d, axis=-1, keepdims=True)
    cos = np.einsum("...ij,...ij->...i", u[..., 1:, :], u[..., :-1, :])
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _corners_of(paths: Array) -> tuple[Array, list[int]]:
    """The section polylines (sections, n, 3) without their switchbacks, and where
    their splines break (the same points on every section, so that every wire has the
    same edges for the loft).

    At a profile corner the two one-sided envelopes leave a short step that turns back
    on itself (the ruled corner strip of :mod:`~reducerlab.geometry.solid`); a point
    where a polyline turns by more than 120 deg on any section is such a step and is
    dropped. The polylines are then split where one turns by more than 30 deg (the
    profile corner, the space bottom's junction with the flanks): an interpolating
    spline through a corner would overshoot into notches that only a fine mesh
    resolves.
    """
    p = np.asarray(paths)
    while p.shape[1] > 3:
        t = _turns(p).max(axis=0)
        k = int(np.argmax(t))
        if t[k] <= 120.0:
            break
        p = np.delete(p, k + 1, axis=1)
    t = _turns(p).max(axis=0)
    n = p.shape[1]
    ends = sorted({0, n - 1, *(int(i) + 1 for i in np.flatnonzero(t > 30.0))})
    return p, ends


@dataclass(frozen=True)
class _Section:
    """One closed transverse section of the tooth space (mm): the flank-space-flank
    path, the indices of its corners (spline ends) and the cap above the face cone."""

    path: Array
    ends: tuple[int, ...]
    cap: Array


def _space_sections(crown: CrownGear, gear: BevelGear, rim: float, ext: float) -> list[_Section]:
    """The sections of one tooth space on the widened gear (the numbers the loft is
    built from, and so the key of the solid)."""
    wide = dataclasses.replace(crown, face_width=crown.face_width + 2 * ext)
    n_face = max(7, math.ceil(wide.face_width / crown.profile.module * 2.5) | 1)
    solid = build_gear_solid(wide, gear, n_profile=21, n_face=n_face, n_land=2, n_space=9, rim=rim)
    bl = default_blank(crown, gear, rim)
    delta = gear.cone_angle
    out_sign = 1.0 if gear.kind == "external" else -1.0
    above = bl.face + out_sign * 0.75 * crown.profile.module
    A, B, sp = solid.parts["A"], solid.parts["B"], solid.parts["space"]
    paths = np.stack([
        np.concatenate([solid.loop[j, B], solid.loop[j, sp],
                        _rot(solid.loop[j, A], -solid.pitch_angle)])
        for j in range(solid.loop.shape[0])
    ])  # fmt: skip
    paths, ends = _corners_of(paths)
    out = []
    for path in paths:
        L, _, psi = cone_coordinates(path, delta)
        psi = np.unwrap(psi)
        Lj = float(np.mean(L))
        top = np.linspace(psi[-1], psi[0], 7)
        r, z = _rz(Lj, above, delta)
        cap = np.stack([r * np.cos(top), r * np.sin(top), np.full_like(top, z)], -1)
        out.append(_Section(path * MM, tuple(int(e) for e in ends), cap * MM))
    return out


def _space_wires(occ: Any, sections: list[_Section]) -> list:
    """Closed wires of the tooth-space sections in the gmsh model."""
    wires = []
    for sec in sections:
        tags = [occ.addPoint(*q) for q in sec.path]
        cap_tags = [occ.addPoint(*q) for q in sec.cap]
        curves = [occ.addSpline(tags[a : b + 1]) for a, b in itertools.pairwise(sec.ends)]
        curves += [
            occ.addLine(tags[-1], cap_tags[0]),
            occ.addSpline(cap_tags),
            occ.addLine(cap_tags[-1], tags[0]),
        ]
        wires.append(occ.addWire(curves))
    return wires


def _revolve_polygon(occ: Any, rz: list[tuple[float, float]], phi0: float, angle: float) -> list:
    """Volume tags of a meridional polygon (m) revolved from ``phi0`` over ``angle``."""
    c, s = math.cos(phi0), math.sin(phi0)
    pts = [occ.addPoint(r * c * MM, r * s * MM, z * MM) for r, z in rz]
    lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    face = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    return [e for e in occ.revolve([(2, face)], 0, 0, 0, 0, 0, 1, angle) if e[0] == 3]


def _feature_polygons(
    gear: BevelGear, bl: Blank, f: BlankFeatures, module: float
) -> tuple[list[list[tuple[float, float]]], float]:
    """Meridional polygons ``(r, z)`` of the web and hub, and the mounting-face ``z``."""
    delta = gear.cone_angle
    s, c = math.sin(delta), math.cos(delta)
    mid = 0.5 * (bl.root + bl.body)  # mid-rim cone: the web overlaps the rim there
    if f.bore is None:
        z_heel = max(_rz(bl.back, bl.body, delta)[1], _rz(bl.back, bl.face, delta)[1])
        return [], z_heel
    rb, rh = 0.5 * f.bore, 0.5 * f.hub
    if gear.kind == "external":
        z1 = _rz(bl.back, mid, delta)[1]
        z0 = z1 - f.web
        if z0 < _rz(bl.front, mid, delta)[1]:
            raise MeshError(
                f"blank.web: {f.web * 1e3:.5g} mm is thicker than the rim reaches along the axis"
            )

        def r_mid(z: float) -> float:  # r on the mid-rim cone at height z
            return (mid + z * s) / c

        r_in = _rz(bl.back, bl.body, delta)[0]
        if not rh < min(r_mid(z0), r_in) - 0.5 * module:
            raise MeshError(
                f"blank.hub: {f.hub * 1e3:.5g} mm across does not fit inside the rim "
                f"(inner diameter {2 * r_in * 1e3:.5g} mm)"
            )
        web = [(rb, z0), (r_mid(z0), z0), (r_mid(z1), z1), (rb, z1)]
        zc = z0
    else:
        A = _rz(bl.back, bl.root, delta)
        B = _rz(bl.back, bl.body, delta)
        r_tip, z_tip = _rz(bl.back, bl.face, delta)
        z0 = z_tip + 0.5 * module  # clear of the teeth's heel ends
        z1 = z0 + f.web
        if not rh < r_tip - 0.5 * module:
            raise MeshError(
                f"blank.hub: {f.hub * 1e3:.5g} mm across does not fit inside the teeth "
                f"(tip diameter {2 * r_tip * 1e3:.5g} mm at the heel)"
            )
        a_in = _rz(bl.back - 0.5 * module, bl.root, delta)
        b_in = _rz(bl.back - 0.5 * module, bl.body, delta)
        web = [a_in, b_in, (B[0], z1), (rb, z1), (rb, z0), (A[0], z0)]
        zc = z1
    z_mid = 0.5 * (web[0][1] + zc) if gear.kind == "external" else 0.5 * (z0 + z1)
    hub = [
        (rb, z_mid - 0.5 * f.hub_length),
        (rh, z_mid - 0.5 * f.hub_length),
        (rh, z_mid + 0.5 * f.hub_length),
        (rb, z_mid + 0.5 * f.hub_length),
    ]
    mount = (
        (z_mid + 0.5 * f.hub_length) if gear.kind == "internal" else (z_mid - 0.5 * f.hub_length)
    )
    return [web, hub], mount


def _side_surfaces(gmsh: Any, phi: float, tol: float) -> list[int]:
    """Boundary surfaces of the model lying in the half-plane at azimuth ``phi``."""
    n = np.array([-math.sin(phi), math.cos(phi), 0.0])
    e = np.array([math.cos(phi), math.sin(phi), 0.0])
    out = []
    for _, tag in gmsh.model.getEntities(2):
        cm = np.array(gmsh.model.occ.getCenterOfMass(2, tag))
        if abs(cm @ n) < tol and cm @ e > 0:
            # and its points all lie on it (sample the parametric domain)
            b = gmsh.model.getParametrizationBounds(2, tag)
            uv = np.array([[u, v] for u in np.linspace(b[0][0], b[1][0], 4)
                           for v in np.linspace(b[0][1], b[1][1], 4)]).ravel()  # fmt: skip
            xyz = np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3)
            if np.all(np.abs(xyz @ n) < tol):
                out.append(tag)
    return out


def element_density(
    crown: CrownGear,
    gear: BevelGear,
    rim: float,
    features: BlankFeatures,
    sizes: MeshSizes,
    sectors: int | None = None,
) -> float:
    """``sum V / s^3`` over the gear body (dimensionless): its volume in cubes of the
    local element size ``s`` of :func:`mesh_gear`'s size field (the tooth band at the
    tooth size, taken whole, spaces included; the rim graded to the body size over one
    tooth depth; web and hub at the body size), for ``sectors`` tooth sectors (default
    the whole gear). No CAD, no meshing: milliseconds."""
    bl = default_blank(crown, gear, rim)
    delta = gear.cone_angle
    b = sizes.body
    m_n = crown.profile.module
    depth = abs(bl.face - bl.root)
    total = 0.0
    steps = 32
    # the tooth band (root to face cone) and the rim (root to body cone), in slices
    for end, sign in ((bl.face, -1.0), (bl.body, 1.0)):
        edges = np.linspace(bl.root, end, steps + 1)
        for h0, h1 in itertools.pairwise(edges):
            d = sign * abs(0.5 * (h0 + h1) - bl.root)
            s = float(sizes.local(np.array(d), m_n, depth))
            total += abs(bl.ring_volume(delta, h0, h1)) / s**3
    polys, _ = _feature_polygons(gear, bl, features, crown.profile.module)
    for poly in polys:
        r = np.array([p[0] for p in poly])
        z = np.array([p[1] for p in poly])
        r1, z1 = np.roll(r, -1), np.roll(z, -1)
        cross = r * z1 - r1 * z
        area = 0.5 * cross.sum()
        rc = ((r + r1) * cross).sum() / (6.0 * area) if area else 0.0
        total += abs(2 * math.pi * rc * area) / b**3  # Pappus
    share = 1.0 if sectors is None else min(sectors, gear.teeth) / gear.teeth
    return float(total * share)


#: DOFs of one finite-element gear model at most (quadratic tetrahedra, 3 per node): the
#: documented work bound of ``body-modal``, ``check --bodies`` and the contact analysis'
#: tooth compliance (the default meshes of the bundled gears have 0.14-0.16 million)
MAX_DOFS = 3_000_000
#: tetrahedra per cube of the local element size (``element_density``): gmsh's HXT
#: mesher gave 3.2 (fine meshes) to 5.3 (coarse, surface-dominated) on the bundled
#: gears; the estimate takes the high side
TETS_PER_CUBE = 5.5
#: P2 nodes per tetrahedron (measured 1.65-1.80)
NODES_PER_TET = 1.8
#: peak bytes per DOF of meshing, assembling the P2 stiffness and mass matrices and
#: factorising ``K - sigma M`` (measured on the bundled gears: see docs/reliability.md)
BYTES_PER_DOF = 16_000.0


def mesh_estimate(
    crown: CrownGear,
    gear: BevelGear,
    rim: float,
    features: BlankFeatures,
    sizes: MeshSizes,
    *,
    what: str,
    control: str,
    sectors: int | None = None,
    dense_columns: int = 0,
) -> Estimate:
    """The tetrahedra, DOFs and peak memory of meshing gear ``gear`` with ``sizes`` and
    solving on it, estimated from the body's volume and the element sizes
    (:func:`element_density`) before gmsh runs (milliseconds).

    ``dense_columns`` adds dense load and solution blocks of that many columns (the
    tooth-compliance model's flank loads). Work: DOFs, bounded by :data:`MAX_DOFS`."""
    tets = TETS_PER_CUBE * element_density(crown, gear, rim, features, sizes, sectors)
    dofs = 3.0 * NODES_PER_TET * tets
    memory = BYTES_PER_DOF * dofs + 3 * 8.0 * dofs * dense_columns
    return Estimate(
        f"{what}: a mesh of about {tets:.3g} quadratic tetrahedra ({sizes.tooth * 1e3:.3g} mm "
        f"in the teeth, {sizes.body * 1e3:.3g} mm in the blank)",
        memory, dofs, "DOFs", MAX_DOFS, control,
    )  # fmt: skip


def max_tooth_size(crown: CrownGear, gear: BevelGear, rim: float) -> float:
    """Largest tooth-band element size (m) that resolves a tooth: half its depth."""
    return _max_tooth(default_blank(crown, gear, rim))


def _max_tooth(bl: Blank) -> float:
    return 0.5 * abs(bl.face - bl.root)


def check_blank(
    crown: CrownGear, gear: BevelGear, rim: float, features: BlankFeatures | None = None
) -> Blank:
    """The blank of the gear, after checking its body geometry before any CAD work: the
    rim of an external gear must stay half a module clear of the axis at the toe (its
    body cone closes toward the apex), and the web and hub must fit the rim
    (:class:`BlankFeatures`).

    Raises
    ------
    MeshError
        ``rim: ...`` or ``blank.web: ...``, ``blank.hub: ...`` with the dimension and
        its limit.
    """
    m_n = crown.profile.module
    bl = default_blank(crown, gear, rim)
    delta = gear.cone_angle
    if gear.kind == "external":
        r_toe = _rz(bl.front, bl.body, delta)[0]
        if r_toe < 0.5 * m_n:
            most = rim - (0.5 * m_n - r_toe) / math.cos(delta)
            raise MeshError(
                f"rim: {rim * 1e3:.5g} mm reaches past the axis of the external gear (its "
                f"body cone meets the axis inside the toe: inner radius {r_toe * 1e3:.4g} mm "
                f"at the toe); at most {max(most, 0.0) * 1e3:.4g} mm leaves half a module "
                "clear of the axis"
            )
    _feature_polygons(gear, bl, features or BlankFeatures(), m_n)
    return bl


def check_sizes(crown: CrownGear, gear: BevelGear, rim: float, sizes: MeshSizes) -> Blank:
    """The blank of the gear, after checking that ``sizes`` resolve its teeth: the tooth
    size at most half the tooth depth, the body size at least the tooth size.

    Raises
    ------
    MeshError
    """
    bl = default_blank(crown, gear, rim)
    depth = abs(bl.face - bl.root)
    if sizes.tooth > _max_tooth(bl):
        raise MeshError(
            f"mesh size: the tooth size {sizes.tooth * 1e3:.4g} mm does not resolve a tooth "
            f"{depth * 1e3:.4g} mm deep: it must be at most half the tooth depth"
        )
    if sizes.body < sizes.tooth:
        raise MeshError(
            f"mesh size: the body size {sizes.body * 1e3:.4g} mm must be >= the tooth size "
            f"{sizes.tooth * 1e3:.4g} mm"
        )
    return bl


def mesh_gear(
    crown: CrownGear,
    gear: BevelGear,
    *,
    rim: float | None = None,
    features: BlankFeatures | None = None,
    sizes: MeshSizes | None = None,
    stage: Stage | None = None,
    threads: int = 2,
    sectors: range | None = None,
    budget: Estimate | None = None,
) -> GearBodyMesh:
    """Tetrahedral mesh of the whole gear generated by ``crown`` (module docstring).

    Parameters
    ----------
    crown, gear :
        From :meth:`NutationDesign.tooth_generation`.
    rim : float, optional
        Rim thickness beyond the root cone (m); default ``2 m_n``.
    features : BlankFeatures, optional
        Web, hub and bore; default none (the rim ring).
    sizes : MeshSizes, optional
        Element sizes; default :meth:`MeshSizes.default`.
    stage : callable, optional
        ``stage(description)`` when a stage starts (progress display).
    threads : int
        Threads of the CAD kernel's boolean operations (the sector is meshed on one:
        the same mesh in every run).
    sectors : range, optional
        Only these consecutive tooth sectors (sector ``k`` is sector 0 turned by ``k``
        pitches; sector 0 spans the azimuths ``[phi0 - pitch, phi0]``, its walls through
        the middle of two teeth): a part of the gear, open at its two end walls, for
        tooth-level analyses. Default: all ``z`` sectors (the whole, closed gear).
    budget : Estimate, optional
        The work and memory checked before meshing: the caller's estimate of what it
        will do with the mesh (a solution by cyclic symmetry needs less than one on the
        whole mesh). Default: :func:`mesh_estimate` of a solution on the meshed sectors.

    Raises
    ------
    MeshError
        A mesh too coarse to resolve a tooth, a blank feature that does not fit, or a
        solid the CAD kernel or the mesher cannot build.
    """
    m_n = crown.profile.module
    rim = 2.0 * m_n if rim is None else float(rim)
    features = BlankFeatures() if features is None else features
    sizes = MeshSizes.default(m_n) if sizes is None else sizes
    bl = check_sizes(crown, gear, rim, sizes)
    check_blank(crown, gear, rim, features)
    if budget is None:
        budget = mesh_estimate(
            crown, gear, rim, features, sizes, what="gear body", control="the element sizes",
            sectors=None if sectors is None else len(sectors),
        )  # fmt: skip
    budget.check()
    try:
        return _mesh_gear(crown, gear, bl, rim, features, sizes, stage, threads, sectors)
    except ReducerlabError:
        raise
    except Exception as exc:  # gmsh raises plain Exception; any other failure inside it
        raise MeshError(f"gear body: gmsh failed ({exc})") from None


def _mesh_gear(
    crown: CrownGear,
    gear: BevelGear,
    bl: Blank,
    rim: float,
    features: BlankFeatures,
    sizes: MeshSizes,
    stage: Stage | None,
    threads: int,
    sectors: range | None,
) -> GearBodyMesh:
    m_n = crown.profile.module
    depth = abs(bl.face - bl.root)
    z = gear.teeth
    pitch = 2 * math.pi / z
    delta = gear.cone_angle
    say = stage or (lambda _s: None)
    polys, mount_z = _feature_polygons(gear, bl, features, m_n)
    ext = _space_extension(crown)
    ring = [
        (bl.front, bl.body), (bl.back, bl.body), (bl.back, bl.face), (bl.front, bl.face),
    ]  # fmt: skip
    ring_rz = [_rz(L, h, delta) for L, h in ring]
    sections = _space_sections(crown, gear, rim, ext)
    key = _solid_key(sections, ring_rz, polys, pitch)
    stored = _SOLIDS.get(key)
    if stored is None:
        say("tooth space")
        with gmsh_session() as gmsh:
            gmsh.option.setNumber("Geometry.OCCParallel", 1)
            gmsh.option.setNumber("General.NumThreads", threads)
            stored = _sector_solid(gmsh, sections, ring_rz, polys, pitch, say)
        _SOLIDS.put(key, stored)
    else:
        say("sector solid (built before)")
    brep, phi0 = stored
    # the solid is always meshed as read back, in a session of its own, on one thread
    # (HXT on two threads meshes the same solid differently from run to run): the same
    # mesh whether the solid was built now or before, in every run
    with gmsh_session() as gmsh:
        occ = gmsh.model.occ
        gmsh.option.setNumber("General.NumThreads", 1)
        _import_brep(gmsh, brep)
        vols = gmsh.model.getEntities(3)
        if len(vols) != 1:
            raise MeshError(
                f"gear body: the sector solid came out as {len(vols)} pieces (the blank "
                "features do not join the rim?)"
            )
        volume = occ.getMass(3, vols[0][1]) / MM**3
        if not volume > 0:
            raise MeshError("gear body: the sector solid has no volume")
        tol = 1e-6 * bl.back * MM
        slaves = _side_surfaces(gmsh, phi0, tol)
        masters = _side_surfaces(gmsh, phi0 - pitch, tol)
        if not slaves or len(slaves) != len(masters):
            raise MeshError("gear body: the sector walls could not be matched for a periodic mesh")
        c, s = math.cos(pitch), math.sin(pitch)
        affine = [c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
        gmsh.model.mesh.setPeriodic(2, slaves, masters, affine)
        # size field: tooth size in the tooth band, growing to the body size one tooth
        # depth further into the blank
        sign = 1.0 if gear.kind == "external" else -1.0
        h_expr = f"(Sqrt(x*x+y*y)*{math.cos(delta)!r} - z*{math.sin(delta)!r})"
        d_expr = f"Max(0, {sign!r}*({bl.root * MM!r} - {h_expr}))/{depth * MM!r}"
        field = gmsh.model.mesh.field
        fid = field.add("MathEval")
        a, b = sizes.tooth * MM, sizes.body * MM
        expr = f"{a!r} + {b - a!r}*Min(1, {d_expr})"
        if sizes.fillet is not None and sizes.fillet < sizes.tooth:
            # MeshSizes.local: the root band at the fillet size, graded to the tooth size
            f, lo, hi = sizes.fillet * MM, FILLET_BAND[0] * m_n * MM, FILLET_BAND[1] * m_n * MM
            below = f"({sign!r}*({bl.root * MM!r} - {h_expr}))"
            e = f"Max(0, Max({below} - {lo!r}, -{below} - {hi!r}))"
            g = FILLET_GRADING * m_n * MM
            expr = f"Min({expr}, {f!r} + {a - f!r}*{e}/{g!r})"
        field.setString(fid, "F", expr)
        field.setAsBackgroundMesh(fid)
        tet_options(gmsh)
        say("meshing a tooth sector")
        try:
            gmsh.model.mesh.generate(3)
        except Exception as exc:
            raise MeshError(f"gear body: gmsh could not mesh the sector ({exc})") from None
        try:
            gmsh.model.mesh.setOrder(2)  # mid-edge nodes on the curved surfaces
        except Exception as exc:  # pragma: no cover - gmsh's own failure
            raise MeshError(f"gear body: quadratic nodes could not be placed ({exc})") from None
        tags, coords, _ = gmsh.model.mesh.getNodes()
        etypes, _, enodes = gmsh.model.mesh.getElements(3)
        if list(etypes) != [11]:
            raise MeshError(f"gear body: unexpected element types {list(etypes)} in the sector")
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags] = np.arange(len(tags))
        T = index[enodes[0].reshape(-1, 10)][:, GMSH_TO_VTK]
        used = np.unique(T)  # drop the nodes of free construction curves
        index = np.full(len(tags), -1, dtype=np.int64)
        index[used] = np.arange(len(used))
        P = coords.reshape(-1, 3)[used] / MM
        T = index[T]
    if sectors is not None:
        # tooth models (nodal stresses and flank compliances are read there): folded
        # curved elements straightened. Whole-gear bodies keep gmsh's curved elements,
        # whose signed Jacobian still integrates mass and inertia right (nutation_surface
        # gear 2 at 1.0 m_n: +0.06 % against the CAD volume as meshed, +0.8 % mended;
        # docs/assumptions.md)
        P = _mend_sector(P, T, pitch, phi0, tol / MM)
    say("patterning the teeth")
    ks = range(z) if sectors is None else sectors
    if len(ks) == 0 or ks.step != 1 or len(ks) > z:
        raise MeshError(f"sectors: must be 1 to {z} consecutive sectors; got {ks!r}")
    points, tets = _pattern(P, T, z, pitch, phi0, tol / MM, ks)
    mesh = GearBodyMesh(
        points, tets, gear, bl, features, sizes,
        None if features.bore is None else 0.5 * features.bore, mount_z, len(T),
    )  # fmt: skip
    err = abs(mesh.volume / (len(ks) * volume) - 1)
    if err > 0.05:
        raise MeshError(
            f"gear body: the mesh's volume is {100 * err:.2g} % off the CAD solid's (elements "
            "too coarse for the curved surfaces?)"
        )
    return mesh


class _SolidCache:
    """The last few sector solids built in this process, as BREP text by key (issue
    28): the tooth compliance and the gear body of one gear (and any other mesh sizes
    of it) cut the same solid once. Small: a solid is 0.1-2 MB of text."""

    def __init__(self, size: int = 16) -> None:
        self.size = size
        self.items: dict[str, tuple[str, float]] = {}

    def get(self, key: str) -> tuple[str, float] | None:
        item = self.items.pop(key, None)
        if item is not None:
            self.items[key] = item  # most recent last
        return item

    def put(self, key: str, item: tuple[str, float]) -> None:
        self.items.pop(key, None)
        self.items[key] = item
        while len(self.items) > self.size:
            self.items.pop(next(iter(self.items)))


#: Sector solids of this process (:class:`_SolidCache`).
_SOLIDS = _SolidCache()


def stored_solids() -> dict[str, tuple[str, float]]:
    """The sector solids built in this process, by key: BREP text and the azimuth
    ``phi0`` (rad) at which sector 0 ends; a copy (picklable: another process adds them
    to its own with :func:`store_solids`)."""
    return dict(_SOLIDS.items)


def store_solids(items: dict[str, tuple[str, float]]) -> None:
    """Add sector solids built elsewhere (:func:`stored_solids` of another process) to
    this process's cache."""
    for key, item in items.items():
        _SOLIDS.put(key, item)


def _solid_key(
    sections: list[_Section],
    ring: list[tuple[float, float]],
    polys: list[list[tuple[float, float]]],
    pitch: float,
) -> str:
    """SHA-256 of everything the sector solid is built from: the tooth-space sections,
    the ring and blank-feature polygons, the pitch, and the gmsh version."""
    import hashlib

    import gmsh

    h = hashlib.sha256()
    h.update(f"{gmsh.__version__}|{pitch!r}|{ring!r}|{polys!r}".encode())
    for sec in sections:
        h.update(np.ascontiguousarray(sec.path, dtype=np.float64).tobytes())
        h.update(repr(sec.ends).encode())
        h.update(np.ascontiguousarray(sec.cap, dtype=np.float64).tobytes())
    return h.hexdigest()


def _sector_solid(
    gmsh: Any,
    sections: list[_Section],
    ring: list[tuple[float, float]],
    polys: list[list[tuple[float, float]]],
    pitch: float,
    say: Stage,
) -> tuple[str, float]:
    """Build the sector solid in the (empty) gmsh model: the ring revolved over one
    pitch, the three tooth spaces that can meet it cut away, the blank features fused
    on. Returns its BREP text and ``phi0``, the azimuth of its second wall (rad)."""
    import tempfile
    from pathlib import Path

    occ = gmsh.model.occ
    space, phi0 = _space_loft(gmsh, sections, pitch)
    say("sector solid")
    sector = _revolve_polygon(occ, ring, phi0 - pitch, pitch)
    tools = list(space)
    for k in (-1, 1):
        c = occ.copy(space)
        occ.rotate(c, 0, 0, 0, 0, 0, 1, k * pitch)
        tools += c
    try:
        cut, _ = occ.cut(sector, tools)
        if polys:
            parts = [v for p in polys for v in _revolve_polygon(occ, p, phi0 - pitch, pitch)]
            cut, _ = occ.fuse(cut, parts)
        occ.synchronize()
    except Exception as exc:
        raise MeshError(f"gear body: the CAD kernel could not build the sector ({exc})") from None
    # OpenCASCADE's own text of the model (free construction curves included: the
    # import takes the volumes alone)
    with tempfile.TemporaryDirectory(prefix="reducerlab-solid-") as tmp:
        path = Path(tmp) / "sector.brep"
        gmsh.write(str(path))
        return path.read_text(), phi0


def _space_loft(gmsh: Any, sections: list[_Section], pitch: float) -> tuple[list, float]:
    """The tooth-space loft in the (empty) gmsh model and ``phi0`` (rad), the azimuth of
    sector 0's second wall: half a pitch beyond the loft's centre of mass, so that the
    walls pass through the middle of the teeth either side of tooth space 0."""
    occ = gmsh.model.occ
    try:
        wires = _space_wires(occ, sections)
        # cubic across the sections: as exact as OpenCASCADE's default (degree up to 8)
        # between them (both within 1 nm of the enveloped surface at the mid-sections)
        # and its booleans 5x faster (docs/assumptions.md, "Loft degree")
        space = occ.addThruSections(wires, makeSolid=True, makeRuled=False, maxDegree=3)
    except Exception as exc:  # gmsh raises plain Exception
        raise MeshError(f"gear body: the tooth space loft failed ({exc})") from None
    occ.synchronize()
    cm = np.array(occ.getCenterOfMass(3, space[0][1]))
    return space, math.atan2(cm[1], cm[0]) + 0.5 * pitch


def _space_extension(crown: CrownGear) -> float:
    """How far the tooth-space sections reach beyond the toe and the heel (m)."""
    return min(1.0e-3, 0.1 * crown.face_width)


def sector_walls(
    crown: CrownGear, gear: BevelGear, sectors: range, *, rim: float | None = None
) -> tuple[float, float]:
    """Azimuths (rad, about the gear axis ``z``) of the two end walls of
    ``mesh_gear(crown, gear, rim=rim, sectors=sectors)``, lower then upper: the planes
    through the axis that bound the part of the gear (held in a tooth-level analysis).
    Sector ``k`` spans ``[phi0 + (k - 1) pitch, phi0 + k pitch]``, ``phi0`` from the
    tooth-space loft as :func:`mesh_gear` has it (no cut, no mesh: about a second).

    Raises
    ------
    MeshError
        ``sectors`` not 1 to ``z`` consecutive sectors, or the loft failing.
    """
    z = gear.teeth
    if not isinstance(sectors, range) or len(sectors) == 0 or sectors.step != 1 or len(sectors) > z:
        raise MeshError(f"sectors: must be 1 to {z} consecutive sectors; got {sectors!r}")
    m_n = crown.profile.module
    rim = 2.0 * m_n if rim is None else float(rim)
    pitch = 2 * math.pi / z
    sections = _space_sections(crown, gear, rim, _space_extension(crown))
    with gmsh_session() as gmsh:
        _, phi0 = _space_loft(gmsh, sections, pitch)
    return phi0 + (sectors[0] - 1) * pitch, phi0 + sectors[-1] * pitch


def _import_brep(gmsh: Any, brep: str) -> None:
    """Read a sector solid's BREP text into the (empty) gmsh model."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory(prefix="reducerlab-solid-") as tmp:
        path = Path(tmp) / "sector.brep"
        path.write_text(brep)
        gmsh.model.occ.importShapes(str(path), highestDimOnly=True)
        gmsh.model.occ.synchronize()


def _mend_sector(P: Array, T: NDArray[np.int64], pitch: float, phi0: float, tol: float) -> Array:
    """The sector's nodes with the folded curved tetrahedra straightened
    (:func:`~reducerlab.fe.quality.mend_curved_tets`); a mid-edge node moved on one
    periodic wall moves its partner on the other wall alike, so that the walls still
    match when the sectors are joined (:func:`_pattern`).

    Raises
    ------
    MeshError
        Elements that stay folded or slivers (``fe.quality``).
    """
    from scipy.spatial import cKDTree

    from .quality import MIN_JACOBIAN_RATIO, jacobian_ratio, mend_curved_tets

    try:
        Q, mended = mend_curved_tets(P, T, "gear body")
    except ReducerlabError as exc:
        raise MeshError(str(exc)) from None
    if mended == 0:
        return P
    moved = np.flatnonzero(np.any(Q != P, axis=1))
    nrm = lambda phi: np.array([-math.sin(phi), math.cos(phi), 0.0])  # noqa: E731
    for wall, turn in ((phi0, -pitch), (phi0 - pitch, pitch)):
        on = moved[np.abs(P[moved] @ nrm(wall)) < tol]
        if on.size == 0:
            continue
        other = np.flatnonzero(np.abs(P @ nrm(wall + turn)) < tol)
        dist, j = cKDTree(P[other]).query(_rot(P[on], turn))
        if np.any(dist > tol):
            raise MeshError(
                "gear body: the sector walls' nodes do not match (periodic mesh failed)"
            )
        Q[other[j]] = _rot(Q[on], turn)
    r = jacobian_ratio(Q, T)
    if r.min() < MIN_JACOBIAN_RATIO:
        raise MeshError(
            f"gear body: {np.count_nonzero(r < MIN_JACOBIAN_RATIO)} quadratic tetrahedra "
            f"keep a Jacobian ratio below {MIN_JACOBIAN_RATIO} (worst {r.min():.3g}) with "
            "straightened edges; change the element sizes"
        )
    return Q


def _pattern(
    P: Array,
    T: NDArray[np.int64],
    z: int,
    pitch: float,
    phi0: float,
    tol: float,
    sectors: range | None = None,
) -> tuple[Array, NDArray[np.int64]]:
    """Join copies of the sector mesh, turned by ``k`` pitches (``k`` in ``sectors``,
    default all ``z``), on their walls; a part of the gear keeps its last wall."""
    from scipy.spatial import cKDTree

    n = len(P)
    nrm = lambda phi: np.array([-math.sin(phi), math.cos(phi), 0.0])  # noqa: E731
    on_slave = np.flatnonzero(np.abs(P @ nrm(phi0)) < tol)
    on_master = np.flatnonzero(np.abs(P @ nrm(phi0 - pitch)) < tol)
    # the slave wall turned back by one pitch lands on the master wall
    dist, j = cKDTree(P[on_master]).query(_rot(P[on_slave], -pitch))
    if len(on_slave) != len(on_master) or np.any(dist > tol):
        raise MeshError("gear body: the sector walls' nodes do not match (periodic mesh failed)")
    partner = on_master[j]  # slave node i of sector k == master node partner of sector k+1
    is_slave = np.zeros(n, bool)
    is_slave[on_slave] = True
    keep = np.flatnonzero(~is_slave)
    local = np.full(n, -1, dtype=np.int64)
    local[keep] = np.arange(len(keep))
    per = len(keep)
    ks = range(z) if sectors is None else sectors
    closed = len(ks) == z
    parts = [_rot(P[keep], k * pitch) for k in ks]
    if not closed:  # the open end: the last sector's slave wall nodes of its own
        parts.append(_rot(P[on_slave], ks[-1] * pitch))
    points = np.concatenate(parts)
    tets = []
    for i in range(len(ks)):
        g = local + i * per
        if i + 1 < len(ks) or closed:
            g[on_slave] = local[partner] + ((i + 1) % len(ks)) * per
        else:
            g[on_slave] = len(ks) * per + np.arange(len(on_slave))
        tets.append(g[T])
    tets_all = np.concatenate(tets)
    p = points[tets_all[:, :4]]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    if np.any(vol <= 0):
        raise MeshError("gear body: the mesher returned inverted tetrahedra")
    return points, tets_all
