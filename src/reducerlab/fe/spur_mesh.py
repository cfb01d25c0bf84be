"""Quadratic tetrahedral meshes of spur gear tooth sectors (LTCA bodies).

A sector of ``teeth`` consecutive teeth of a :class:`~reducerlab.geometry.spur.SpurGear`
(tooth 0 in the middle, centred on the gear frame's ``+x`` axis) and the rim below them
is built as an OpenCASCADE solid inside gmsh and meshed into 10-node tetrahedra:

1. **Outline.** The transverse outline is drawn with the exact pieces of
   :meth:`SpurGear.tooth_profile`: interpolating splines through the involutes and the
   generated root fillets, circle arcs for the tip lands and the root circle between the
   fillets. The sector is cut radially through the middle of its two outer tooth spaces
   (at polar angles ``(k_min - 1/2) 2 pi / z`` and ``(k_max + 1/2) 2 pi / z``) and closed
   by the inner circle of the rim: the root circle minus the rim thickness (default
   ``3.5 m``, ISO 6336-1's solid-gear rim ``s_R >= 3.5 m_n``) or the bore.
2. **Solid.** The plane face is extruded over the face width, ``z = -b/2 ... b/2``.
3. **Mesh.** gmsh meshes it with a size field ``tooth`` from the root circle outward,
   growing linearly to ``body`` one tooth depth below the root circle; the mid-edge
   nodes of the quadratic tetrahedra are placed on the curved CAD surfaces.

Lengths are metres at the interface (gmsh works in millimetres inside).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..geometry.spur import SpurGear
from .gear_mesh import GMSH_TO_VTK, MeshError, MeshSizes, gmsh_session, tet_options
from .quality import mend_curved_tets

__all__ = ["SpurSectorMesh", "default_spur_sizes", "mesh_spur_sector", "quadratic_tets"]

Array = NDArray[np.float64]
MM = 1e3  # gmsh works in mm
#: Rim thickness below the root circle, in modules (ISO 6336-1 solid gear: s_R >= 3.5 m_n).
DEFAULT_RIM = 3.5
#: Points per spline of the involutes and fillets handed to the CAD kernel.
SPLINE_POINTS = 41


def default_spur_sizes(module: float) -> MeshSizes:
    """Default element sizes ``tooth = 0.25 m``, ``body = 0.8 m``."""
    return MeshSizes(0.25 * module, 0.8 * module)


@dataclass(frozen=True)
class SpurSectorMesh:
    """A quadratic tetrahedral mesh of a spur gear tooth sector.

    Attributes
    ----------
    points : ndarray (n, 3)
        Nodes (m), gear frame (:mod:`reducerlab.geometry.spur`: axis ``z``, tooth 0
        centred on ``+x``, face from ``z = -b/2`` to ``b/2``).
    tets : ndarray (m, 10)
        Quadratic tetrahedra, corners then the mid-edge nodes of edges 0-1, 1-2, 0-2, 0-3,
        1-3, 2-3 (VTK/meshio/scikit-fem order), positively oriented.
    gear : SpurGear
    tooth_ids : tuple of int
        The teeth of the sector (tooth ``k`` is tooth 0 turned by ``2 pi k / z``).
    inner_radius : float
        Radius of the rim's inner (bore) surface (m).
    sizes : MeshSizes
        Element sizes used.
    """

    points: Array
    tets: NDArray[np.int64]
    gear: SpurGear
    tooth_ids: tuple[int, ...]
    inner_radius: float
    sizes: MeshSizes

    @property
    def cut_angles(self) -> tuple[float, float]:
        """Polar angles (rad) of the two radial cut faces (through the middle of the outer
        tooth spaces)."""
        p = self.gear.pitch
        return (self.tooth_ids[0] - 0.5) * p, (self.tooth_ids[-1] + 0.5) * p

    @property
    def volume(self) -> float:
        """Volume of the straight-sided tetrahedra (m^3)."""
        p = self.points[self.tets[:, :4]]
        d = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
        return float(d.sum() / 6.0)

    def curved_volume(self) -> float:
        """Volume of the curved (isoparametric P2) mesh by quadrature (m^3)."""
        from skfem import Basis, ElementTetP2, Functional

        mesh = self.skfem()
        basis = Basis(mesh, ElementTetP2())
        one = Functional(lambda w: 1.0 + 0.0 * w.x[0])
        return float(one.assemble(basis))

    @property
    def exact_volume(self) -> float:
        """Sector area x face width of the exact geometry (m^3)."""
        return self.gear.sector_area(len(self.tooth_ids), self.inner_radius) * self.gear.face_width

    @property
    def corners(self) -> NDArray[np.int64]:
        """Indices of the nodes that are tetrahedron corners."""
        return np.unique(self.tets[:, :4])

    def skfem(self) -> Any:
        """The mesh as a :class:`skfem.MeshTet2` (quadratic, curved geometry)."""
        import meshio
        from skfem.io.meshio import from_meshio

        return from_meshio(meshio.Mesh(self.points, [("tetra10", self.tets)]))

    def _tol(self, tol: float | None) -> float:
        return 1e-6 * self.gear.module if tol is None else float(tol)

    def bore_nodes(self, tol: float | None = None) -> NDArray[np.int64]:
        """Nodes on the rim's inner cylinder ``r = inner_radius`` (within ``tol``, m;
        default ``1e-6 m_n``)."""
        r = np.hypot(self.points[:, 0], self.points[:, 1])
        return np.flatnonzero(np.abs(r - self.inner_radius) <= self._tol(tol))

    def cut_nodes(self, tol: float | None = None) -> NDArray[np.int64]:
        """Nodes on the two radial cut faces of the sector (within ``tol``, m; default
        ``1e-6 m_n``)."""
        t = self._tol(tol)
        out = []
        for phi in self.cut_angles:
            nrm = np.array([-math.sin(phi), math.cos(phi), 0.0])
            e = np.array([math.cos(phi), math.sin(phi), 0.0])
            on = (np.abs(self.points @ nrm) <= t) & (self.points @ e > 0)
            out.append(np.flatnonzero(on))
        return np.unique(np.concatenate(out))

    def fixed_nodes(self, tol: float | None = None) -> NDArray[np.int64]:
        """Nodes an LTCA clamps: the bore surface and the two cut faces."""
        return np.union1d(self.bore_nodes(tol), self.cut_nodes(tol))

    def flank_nodes(
        self, flank: int = 1, tooth: int = 0, tol: float | None = None
    ) -> tuple[NDArray[np.int64], Array, Array]:
        """Nodes on the active involute of a flank, with their flank parameters.

        Parameters
        ----------
        flank : {+1, -1}
        tooth : int
            One of :attr:`tooth_ids`.
        tol : float, optional
            Distance from the exact involute (m); default ``1e-6 m_n`` (the splines of
            the CAD model follow the involute to ~1e-8 m_n).

        Returns
        -------
        nodes : ndarray (k,)
        u, v : ndarray (k,)
            Flank parameters (:meth:`SpurGear.flank_points`) of the nodes, in ``[0, 1]``.
        """
        if tooth not in self.tooth_ids:
            raise ReducerlabError(f"tooth: {tooth!r} is not in the sector {self.tooth_ids}")
        t = self._tol(tol)
        d, u, v = self.gear.flank_distance(self.points, flank, tooth)
        eps = t / max(self.gear.tip_roll - self.gear.form_roll, 1e-300)
        ok = (np.abs(d) <= t) & (u >= -eps) & (u <= 1 + eps)
        # the other teeth's flanks do not lie on this involute: keep the angular window
        ang = np.arctan2(self.points[:, 1], self.points[:, 0]) - tooth * self.gear.pitch
        ang = (ang + math.pi) % (2 * math.pi) - math.pi
        ok &= np.abs(ang) < 0.5 * self.gear.pitch
        idx = np.flatnonzero(ok)
        return idx, np.clip(u[idx], 0.0, 1.0), np.clip(v[idx], 0.0, 1.0)


def _inner_radius(gear: SpurGear, rim: float | None, bore: float | None) -> float:
    if rim is not None and bore is not None:
        raise MeshError("rim, bore: give the rim thickness or the bore diameter, not both")
    if bore is not None:
        if (
            isinstance(bore, bool)
            or not isinstance(bore, int | float)
            or not (math.isfinite(bore) and bore > 0)
        ):
            raise MeshError(f"bore: must be a diameter > 0 m; got {bore!r}")
        ri = 0.5 * bore
    else:
        t = DEFAULT_RIM * gear.module if rim is None else rim
        if (
            isinstance(t, bool)
            or not isinstance(t, int | float)
            or not (math.isfinite(t) and t > 0)
        ):
            raise MeshError(f"rim: must be a thickness > 0 m; got {rim!r}")
        ri = gear.root_radius - t
    if not 0.05 * gear.root_radius <= ri <= gear.root_radius - 0.5 * gear.module:
        raise MeshError(
            f"rim/bore: the inner radius {ri * 1e3:.5g} mm must lie between 0.05 r_f and "
            f"r_f - 0.5 m = {(gear.root_radius - 0.5 * gear.module) * 1e3:.5g} mm"
        )
    return ri


def mesh_spur_sector(
    gear: SpurGear,
    teeth: int = 3,
    rim: float | None = None,
    sizes: MeshSizes | None = None,
    bore: float | None = None,
    *,
    threads: int = 2,
) -> SpurSectorMesh:
    """Quadratic tetrahedral mesh of ``teeth`` consecutive teeth and their rim.

    Parameters
    ----------
    gear : SpurGear
    teeth : int
        Number of teeth in the sector, ``1 <= teeth < z``; the tooth indices are
        :meth:`SpurGear.sector_teeth` (tooth 0 in the middle, centred on ``+x``).
    rim : float, optional
        Rim thickness below the root circle (m); default ``3.5 m`` (ISO 6336-1 treats a
        gear with ``s_R >= 3.5 m_n`` as solid). Exclusive with ``bore``.
    sizes : MeshSizes, optional
        Element sizes (m): ``tooth`` from the root circle outward, ``body`` one tooth
        depth below it; default :func:`default_spur_sizes` (0.25 m, 0.8 m).
    bore : float, optional
        Bore *diameter* (m): the sector reaches down to the bore instead of a rim.
    threads : int
        gmsh threads for the CAD work; the mesh is made on one (gmsh's HXT on several
        meshes the same solid differently from run to run: ``docs/assumptions.md``,
        "One meshing thread").

    Raises
    ------
    MeshError
        Bad rim/bore/sizes, or a solid gmsh cannot build or mesh.
    """
    if not isinstance(gear, SpurGear):
        raise MeshError(f"gear: must be a SpurGear; got {type(gear).__name__}")
    ids = gear.sector_teeth(teeth)
    ri = _inner_radius(gear, rim, bore)
    m = gear.module
    sizes = default_spur_sizes(m) if sizes is None else sizes
    if not isinstance(sizes, MeshSizes):
        raise MeshError(f"sizes: must be a MeshSizes; got {sizes!r}")
    depth = gear.tip_radius - gear.root_radius
    if sizes.tooth > 0.5 * depth:
        raise MeshError(
            f"sizes.tooth: {sizes.tooth * 1e3:.4g} mm does not resolve a tooth "
            f"{depth * 1e3:.4g} mm deep: it must be at most half the tooth depth"
        )
    if sizes.body < sizes.tooth:
        raise MeshError(
            f"sizes.body: {sizes.body * 1e3:.4g} mm must be >= the tooth size "
            f"{sizes.tooth * 1e3:.4g} mm"
        )
    pitch = gear.pitch
    lo, hi = (ids[0] - 0.5) * pitch, (ids[-1] + 0.5) * pitch
    b = gear.face_width
    z0 = -0.5 * b * MM
    fil, _ = gear.fillet_points(SPLINE_POINTS)  # flank +1 of tooth 0: form point -> root
    ivl, _ = gear.involute_points(SPLINE_POINTS)  # form point -> tip
    mirror = np.array([1.0, -1.0])

    def rot(p: Array, a: float) -> Array:
        c, s = math.cos(a), math.sin(a)
        return np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]], -1)

    with gmsh_session() as gmsh:
        occ = gmsh.model.occ
        gmsh.option.setNumber("General.NumThreads", threads)

        def pt(q: Array) -> int:
            return occ.addPoint(float(q[0]) * MM, float(q[1]) * MM, z0)

        origin = occ.addPoint(0.0, 0.0, z0)
        curves: list[int] = []
        rf = gear.root_radius
        first = pt(rf * np.array([math.cos(lo), math.sin(lo)]))
        prev = first  # last point of the outline so far (on the root circle)
        try:
            for k in ids:
                a = k * pitch
                f_minus = rot((fil * mirror)[::-1], a)  # root -> form
                i_minus = rot(ivl * mirror, a)  # form -> tip
                i_plus = rot(ivl[::-1], a)  # tip -> form
                f_plus = rot(fil, a)  # form -> root
                root_m = pt(f_minus[0])
                curves.append(occ.addCircleArc(prev, origin, root_m))
                form_m = pt(f_minus[-1])
                tags = [root_m] + [pt(q) for q in f_minus[1:-1]] + [form_m]
                curves.append(occ.addSpline(tags))
                tip_m = pt(i_minus[-1])
                tags = [form_m] + [pt(q) for q in i_minus[1:-1]] + [tip_m]
                curves.append(occ.addSpline(tags))
                tip_p = pt(i_plus[0])
                curves.append(occ.addCircleArc(tip_m, origin, tip_p))
                form_p = pt(i_plus[-1])
                tags = [tip_p] + [pt(q) for q in i_plus[1:-1]] + [form_p]
                curves.append(occ.addSpline(tags))
                root_p = pt(f_plus[-1])
                tags = [form_p] + [pt(q) for q in f_plus[1:-1]] + [root_p]
                curves.append(occ.addSpline(tags))
                prev = root_p
            last = pt(rf * np.array([math.cos(hi), math.sin(hi)]))
            curves.append(occ.addCircleArc(prev, origin, last))
            inner_hi = pt(ri * np.array([math.cos(hi), math.sin(hi)]))
            curves.append(occ.addLine(last, inner_hi))
            n_arc = max(1, math.ceil((hi - lo) / (0.5 * math.pi)))
            angs = np.linspace(hi, lo, n_arc + 1)
            p_prev = inner_hi
            for ang in angs[1:]:
                p_next = pt(ri * np.array([math.cos(ang), math.sin(ang)]))
                curves.append(occ.addCircleArc(p_prev, origin, p_next))
                p_prev = p_next
            curves.append(occ.addLine(p_prev, first))
            face = occ.addPlaneSurface([occ.addCurveLoop(curves)])
            out = occ.extrude([(2, face)], 0, 0, b * MM)
            occ.remove([(0, origin)])
            occ.synchronize()
        except Exception as exc:  # gmsh raises plain Exception
            raise MeshError(f"spur sector: the CAD kernel could not build it ({exc})") from None
        vols = [e for e in out if e[0] == 3]
        if len(vols) != 1:
            raise MeshError(f"spur sector: the extrusion gave {len(vols)} volumes")
        cad_volume = occ.getMass(3, vols[0][1]) / MM**3
        # size field: tooth size outside the root circle, body size one depth below it
        r_expr = "Sqrt(x*x+y*y)"
        ramp = f"Min(1, Max(0, ({rf * MM!r} - {r_expr})/{depth * MM!r}))"
        field = gmsh.model.mesh.field
        fid = field.add("MathEval")
        st, sb = sizes.tooth * MM, sizes.body * MM
        field.setString(fid, "F", f"{st!r} + {sb - st!r}*{ramp}")
        field.setAsBackgroundMesh(fid)
        tet_options(gmsh)
        P, T = quadratic_tets(gmsh, "spur sector")
    mesh = SpurSectorMesh(P, T, gear, ids, ri, sizes)
    err = abs(mesh.volume / cad_volume - 1)
    if err > 0.02:
        raise MeshError(
            f"spur sector: the mesh volume is {100 * err:.2g} % off the CAD solid's (elements "
            "too coarse?)"
        )
    return mesh


def quadratic_tets(gmsh, what: str) -> tuple[Array, Array]:
    """Mesh the open gmsh model with quadratic tetrahedra (one thread: the same mesh in
    every run) and return its nodes ``P`` (m, only those the elements use) and elements
    ``T`` (VTK node order).

    Raises
    ------
    MeshError
        gmsh fails, returns other elements, inverted tetrahedra, or curved elements
        that stay folded with straight edges (``fe.quality.mend_curved_tets``, which
        straightens those below its Jacobian ratio first; ``what`` names the part in
        the message).
    """
    gmsh.option.setNumber("General.NumThreads", 1)
    try:
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)  # mid-edge nodes on the curved surfaces
    except Exception as exc:
        raise MeshError(f"{what}: gmsh could not mesh it ({exc})") from None
    tags, coords, _ = gmsh.model.mesh.getNodes()
    etypes, _, enodes = gmsh.model.mesh.getElements(3)
    if list(etypes) != [11]:
        raise MeshError(f"{what}: unexpected element types {list(etypes)}")
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags] = np.arange(len(tags))
    T = index[enodes[0].reshape(-1, 10)][:, GMSH_TO_VTK]
    used = np.unique(T)
    index = np.full(len(tags), -1, dtype=np.int64)
    index[used] = np.arange(len(used))
    P = coords.reshape(-1, 3)[used] / MM
    T = index[T]
    p = P[T[:, :4]]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    if np.any(vol <= 0):
        raise MeshError(f"{what}: the mesher returned inverted tetrahedra")
    try:  # folded curved elements straightened (unchanged where there are none)
        P, _ = mend_curved_tets(P, T, what)
    except ReducerlabError as exc:
        raise MeshError(str(exc)) from None
    return P, T
