"""Export of gear solids and flank point clouds: binary STL, PLY, optional STEP.

* STL (binary) and PLY (binary) meshes are written by :mod:`trimesh` (the ``cad``
  extra), imported only here, when a file is written.
* Flank point clouds with normals are written as PLY by plain numpy (no extra needed).
* STEP needs an OpenCASCADE kernel: the ``OCP`` bindings (pip package
  ``cadquery-ocp``). The mesh is written as a faceted solid (one planar face per
  triangle, sewn into a closed shell); practical for tooth sectors and coarse gears
  (sewing takes about a minute per 10^5 triangles).

Lengths are written in the unit asked for (``unit="mm"`` by default for CAD tools; the
solids themselves are in metres).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .solid import SolidError, TriangleMesh, require_trimesh

__all__ = ["MESH_FORMATS", "export_mesh", "export_point_cloud", "export_step", "load_mesh"]

Array = NDArray[np.float64]

#: File suffixes written by :func:`export_mesh` (``.step``/``.stp`` go to :func:`export_step`).
MESH_FORMATS = (".stl", ".ply", ".step", ".stp")

_SCALE = {"m": 1.0, "mm": 1e3}


def _scale(unit: str) -> float:
    if unit not in _SCALE:
        raise SolidError(f"export.unit: must be one of {sorted(_SCALE)}; got {unit!r}")
    return _SCALE[unit]


def export_mesh(mesh: TriangleMesh, path: str | Path, unit: str = "mm") -> Path:
    """Write ``mesh`` to ``path``; the format follows the suffix (.stl, .ply, .step/.stp).

    Parameters
    ----------
    mesh : TriangleMesh
        Vertices in m.
    path : str or Path
    unit : {"mm", "m"}
        Length unit of the file (STL and PLY carry none; CAD tools assume mm).

    Returns
    -------
    Path
        The file written.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in MESH_FORMATS:
        raise SolidError(
            f"export: unknown file type {p.suffix!r}; use one of {', '.join(MESH_FORMATS)}"
        )
    if suffix in (".step", ".stp"):
        return export_step(mesh, p, unit)
    tm = require_trimesh()
    m = tm.Trimesh(vertices=mesh.vertices * _scale(unit), faces=mesh.faces, process=False)
    p.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".stl":
        m.export(p, file_type="stl")  # binary STL
    else:
        m.export(p, file_type="ply", encoding="binary")
    return p


def load_mesh(path: str | Path, unit: str = "mm") -> TriangleMesh:
    """Read an STL or PLY file written by :func:`export_mesh` (vertices back in m).

    STL stores each triangle's corners separately; they are merged by position.
    """
    tm = require_trimesh()
    m = tm.load_mesh(Path(path), process=True)
    return TriangleMesh(
        np.asarray(m.vertices, float) / _scale(unit), np.asarray(m.faces, np.int64), Path(path).stem
    )


def export_point_cloud(
    points: Array, normals: Array | None, path: str | Path, unit: str = "mm"
) -> Path:
    """Write points (n, 3, in m) and optional unit normals as a binary little-endian PLY.

    Parameters
    ----------
    points : ndarray, shape (n, 3)
    normals : ndarray, shape (n, 3), optional
    path : str or Path
    unit : {"mm", "m"}
    """
    P = np.asarray(points, float).reshape(-1, 3) * _scale(unit)
    cols = [("x", P[:, 0]), ("y", P[:, 1]), ("z", P[:, 2])]
    if normals is not None:
        N = np.asarray(normals, float).reshape(-1, 3)
        if N.shape != P.shape:
            raise SolidError(f"point cloud: normals {N.shape} do not match points {P.shape}")
        cols += [("nx", N[:, 0]), ("ny", N[:, 1]), ("nz", N[:, 2])]
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(P)}"]
    header += [f"property double {name}" for name, _ in cols]
    header.append("end_header")
    data = np.empty(len(P), dtype=[(name, "<f8") for name, _ in cols])
    for name, v in cols:
        data[name] = v
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    with p.open("wb") as fh:
        fh.write(("\n".join(header) + "\n").encode("ascii"))
        fh.write(data.tobytes())
    return p


@contextmanager
def _quiet_stdout() -> Iterator[None]:
    """Silence OpenCASCADE's transfer statistics, printed on file descriptor 1."""
    sys.stdout.flush()
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)


def export_step(mesh: TriangleMesh, path: str | Path, unit: str = "mm") -> Path:
    """Write ``mesh`` as a faceted STEP solid through OpenCASCADE (``OCP``).

    Raises
    ------
    SolidError
        If ``OCP`` (pip package ``cadquery-ocp``) is not installed, or the sewn shell is
        not closed.
    """
    try:
        from OCP.BRep import BRep_Builder
        from OCP.BRepBuilderAPI import (
            BRepBuilderAPI_MakeFace,
            BRepBuilderAPI_MakePolygon,
            BRepBuilderAPI_MakeSolid,
            BRepBuilderAPI_Sewing,
        )
        from OCP.gp import gp_Pnt
        from OCP.IFSelect import IFSelect_RetDone
        from OCP.Interface import Interface_Static
        from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
        from OCP.TopAbs import TopAbs_SHELL
        from OCP.TopExp import TopExp_Explorer
        from OCP.TopoDS import TopoDS, TopoDS_Compound
    except ImportError:
        raise SolidError(
            "STEP export needs the OpenCASCADE bindings: pip install 'reducerlab[step]' "
            "(the cadquery-ocp package), or write .stl / .ply"
        ) from None
    s = _scale(unit)
    V = mesh.vertices * s
    pts = [gp_Pnt(*map(float, v)) for v in V]
    tol = 1e-6 * float(np.ptp(V, axis=0).max())
    sew = BRepBuilderAPI_Sewing(tol)
    for a, b, c in mesh.faces:
        poly = BRepBuilderAPI_MakePolygon(pts[a], pts[b], pts[c], True)
        sew.Add(BRepBuilderAPI_MakeFace(poly.Wire(), True).Face())
    sew.Perform()
    sewn = sew.SewedShape()
    exp = TopExp_Explorer(sewn, TopAbs_SHELL)
    if not exp.More():
        raise SolidError("STEP export: the triangles did not sew into a closed shell")
    solid = BRepBuilderAPI_MakeSolid(TopoDS.Shell(exp.Current())).Solid()
    comp = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(comp)
    builder.Add(comp, solid)
    Interface_Static.SetCVal_s("write.step.unit", "MM" if unit == "mm" else "M")
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    with _quiet_stdout():
        writer = STEPControl_Writer()
        writer.Transfer(comp, STEPControl_AsIs)
        status = writer.Write(str(p))
    if status != IFSelect_RetDone:
        raise SolidError(f"STEP export: could not write {p}")
    return p
