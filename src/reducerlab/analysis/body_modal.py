"""Finite-element modes of the gear bodies of a nutation design (paper 000 §4, Table 4).

``body_modal(design, gear)`` meshes the gear generated from the design's ``[surface]``
table (:func:`reducerlab.fe.gear_mesh.mesh_gear`, blank from ``[gearN.blank]``),
assembles quadratic tetrahedra of the design's ``[material]`` and solves for the first
elastic modes, free-free (rigid modes removed) or with the bore or the mounting face
fixed: by cyclic symmetry on one tooth sector (:mod:`reducerlab.fe.cyclic`, the default)
or on the whole mesh at once (``method="full"``), the same discrete model. Each mode is
named by :mod:`reducerlab.fe.modetypes`, its shares weighted by the nodes' masses (the
HRZ lumped mass: the diagonal of the consistent mass matrix the eigen-solution used, so
a graded mesh does not count its fine teeth many times over). With ``convergence`` the
same gear is also solved on a mesh 1.5 times coarser and every mode states its
frequency change from that mesh to the result's: an upper estimate of the result's own
discretisation error (the error falls with the element size).
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..errors import DesignError, ReducerlabError, names_source
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..threads import with_compute_threads

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..fe.gear_mesh import GearBodyMesh

__all__ = [
    "BOUNDARIES",
    "METHODS",
    "BodyModalResult",
    "body_estimate",
    "body_modal",
    "check_bodies",
    "gear_blank",
]

#: Boundary conditions of the gear body.
BOUNDARIES = ("free", "bore", "face")
Boundary = Literal["free", "bore", "face"]
#: Solutions of the whole gear: by cyclic symmetry on one tooth sector (the default), or
#: on the whole mesh at once (the same discrete model; ``docs/body_modes.md``).
METHODS = ("cyclic", "full")
Method = Literal["cyclic", "full"]
#: Coarsening of the mesh the convergence estimate compares with.
COARSER = 1.5
Stage = Callable[[str], None]


class BodyModalResult(Result):
    """Natural frequencies (Hz) and mode types of one gear body.

    ``data`` has dimension ``mode`` (1..count) with ``frequency`` (Hz), ``type``
    (paper 000's names), ``nodal_diameters``, ``nodal_circles``, the ``axial``,
    ``radial`` and ``tangential`` shares of the modal displacement, ``family`` (repeated
    roots share one), ``coarse_frequency`` and ``change`` (relative change from the
    coarser mesh, NaN without the convergence run). ``mesh`` and ``shapes`` (the mode
    shapes at the mesh points, (n, 3, modes), m per unit modal mass) are kept in memory
    for renders and VTU export; they are not written to the netCDF file.
    """

    kind: ClassVar[str] = "body-modal"

    def __init__(
        self, data: xr.Dataset, mesh: GearBodyMesh | None = None, shapes: Any = None
    ) -> None:
        super().__init__(data)
        self.mesh = mesh
        self.shapes = shapes

    @property
    def frequencies(self) -> NDArray[np.float64]:
        """Natural frequencies (Hz), ascending."""
        return np.asarray(self.data["frequency"].values, dtype=float)

    @property
    def types(self) -> list[str]:
        """Mode type of each mode."""
        return [str(t) for t in self.data["type"].values]

    @property
    def labels(self) -> list[str]:
        """``"type (n = nodal diameters)"`` of each mode, for titles and VTU fields."""
        n = self.data["nodal_diameters"].values
        return [f"{t} (n = {k})" for t, k in zip(self.types, n, strict=True)]

    @property
    def max_change(self) -> float:
        """Largest relative frequency change from the coarser mesh (NaN without it)."""
        ch = np.asarray(self.data["change"].values, dtype=float)
        return float(np.max(np.abs(ch))) if np.all(np.isfinite(ch)) else math.nan

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: one row a mode, mesh and convergence attributes."""
        ds = self.data
        rows = []
        for i in range(ds.sizes["mode"]):
            row = {
                "mode": int(ds["mode"].values[i]),
                "frequency_hz": float(ds["frequency"].values[i]),
                "type": str(ds["type"].values[i]),
                "nodal_diameters": int(ds["nodal_diameters"].values[i]),
                "nodal_circles": int(ds["nodal_circles"].values[i]),
                "family": int(ds["family"].values[i]),
            }
            ch = float(ds["change"].values[i])
            row["change_from_coarser"] = None if math.isnan(ch) else ch
            rows.append(row)
        keys = ("gear", "teeth", "gear_kind", "boundary", "method", "tooth_size_mm",
                "body_size_mm", "tetrahedra", "dofs", "mass_kg", "seconds")  # fmt: skip
        out = {k: _plain(ds.attrs[k]) for k in keys if k in ds.attrs}
        out["max_change_from_coarser"] = None if math.isnan(self.max_change) else self.max_change
        out["modes"] = rows
        return out

    def table(self) -> str:
        """Plain-text table of the modes."""
        a = self.data.attrs
        lines = [
            f"Gear {a.get('gear')} body ({a.get('gear_kind')}, z = {a.get('teeth')}), "
            f"{a.get('boundary')}: {a.get('tetrahedra')} quadratic tetrahedra, "
            f"{a.get('dofs')} DOFs, mass {fmt(1e3 * float(a.get('mass_kg', math.nan)))} g",
        ]
        t = Table([Column("mode", kind="count"), Column("frequency", "Hz", "frequency"),
                   Column("type", kind="text"), Column("n", kind="count"),
                   Column("circles", kind="count"),
                   Column("change from coarser", "%", "percent")])  # fmt: skip
        for r in self.to_dict()["modes"]:
            ch = r["change_from_coarser"]
            t.add(r["mode"], r["frequency_hz"], r["type"], r["nodal_diameters"],
                  r["nodal_circles"], None if ch is None else 100 * ch)  # fmt: skip
        lines.append(t.text())
        return "\n".join(lines)

    def figure(self) -> Figure:
        """Mode-shape renders of all modes in one figure (needs the in-memory mesh)."""
        from ..plot.body import plot_body_modes_grid

        mesh, shapes = self._shapes()
        a = self.data.attrs
        return plot_body_modes_grid(
            mesh.points, mesh.tets[:, :4], shapes, self.frequencies, self.labels,
            f"Gear {a.get('gear')} body modes ({a.get('boundary')})",
        )  # fmt: skip

    def _shapes(self) -> tuple[GearBodyMesh, Any]:
        if self.mesh is None or self.shapes is None:
            raise ReducerlabError(
                "body modal result: the mesh and mode shapes are kept only in the session "
                "that computed them (not in the netCDF file): run body_modal again"
            )
        return self.mesh, self.shapes


def _plain(v: Any) -> Any:
    return v.item() if hasattr(v, "item") else v


def check_bodies(design: Any) -> None:
    """Refuse a design whose gear bodies cannot be generated: not a nutation design, or
    one without a ``[surface]`` table."""
    kind = design.type if isinstance(design, Design) else "?"
    if kind != "nutation":
        raise ReducerlabError(
            f"body modal: type = {kind!r}: gear bodies need a nutation "
            "design with a [surface] table"
        )
    if not design.has_tooth_surfaces:
        raise ReducerlabError(
            "body modal: the design has no [surface] table (profile, face_width): the gear "
            "solid cannot be generated; see examples/nutation_double_sided.toml"
        )


def gear_blank(design: Any, gear: int) -> tuple[float, Any]:
    """Rim thickness (m) and :class:`~reducerlab.fe.gear_mesh.BlankFeatures` of ``gear``
    from the design (``[gearN.blank]``, defaults in ``docs/assumptions.md``), checked
    against the gear's radii before any CAD work.

    Raises
    ------
    DesignError
        Naming the design field that does not fit (``gear1.blank.rim = '100 mm':
        reaches past the axis ...``), or the default it came from.
    """
    from ..fe.gear_mesh import BlankFeatures, MeshError, check_blank

    spec = getattr(design, f"gear{gear}").blank
    crown, bevel = design.tooth_generation(gear)
    m_n = crown.profile.module
    rim = design.surface.rim if design.surface.rim is not None else 2.0 * m_n
    features = BlankFeatures()
    if spec is not None:
        rim = spec.rim if spec.rim is not None else rim
    if spec is not None and spec.bore is not None:
        dflt = BlankFeatures.default(spec.bore, rim, design.surface.face_width)
        features = BlankFeatures(
            spec.bore,
            spec.web if spec.web is not None else dflt.web,
            spec.hub if spec.hub is not None else dflt.hub,
            spec.hub_length if spec.hub_length is not None else dflt.hub_length,
        )
    try:
        check_blank(crown, bevel, rim, features)
    except MeshError as exc:
        raise DesignError(_blank_field(design, gear, rim, features, str(exc))) from None
    return rim, features


def _blank_field(design: Any, gear: int, rim: float, features: Any, message: str) -> str:
    """``path = 'value': rule`` for a blank error ``message`` (``rim: ...``,
    ``blank.web: ...``): the design field it came from, or the default it used."""
    name, _, rule = message.partition(": ")
    field = name.removeprefix("blank.")
    spec = getattr(design, f"gear{gear}").blank
    given = spec is not None and getattr(spec, field, None) is not None
    if field == "rim":
        value = rim
        if given:
            path = f"gear{gear}.blank.rim"
        elif design.surface.rim is not None:
            path = "surface.rim"
        else:
            path = f"gear{gear}.blank.rim (default 2 m_n)"
    else:
        value = getattr(features, field, None)
        path = f"gear{gear}.blank.{field}" + ("" if given else " (default)")
    shown = f"{value * 1e3:.6g} mm" if isinstance(value, int | float) else repr(value)
    return f"{path} = {shown!r}: {rule}"


def body_estimate(
    design: Any, gear: int, sizes: Any = None, method: Method = "cyclic", count: int = 10
) -> Any:
    """The :class:`~reducerlab.budget.Estimate` of gear ``gear``'s body-modal mesh and
    eigen-solution (tetrahedra, DOFs of the whole gear, memory of ``method`` for
    ``count`` modes) from the blank and the element sizes, before any meshing;
    :meth:`~reducerlab.budget.Estimate.check` refuses it naming the sizes and the blank
    fields."""
    from ..fe.cyclic import cyclic_estimate
    from ..fe.gear_mesh import MeshSizes, mesh_estimate

    crown, bevel = design.tooth_generation(gear)
    rim, features = gear_blank(design, gear)
    sizes = MeshSizes.default(crown.profile.module) if sizes is None else sizes
    full = mesh_estimate(
        crown, bevel, rim, features, sizes, what=f"gear {gear} body",
        control=f"the element sizes (--tooth-size, --body-size; sizes=) or the blank "
        f"(gear{gear}.blank.rim, surface.rim, gear{gear}.blank.web/hub)",
    )  # fmt: skip
    if method == "full":
        return full
    one = mesh_estimate(crown, bevel, rim, features, sizes, what="", control="", sectors=1)
    return cyclic_estimate(full, one, count)


def _fixed_dofs(basis: Any, mesh: GearBodyMesh, boundary: Boundary) -> NDArray[np.int64] | None:
    """DOFs held at zero: all DOFs of the boundary facets whose three corners lie on the
    bore (the rim ring's seat, its body cone, without a bore) or on the mounting face.
    Corners lie exactly on the CAD surfaces; facet midpoints of curved facets do not."""
    if boundary == "free":
        return None
    skm = basis.mesh
    tol = 1e-6 * float(np.max(np.abs(mesh.points)))
    x = skm.p  # corners of the scikit-fem mesh (m)
    if boundary == "bore" and mesh.bore_radius is not None:
        on = np.abs(np.hypot(x[0], x[1]) - mesh.bore_radius) < tol
    elif boundary == "bore":
        from ..geometry.solid import cone_coordinates

        h = cone_coordinates(x.T, mesh.gear.cone_angle)[1]
        on = np.abs(h - mesh.blank.body) < tol
    else:
        on = np.abs(x[2] - mesh.mount_z) < tol
    bf = skm.boundary_facets()
    facets = bf[np.all(on[skm.facets[:, bf]], axis=0)]
    if len(facets) == 0:
        where = "bore" if boundary == "bore" else "mounting face"
        raise ReducerlabError(
            f"boundary {boundary!r}: no boundary facets lie on the {where}: the fixed set is empty"
        )
    return np.asarray(basis.get_dofs(facets=facets).all(), dtype=np.int64)


def _solve(
    mesh: GearBodyMesh, material: Any, count: int, boundary: Boundary, stage: Stage,
    method: Method = "cyclic",
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int, float,
    tuple[float, float, float],
]:  # fmt: skip
    """Frequencies (Hz), shapes at the mesh points (n, 3, count), the points' HRZ masses
    (n,) (kg), DOFs, mass (kg), moments of inertia ``(J_x, J_y, J_z)`` (kg m^2)."""
    from ..fe import assemble, body_modes

    if method == "cyclic":
        return _solve_cyclic(mesh, material, count, boundary, stage)
    stage(f"assembling {len(mesh.tets)} quadratic tetrahedra")
    skm = mesh.skfem()
    K, M, basis = assemble(skm, material, order=2)
    fixed = _fixed_dofs(basis, mesh, boundary)
    stage(f"solving {K.shape[0]} DOFs (shift-invert Lanczos)")
    with _support(boundary, fixed):
        modes = body_modes(K, M, count, fixed=fixed)
    _check_rigid(modes.rigid, boundary, fixed)
    # displacement at the corner nodes and at the mid-edge nodes of the mesh points
    shapes = _at_points(basis, mesh, modes.shapes)
    mass = _translation_mass(basis, M)
    weights = _at_points(basis, mesh, np.asarray(M.diagonal(), dtype=float)[:, None])[:, 0, 0]
    inertia = _rigid_inertia(basis, M, mass)
    return modes.frequencies, shapes, weights * (mass / weights.sum()), K.shape[0], mass, inertia


def _solve_cyclic(
    mesh: GearBodyMesh, material: Any, count: int, boundary: Boundary, stage: Stage
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int, float,
    tuple[float, float, float],
]:  # fmt: skip
    """:func:`_solve` by cyclic symmetry (:mod:`reducerlab.fe.cyclic`): one tooth sector
    assembled, one Hermitian sector problem per harmonic, the modes expanded to the whole
    mesh. The body's mass is ``z`` times the sector's, its polar moment too, and its
    diametral moments ``J_x = J_y = z (J_x,s + J_y,s) / 2`` (the sum over the turned
    sectors for ``z >= 3``); the HRZ masses of a wall node add both sectors'."""
    from ..fe import assemble
    from ..fe.cyclic import cyclic_modes, sector_of
    from ..fe.elasticity import point_dofs

    z = mesh.gear.teeth
    sector = sector_of(mesh.points, mesh.tets, z, mesh.sector_tets)
    stage(f"assembling one of {z} tooth sectors ({len(sector.tets)} quadratic tetrahedra)")
    K, M, basis = assemble(sector.skfem(), material, order=2)
    fixed = _fixed_dofs(basis, mesh, boundary)
    dofs = point_dofs(basis, sector.tets, len(sector.points))
    with _support(boundary, fixed):
        modes = cyclic_modes(sector, K, M, dofs, count, fixed=fixed, stage=stage)
    _check_rigid(modes.rigid, boundary, fixed)
    mass = _translation_mass(basis, M)
    J_x, J_y, J_z = _rigid_inertia(basis, M, mass)
    weights = sector.tile(np.asarray(M.diagonal(), dtype=float)[dofs[:, 0]])
    J_d = 0.5 * z * (J_x + J_y)
    return (
        modes.frequencies, modes.shapes, weights * (z * mass / weights.sum()),
        3 * len(mesh.points), z * mass, (J_d, J_d, z * J_z),
    )  # fmt: skip


@contextlib.contextmanager
def _support(boundary: Boundary, fixed: Any) -> Iterator[None]:
    """An eigen-solver failure with a fixed set as the boundary's error."""
    from ..errors import ModelError

    try:
        yield
    except ModelError as exc:
        if fixed is not None:
            raise ReducerlabError(
                f"boundary {boundary!r}: the eigen-solution failed with this fixed set ({exc})"
            ) from None
        raise


def _check_rigid(rigid: int, boundary: Boundary, fixed: Any) -> None:
    """Refuse a free body without six rigid modes, or a held one with any."""
    if fixed is None and rigid != 6:
        raise ReducerlabError(
            f"free-free gear body: found {rigid} rigid-body modes instead of 6 (a "
            "disconnected or badly shaped mesh)"
        )
    if fixed is not None and rigid:
        raise ReducerlabError(
            f"boundary {boundary!r}: the fixed set leaves {rigid} rigid-body "
            "mode(s) (a singular support)"
        )


def _translation_mass(basis: Any, M: Any) -> float:
    """Mass of the body (kg): ``e^T M e`` for the unit translation along x."""
    e = np.zeros(M.shape[0])
    e[basis.nodal_dofs[0]] = 1.0
    e[basis.edge_dofs[0]] = 1.0
    return float(e @ (M @ e))


def _rigid_inertia(basis: Any, M: Any, mass: float) -> tuple[float, float, float]:
    """Moments of inertia (kg m^2) of the body about its centre of mass: ``J_x, J_y``
    (diametral, about axes through the centre) and ``J_z`` (polar, about the gear axis
    z through x = y = 0): ``u^T M u`` for the unit rigid rotation field ``u = e x (r -
    c)`` about each axis, exact for the quadratic elements (the field is linear)."""
    loc = np.asarray(basis.doflocs, dtype=float)
    d = [np.r_[basis.nodal_dofs[k], basis.edge_dofs[k]] for k in range(3)]
    n = M.shape[0]

    def quad(u: NDArray[np.float64], w: NDArray[np.float64] | None = None) -> float:
        return float(u @ (M @ (u if w is None else w)))

    ez, zf = np.zeros(n), np.zeros(n)
    ez[d[2]] = 1.0
    zf[d[2]] = loc[2, d[2]]
    zc = quad(ez, zf) / mass  # centre of mass along the axis
    rel = loc.copy()
    rel[2] -= zc
    out = []
    for a in range(3):  # rotation about axis a: u_b = -r_c, u_c = r_b (cyclic b, c)
        b, c = (a + 1) % 3, (a + 2) % 3
        u = np.zeros(n)
        u[d[b]] = -rel[c, d[b]]
        u[d[c]] = rel[b, d[c]]
        out.append(quad(u))
    return out[0], out[1], out[2]


def _at_points(basis: Any, mesh: GearBodyMesh, shapes: Any) -> NDArray[np.float64]:
    """Mode shapes (n_points, 3, modes) at ``mesh.points`` from the P2 DOFs
    (:func:`~reducerlab.fe.elasticity.point_dofs`); 0 at a point no tetrahedron uses."""
    from ..fe.elasticity import point_dofs

    dofs = point_dofs(basis, mesh.tets, len(mesh.points))
    out = np.zeros((len(mesh.points), 3, shapes.shape[1]))
    used = dofs[:, 0] >= 0
    out[used] = shapes[dofs[used]]
    return out


def _mesh(design: Any, gear: int, crown: Any, bevel: Any, rim: float, features: Any,
          sizes: Any, say: Stage, budget: Any) -> GearBodyMesh:  # fmt: skip
    """:func:`~reducerlab.fe.gear_mesh.mesh_gear`, its failures naming the gear and its
    body fields."""
    from ..fe.gear_mesh import MeshError, mesh_gear

    try:
        return mesh_gear(crown, bevel, rim=rim, features=features, sizes=sizes, stage=say,
                         budget=budget)  # fmt: skip
    except MeshError as exc:
        body = f"rim = {rim * 1e3:.4g} mm"
        if features.bore is not None:
            body += (
                f", bore = {features.bore * 1e3:.4g} mm, web = {features.web * 1e3:.4g} mm, "
                f"hub = {features.hub * 1e3:.4g} mm, hub_length = "
                f"{features.hub_length * 1e3:.4g} mm"
            )
        raise MeshError(
            f"gear {gear} body ({body}; fields gear{gear}.blank.*, surface.rim): {exc}"
        ) from None


def _coarser(sizes: Any, crown: Any, bevel: Any, rim: float) -> Any:
    """The convergence run's sizes: ``COARSER`` times the result's, the tooth size kept
    within the half tooth depth that :func:`~reducerlab.fe.gear_mesh.mesh_gear` allows."""
    from ..fe.gear_mesh import MeshSizes, max_tooth_size

    cap = max_tooth_size(crown, bevel, rim)
    c = sizes.refined(COARSER)
    return MeshSizes(min(c.tooth, cap), max(c.body, min(c.tooth, cap)))


@names_source
@with_compute_threads
def body_modal(
    design: Any,
    gear: int,
    *,
    count: int = 10,
    boundary: Boundary = "free",
    sizes: Any = None,
    convergence: bool = True,
    method: Method = "cyclic",
    stage: Stage | None = None,
) -> BodyModalResult:
    """Natural frequencies and mode types of gear ``gear`` of a nutation design.

    Parameters
    ----------
    design : NutationDesign
        With a ``[surface]`` table.
    gear : int
        1..4 (double-sided) or 1..2.
    count : int
        Elastic modes (1..50); paper 000 gives ten.
    boundary : {"free", "bore", "face"}
        Free-free (six rigid modes found and removed), the bore fixed (the rim ring's
        seat without a bore) or the mounting face fixed.
    sizes : MeshSizes, optional
        Default :meth:`~reducerlab.fe.gear_mesh.MeshSizes.default`.
    convergence : bool
        Also solve on a mesh ``1.5`` times coarser and state the change per mode.
    method : {"cyclic", "full"}
        ``"cyclic"``: one tooth sector with complex periodic conditions per harmonic
        index (:mod:`reducerlab.fe.cyclic`; Thomas 1979), the modes expanded to the
        whole gear; ``"full"``: the whole mesh at once. The same discrete model: the
        frequencies agree to 1e-6 (``docs/body_modes.md``, "Cyclic symmetry").
    stage : callable, optional
        ``stage(description)`` at each stage (progress display).
    """
    from ..fe import Material
    from ..fe.gear_mesh import MeshSizes, check_sizes
    from ..fe.modetypes import classify_modes

    check_bodies(design)
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 50:
        raise ReducerlabError(f"count: must be an integer in [1, 50], got {count!r}")
    if boundary not in BOUNDARIES:
        raise ReducerlabError(f"boundary: must be one of {BOUNDARIES}, got {boundary!r}")
    if method not in METHODS:
        raise ReducerlabError(f"method: must be one of {METHODS}, got {method!r}")
    n_gears = design.gear_count
    if isinstance(gear, bool) or gear not in range(1, n_gears + 1):
        raise ReducerlabError(
            f"gear: must be 1..{n_gears} for a {design.sides}-sided drive, got {gear!r}"
        )
    say = stage or (lambda _s: None)
    t0 = time.perf_counter()
    crown, bevel = design.tooth_generation(gear)
    rim, features = gear_blank(design, gear)
    mat = design.material
    material = Material(mat.youngs_modulus, mat.poisson_ratio, mat.density)
    sizes = MeshSizes.default(crown.profile.module) if sizes is None else sizes
    check_sizes(crown, bevel, rim, sizes)  # before the convergence run
    # the finer mesh, before any meshing
    budget = body_estimate(design, gear, sizes, method, count).check()
    coarse_f = np.full(count, math.nan)
    if convergence:
        say("coarser mesh (convergence check)")
        coarse = _mesh(design, gear, crown, bevel, rim, features,
                       _coarser(sizes, crown, bevel, rim), say, budget)  # fmt: skip
        coarse_f = _solve(coarse, material, count, boundary, say, method)[0]
    mesh = _mesh(design, gear, crown, bevel, rim, features, sizes, say, budget)
    freq, shapes, weights, dofs, mass, (J_x, J_y, J_z) = _solve(
        mesh, material, count, boundary, say, method
    )
    say("classifying the modes")
    types = classify_modes(mesh.points, shapes, freq, weights)
    change = freq / coarse_f - 1.0 if convergence else coarse_f
    shares = {k: np.array([t.shares[k] for t in types]) for k in ("axial", "radial", "tangential")}
    ds = xr.Dataset(
        {
            "frequency": ("mode", freq, {"units": "Hz"}),
            "type": ("mode", np.array([t.name for t in types], dtype=object)),
            "nodal_diameters": ("mode", np.array([t.nodal_diameters for t in types])),
            "nodal_circles": ("mode", np.array([t.nodal_circles for t in types])),
            "family": ("mode", np.array([t.family for t in types])),
            "axial": ("mode", shares["axial"]),
            "radial": ("mode", shares["radial"]),
            "tangential": ("mode", shares["tangential"]),
            "coarse_frequency": ("mode", coarse_f, {"units": "Hz"}),
            "change": ("mode", change),
        },
        coords={"mode": np.arange(1, len(freq) + 1)},
        attrs={"title": f"Gear {gear} body modes", **provenance(design.provenance)},
    )
    ds.attrs.update(
        gear=int(gear), teeth=int(bevel.teeth), gear_kind=bevel.kind, boundary=boundary,
        method=method,
        tooth_size_mm=sizes.tooth * 1e3, body_size_mm=sizes.body * 1e3,
        tetrahedra=len(mesh.tets), dofs=dofs, mass_kg=mass,
        J_x_kg_m2=J_x, J_y_kg_m2=J_y, J_z_kg_m2=J_z,
        seconds=time.perf_counter() - t0,
        material=f"E = {mat.youngs_modulus:.6g} Pa, nu = {mat.poisson_ratio:.4g}, "
        f"rho = {mat.density:.6g} kg/m^3",
        blank=repr(features), rim_m=rim,
    )  # fmt: skip
    return BodyModalResult(ds, mesh, shapes)
