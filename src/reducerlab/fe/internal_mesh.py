"""Quadratic tetrahedral meshes of internal gear tooth sectors (the ring's LTCA body).

A sector of ``teeth`` consecutive teeth of an
:class:`~reducerlab.geometry.internal_gear.InternalGear` (tooth 0 in the middle,
centred on ``+x``, teeth pointing toward the axis) and the rim outside them is built
as an OpenCASCADE solid inside gmsh and meshed into 10-node tetrahedra, as
:mod:`reducerlab.fe.spur_mesh` does for external gears:

1. **Outline.** Interpolating splines through the involutes and the root fillets, circle
   arcs for the tip lands (on the tip circle, inside) and the root circle between the
   fillets (outside). The sector is cut radially through the middle of its two outer
   tooth spaces and closed by the rim's outer circle ``r_f + rim`` (default rim
   ``3.5 m``, ISO 6336-1's solid rim ``s_R >= 3.5 m_n``).
2. **Solid.** The plane face is extruded over the face width, ``z = -b/2 ... b/2``.
3. **Mesh.** A size field ``tooth`` inside the root circle, growing linearly to ``body``
   one tooth depth outside it; mid-edge nodes on the curved CAD surfaces.

Lengths are metres at the interface (gmsh works in millimetres inside).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..budget import Estimate
from ..geometry.internal_gear import InternalGear
from .gear_mesh import (
    BYTES_PER_DOF,
    MAX_DOFS,
    NODES_PER_TET,
    TETS_PER_CUBE,
    MeshError,
    MeshSizes,
    gmsh_session,
    tet_options,
)
from .spur_mesh import quadratic_tets

__all__ = ["InternalSectorMesh", "internal_sector_estimate", "mesh_internal_sector"]

Array = NDArray[np.float64]
MM = 1e3  # gmsh works in mm
#: Rim thickness outside the root circle, in modules (ISO 6336-1 solid rim: s_R >= 3.5 m_n).
DEFAULT_RIM = 3.5
#: Points per spline of the involutes and fillets handed to the CAD kernel.
SPLINE_POINTS = 41


@dataclass(frozen=True)
class InternalSectorMesh:
    """A quadratic tetrahedral mesh of an internal gear tooth sector.

    Attributes
    ----------
    points : ndarray (n, 3)
        Nodes (m), gear frame (:mod:`reducerlab.geometry.internal_gear`).
    tets : ndarray (m, 10)
        Quadratic tetrahedra in VTK/meshio/scikit-fem node order, positively oriented.
    gear : InternalGear
    tooth_ids : tuple of int
        The teeth of the sector (tooth ``k`` is tooth 0 turned by ``2 pi k / z``).
    outer_radius : float
        Radius of the rim's outer surface (m), the held surface.
    sizes : MeshSizes
    """

    points: Array
    tets: NDArray[np.int64]
    gear: InternalGear
    tooth_ids: tuple[int, ...]
    outer_radius: float
    sizes: MeshSizes

    @property
    def cut_angles(self) -> tuple[float, float]:
        """Polar angles (rad) of the two radial cut faces (middle of the outer spaces)."""
        p = self.gear.pitch
        return (self.tooth_ids[0] - 0.5) * p, (self.tooth_ids[-1] + 0.5) * p

    @property
    def volume(self) -> float:
        """Volume of the straight-sided tetrahedra (m^3)."""
        p = self.points[self.tets[:, :4]]
        d = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
        return float(d.sum() / 6.0)

    @property
    def exact_volume(self) -> float:
        """Sector area x face width of the exact geometry (m^3)."""
        area = self.gear.sector_area(len(self.tooth_ids), self.outer_radius)
        return area * self.gear.face_width

    def skfem(self) -> Any:
        """The mesh as a :class:`skfem.MeshTet2` (quadratic, curved geometry)."""
        import meshio
        from skfem.io.meshio import from_meshio

        return from_meshio(meshio.Mesh(self.points, [("tetra10", self.tets)]))


def _outer_radius(gear: InternalGear, rim: float | None) -> float:
    t = DEFAULT_RIM * gear.module if rim is None else rim
    if isinstance(t, bool) or not isinstance(t, int | float) or not (math.isfinite(t) and t > 0):
        raise MeshError(f"rim: must be a thickness > 0 m; got {rim!r}")
    if t < 0.5 * gear.module:
        raise MeshError(f"rim: {t * 1e3:.4g} mm is thinner than half a module")
    return gear.root_radius + t


def _check_sizes(gear: InternalGear, sizes: MeshSizes) -> float:
    if not isinstance(sizes, MeshSizes):
        raise MeshError(f"sizes: must be a MeshSizes; got {sizes!r}")
    depth = gear.root_radius - gear.tip_radius
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
    return depth


def internal_sector_estimate(
    gear: InternalGear,
    teeth: int,
    rim: float | None,
    sizes: MeshSizes,
    *,
    dense_columns: int = 0,
    what: str = "the internal gear's tooth sector",
    control: str = "the tooth element size (tooth_size=)",
) -> Estimate:
    """Tetrahedra, DOFs and peak memory of :func:`mesh_internal_sector` and a solve on
    it, from the sector's volume in cubes of the local element size (the tooth band
    ``r_a ... r_f`` taken whole at the tooth size, the rim graded to the body size over
    one tooth depth), with the constants of :func:`reducerlab.fe.gear_mesh.mesh_estimate`
    (``TETS_PER_CUBE``, ``NODES_PER_TET``, ``BYTES_PER_DOF``); ``dense_columns`` adds
    the dense load and response blocks. Work: DOFs, bounded by ``MAX_DOFS``.
    Milliseconds, nothing meshed."""
    ro = _outer_radius(gear, rim)
    depth = _check_sizes(gear, sizes)
    share = teeth * gear.pitch / 2  # sector angle / 2: area = share (r1^2 - r0^2)
    b = gear.face_width
    a, s_b = sizes.tooth, sizes.body
    total = share * (gear.root_radius**2 - gear.tip_radius**2) * b / a**3
    edges = np.linspace(gear.root_radius, ro, 33)
    for r0, r1 in itertools.pairwise(edges):
        d = (0.5 * (r0 + r1) - gear.root_radius) / depth
        s = a + (s_b - a) * min(1.0, d)
        total += share * (r1**2 - r0**2) * b / s**3
    tets = TETS_PER_CUBE * total
    dofs = 3.0 * NODES_PER_TET * tets
    memory = BYTES_PER_DOF * dofs + 3 * 8.0 * dofs * dense_columns
    return Estimate(
        f"{what}: a mesh of about {tets:.3g} quadratic tetrahedra ({a * 1e3:.3g} mm in the "
        f"teeth, {s_b * 1e3:.3g} mm in the rim)",
        memory, dofs, "DOFs", MAX_DOFS, control,
    )  # fmt: skip


def mesh_internal_sector(
    gear: InternalGear,
    teeth: int = 5,
    rim: float | None = None,
    sizes: MeshSizes | None = None,
    *,
    threads: int = 2,
) -> InternalSectorMesh:
    """Quadratic tetrahedral mesh of ``teeth`` consecutive internal teeth and their rim.

    Parameters
    ----------
    gear : InternalGear
    teeth : int
        Teeth in the sector, ``1 <= teeth < z`` (:meth:`InternalGear.sector_teeth`).
    rim : float, optional
        Rim thickness outside the root circle (m); default ``3.5 m``.
    sizes : MeshSizes, optional
        Element sizes (m): ``tooth`` inside the root circle, ``body`` one tooth depth
        outside it; default ``0.3 m`` and ``m``.
    threads : int
        gmsh threads for the CAD work (the mesh itself is made on one, as
        :func:`reducerlab.fe.spur_mesh.mesh_spur_sector`).

    Raises
    ------
    MeshError
        Bad rim/sizes, or a solid gmsh cannot build or mesh.
    """
    if not isinstance(gear, InternalGear):
        raise MeshError(f"gear: must be an InternalGear; got {type(gear).__name__}")
    ids = gear.sector_teeth(teeth)
    ro = _outer_radius(gear, rim)
    m = gear.module
    sizes = MeshSizes(0.3 * m, 1.0 * m) if sizes is None else sizes
    depth = _check_sizes(gear, sizes)
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

        def spline(first: int, q: Array, last: int) -> int:
            return occ.addSpline([first] + [pt(p) for p in q[1:-1]] + [last])

        origin = occ.addPoint(0.0, 0.0, z0)
        curves: list[int] = []
        rf = gear.root_radius
        first = pt(rf * np.array([math.cos(lo), math.sin(lo)]))
        prev = first
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
                curves.append(spline(root_m, f_minus, form_m))
                tip_m = pt(i_minus[-1])
                curves.append(spline(form_m, i_minus, tip_m))
                tip_p = pt(i_plus[0])
                curves.append(occ.addCircleArc(tip_m, origin, tip_p))
                form_p = pt(i_plus[-1])
                curves.append(spline(tip_p, i_plus, form_p))
                root_p = pt(f_plus[-1])
                curves.append(spline(form_p, f_plus, root_p))
                prev = root_p
            last = pt(rf * np.array([math.cos(hi), math.sin(hi)]))
            curves.append(occ.addCircleArc(prev, origin, last))
            outer_hi = pt(ro * np.array([math.cos(hi), math.sin(hi)]))
            curves.append(occ.addLine(last, outer_hi))
            n_arc = max(1, math.ceil((hi - lo) / (0.5 * math.pi)))
            p_prev = outer_hi
            for ang in np.linspace(hi, lo, n_arc + 1)[1:]:
                p_next = pt(ro * np.array([math.cos(ang), math.sin(ang)]))
                curves.append(occ.addCircleArc(p_prev, origin, p_next))
                p_prev = p_next
            curves.append(occ.addLine(p_prev, first))
            face = occ.addPlaneSurface([occ.addCurveLoop(curves)])
            out = occ.extrude([(2, face)], 0, 0, b * MM)
            occ.remove([(0, origin)])
            occ.synchronize()
        except Exception as exc:  # gmsh raises plain Exception
            raise MeshError(f"internal sector: the CAD kernel could not build it ({exc})") from None
        vols = [e for e in out if e[0] == 3]
        if len(vols) != 1:
            raise MeshError(f"internal sector: the extrusion gave {len(vols)} volumes")
        cad_volume = occ.getMass(3, vols[0][1]) / MM**3
        r_expr = "Sqrt(x*x+y*y)"
        ramp = f"Min(1, Max(0, ({r_expr} - {rf * MM!r})/{depth * MM!r}))"
        field = gmsh.model.mesh.field
        fid = field.add("MathEval")
        st, sb = sizes.tooth * MM, sizes.body * MM
        field.setString(fid, "F", f"{st!r} + {sb - st!r}*{ramp}")
        field.setAsBackgroundMesh(fid)
        tet_options(gmsh)
        P, T = quadratic_tets(gmsh, "internal sector")
    mesh = InternalSectorMesh(P, T, gear, ids, ro, sizes)
    err = abs(mesh.volume / cad_volume - 1)
    if err > 0.02:
        raise MeshError(
            f"internal sector: the mesh volume is {100 * err:.2g} % off the CAD solid's "
            "(elements too coarse?)"
        )
    return mesh
