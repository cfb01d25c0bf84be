"""VTU output of tetrahedral meshes and their mode shapes (ParaView, VisIt), and the
boundary triangles of a tetrahedral mesh (for renders).

:func:`write_vtu` writes an XML unstructured grid (``.vtu``, via meshio) of linear
tetrahedra with, for each mode, the displacement vector field at the points and its
magnitude, and the natural frequencies as field data. **Points are in metres** (SI, as
everywhere in :mod:`reducerlab.fe`); mode shapes are written as given (mass-normalised
shapes are in m per unit modal mass: scale them freely for display, e.g. ParaView's
*Warp By Vector*).
"""

from __future__ import annotations

import os
import re
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = ["boundary_faces", "checked_points", "checked_tets", "mode_field_names", "write_vtu"]

Array = NDArray[np.float64]

#: The faces of a tetrahedron ``(0, 1, 2, 3)``, each opposite vertex ``k`` for row ``k``,
#: ordered so that their right-hand normals point outward when the tetrahedron is
#: positively oriented (``((p1 - p0) x (p2 - p0)) . (p3 - p0) > 0``).
_TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


def boundary_faces(tets: ArrayLike, points: ArrayLike | None = None) -> NDArray[np.int64]:
    """The boundary triangles of a tetrahedral mesh, oriented outward.

    A boundary face is a face used by exactly one tetrahedron; its vertices are ordered
    so that its right-hand normal ``(b - a) x (c - a)`` points away from the fourth
    vertex of that tetrahedron (out of the body).

    Parameters
    ----------
    tets : array_like of int (m, 4)
        Linear tetrahedra (vertex indices; for quadratic ones pass ``tets[:, :4]``).
    points : array_like (n, 3), optional
        The vertices. With them each face is oriented by the geometry, whatever the
        orientation of its tetrahedron; without them the tetrahedra are taken to be
        positively oriented (as :func:`~reducerlab.fe.gear_mesh.mesh_gear` gives them).

    Returns
    -------
    faces : ndarray of int (k, 3)
        In the order of their tetrahedra.

    Raises
    ------
    ReducerlabError
        Bad arrays, or a face shared by more than two tetrahedra (not a conforming
        mesh of a solid).
    """
    t = checked_tets(tets, None if points is None else len(checked_points(points)))
    faces = t[:, _TET_FACES].reshape(-1, 3)  # tet i's faces at rows 4 i .. 4 i + 3
    opposite = t.reshape(-1)
    s = np.sort(faces, axis=1)
    n = int(t.max()) + 1 if t.size else 1
    if n < 2**21:  # one int64 key per face: fast unique
        key: NDArray[Any] = (s[:, 0] * n + s[:, 1]) * n + s[:, 2]
        _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    else:
        _, inverse, counts = np.unique(s, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    if counts.size and counts.max() > 2:
        raise ReducerlabError(
            "tets: a face is shared by more than two tetrahedra (not a conforming mesh of a solid)"
        )
    keep = counts[inverse] == 1
    out, opp = faces[keep], opposite[keep]
    if points is not None:
        p = np.asarray(points, dtype=float)
        a = p[out[:, 0]]
        normal = np.cross(p[out[:, 1]] - a, p[out[:, 2]] - a)
        inward = np.einsum("ij,ij->i", normal, p[opp] - a) > 0
        out[inward] = out[inward][:, ::-1]
    return out.astype(np.int64, copy=False)


def mode_field_names(
    frequencies: ArrayLike | None = None, types: Sequence[str] | None = None, count: int = 0
) -> list[str]:
    """Names of the mode fields :func:`write_vtu` writes: ``mode_01_4162.7Hz``, with
    ``_<type>`` appended when types are given (``"bending (n=2)"`` -> ``_bending_n_2``);
    ``count`` modes when no frequencies are given."""
    f = None if frequencies is None else np.asarray(frequencies, dtype=float).reshape(-1)
    m = len(f) if f is not None else (len(types) if types is not None else count)
    width = max(2, len(str(m)))
    names = []
    for i in range(m):
        name = f"mode_{i + 1:0{width}d}"
        if f is not None:
            name += f"_{f[i]:.1f}Hz"
        if types is not None:
            tag = re.sub(r"[^0-9A-Za-z.+-]+", "_", str(types[i])).strip("_")
            name += f"_{tag}" if tag else ""
        names.append(name)
    return names


def write_vtu(
    path: str | os.PathLike[str],
    points: ArrayLike,
    tets: ArrayLike,
    shapes: ArrayLike | None = None,
    frequencies: ArrayLike | None = None,
    types: Sequence[str] | None = None,
    cell_data: Mapping[str, ArrayLike] | None = None,
) -> Path:
    """Write a tetrahedral mesh and its mode shapes to a VTU file.

    Parameters
    ----------
    path : str or PathLike
        The file (``.vtu``); its folder must exist.
    points : array_like (n, 3)
        The vertices, **in metres**.
    tets : array_like of int (m, 4)
        Linear tetrahedra (indices into ``points``; for quadratic ones pass
        ``tets[:, :4]``). Points used by no tetrahedron are allowed.
    shapes : array_like (n, 3) or (n, 3, modes), optional
        Displacement of every point in each mode (any scale). Each mode ``i`` becomes a
        point-data vector field named as :func:`mode_field_names` gives
        (``mode_01_4162.7Hz``) and a scalar field ``<name>_magnitude``.
    frequencies : array_like (modes,), optional
        Natural frequencies (Hz), finite and >= 0: in the field names and as field data
        ``frequency_Hz`` (with ``mode``, the mode numbers 1..modes).
    types : sequence of str (modes,), optional
        Mode names (e.g. ``"folding (n = 2)"``), appended to the field names.
    cell_data : mapping of str to array_like (m,) or (m, k), optional
        Extra per-tetrahedron fields (e.g. element quality).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ReducerlabError
        An argument of the wrong shape or type, non-finite values, indices out of
        range, or frequencies/types that do not match the shapes; the message names the
        argument.
    """
    import meshio

    p = checked_points(points)
    n = len(p)
    t = checked_tets(tets, n)
    if len(t) == 0:
        raise ReducerlabError("tets: need at least one tetrahedron")
    s = None
    if shapes is not None:
        s = finite_array("shapes", shapes)
        if s.ndim == 2:
            s = s[:, :, None]
        if s.ndim != 3 or s.shape[:2] != (n, 3):
            raise ReducerlabError(
                f"shapes: must have shape ({n}, 3) or ({n}, 3, modes) for {n} points, "
                f"got {np.shape(shapes)}"
            )
    modes = s.shape[2] if s is not None else 0
    f = None
    if frequencies is not None:
        f = finite_array("frequencies", frequencies)
        if f.ndim != 1 or (s is not None and len(f) != modes):
            raise ReducerlabError(
                f"frequencies: must be 1-D with one value per mode ({modes} modes), got "
                f"shape {f.shape}"
            )
        if s is None:
            raise ReducerlabError("frequencies: given without shapes")
        if np.any(f < 0):
            raise ReducerlabError("frequencies: must be >= 0 (Hz)")
    if types is not None:
        if isinstance(types, str) or not all(isinstance(x, str) for x in types):
            raise ReducerlabError("types: must be a sequence of str, one per mode")
        if s is None:
            raise ReducerlabError("types: given without shapes")
        if len(types) != modes:
            raise ReducerlabError(f"types: need one per mode ({modes}), got {len(types)}")
    point_data: dict[str, Array] = {}
    if s is not None:
        for i, name in enumerate(mode_field_names(f, types, modes)):
            u = np.ascontiguousarray(s[:, :, i])
            point_data[name] = u
            point_data[f"{name}_magnitude"] = np.linalg.norm(u, axis=1)
    cells: dict[str, list[Array]] = {}
    for name, value in (cell_data or {}).items():
        if not isinstance(name, str) or not name:
            raise ReducerlabError(f"cell_data: names must be non-empty str, got {name!r}")
        a = finite_array(f"cell_data[{name!r}]", value)
        if a.ndim not in (1, 2) or len(a) != len(t):
            raise ReducerlabError(
                f"cell_data[{name!r}]: must have shape ({len(t)},) or ({len(t)}, k) "
                f"(one row per tetrahedron), got {a.shape}"
            )
        cells[name] = [a]
    try:
        out = Path(os.fspath(path))
    except TypeError:
        raise ReducerlabError(f"path: must be a file path, got {path!r}") from None
    if not out.parent.is_dir():
        raise ReducerlabError(f"path: folder {str(out.parent)!r} does not exist")
    mesh = meshio.Mesh(p, [("tetra", t)], point_data=point_data, cell_data=cells)
    fd, tmp = tempfile.mkstemp(suffix=".vtu", dir=out.parent)
    os.close(fd)
    try:
        meshio.write(tmp, mesh, file_format="vtu")
        _add_field_data(tmp, f, modes)
        umask = os.umask(0)  # mkstemp made it private: give it the usual permissions
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return out


def _add_field_data(path: str, frequencies: Array | None, modes: int) -> None:
    """meshio (5.3) does not write field data to VTU: insert it, with a comment on the
    units, as the first child of ``<UnstructuredGrid>``."""
    text = Path(path).read_text(encoding="utf-8")
    comment = (
        "<!-- reducerlab: points in metres; mode_* fields are displacements (shape units)"
        + (", frequency_Hz in Hz" if frequencies is not None else "")
        + " -->\n"
    )
    arrays = ""
    if frequencies is not None:
        values = " ".join(repr(float(x)) for x in frequencies)
        number = " ".join(str(i + 1) for i in range(modes))
        arrays = (
            "<FieldData>\n"
            f'<DataArray type="Float64" Name="frequency_Hz" NumberOfTuples="{modes}" '
            f'format="ascii">\n{values}\n</DataArray>\n'
            f'<DataArray type="Int64" Name="mode" NumberOfTuples="{modes}" '
            f'format="ascii">\n{number}\n</DataArray>\n'
            "</FieldData>\n"
        )
    match = re.search(r"<UnstructuredGrid[^>]*>", text)
    if match is None:  # pragma: no cover - meshio always writes it
        raise ReducerlabError("write_vtu: unexpected VTU layout from meshio")
    start, end = match.span()
    text = text[:start] + comment + text[start:end] + "\n" + arrays + text[end:]
    Path(path).write_text(text, encoding="utf-8")


# -- input checks ------------------------------------------------------------------------


def finite_array(name: str, value: ArrayLike) -> Array:
    """``value`` as a float array, or an error naming ``name`` (not numbers, not finite)."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ReducerlabError(f"{name}: must be an array of numbers") from None
    if not np.all(np.isfinite(a)):
        raise ReducerlabError(f"{name}: must be finite (no NaN or inf)")
    return a


def checked_points(points: ArrayLike) -> Array:
    """``points`` as a finite ``(n, 3)`` float array, ``n >= 1`` (m).

    Raises
    ------
    ReducerlabError
        Naming ``points`` and the rule broken.
    """
    p = finite_array("points", points)
    if p.ndim != 2 or p.shape[1] != 3 or len(p) == 0:
        raise ReducerlabError(f"points: must have shape (n, 3) with n >= 1, got {p.shape}")
    return p


def checked_tets(tets: ArrayLike, n: int | None, name: str = "tets") -> NDArray[np.int64]:
    """``tets`` as an ``(m, 4)`` integer array of vertex indices of linear tetrahedra.

    Parameters
    ----------
    tets : array_like
        Vertex indices (integers, or floats with integer values).
    n : int or None
        Number of points the indices refer to (None: not checked against a count).
    name : str
        What the errors call the array.

    Raises
    ------
    ReducerlabError
        For a wrong shape, non-integer, negative or out-of-range indices, or a
        tetrahedron that repeats a vertex.
    """
    a = np.asarray(tets)
    if a.dtype == object or not (
        np.issubdtype(a.dtype, np.integer)
        or (np.issubdtype(a.dtype, np.floating) and np.all(np.isfinite(a)) and np.all(a % 1 == 0))
    ):
        raise ReducerlabError(f"{name}: must be an array of integer vertex indices")
    if a.ndim != 2 or a.shape[1] != 4:
        hint = " (pass tets[:, :4] for quadratic tetrahedra)" if a.ndim == 2 else ""
        raise ReducerlabError(f"{name}: must have shape (m, 4), got {a.shape}{hint}")
    t = a.astype(np.int64)
    if t.size and t.min() < 0:
        raise ReducerlabError(f"{name}: vertex indices must be >= 0, got {int(t.min())}")
    if n is not None and t.size and t.max() >= n:
        raise ReducerlabError(
            f"{name}: vertex index {int(t.max())} out of range for {n} points (0..{n - 1})"
        )
    if t.size and np.any(np.diff(np.sort(t, axis=1), axis=1) == 0):
        raise ReducerlabError(f"{name}: a tetrahedron repeats a vertex")
    return t
