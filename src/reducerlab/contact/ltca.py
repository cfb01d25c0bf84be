"""Loaded tooth contact analysis (LTCA) over a mesh cycle.

At each mesh position ``phi`` (rotation of gear A):

1. **Unloaded contact (TCA).** On a coarse grid of each tooth pair ``k`` the exact
   separation ``t`` along A's normal and the lever ``lam`` of B's rotation are computed
   (``contact.flanks.separations``). The unloaded transmission error is the rotation of
   B that closes the first point, ``psi_0 = min t / lam``; ``g = t - lam psi_0`` is the
   ease-off (separation field) of the aligned pair.
2. **Contact grid.** Coarse cells whose separation is below ``s_max`` (and their
   neighbours) are split into fine cells (``cell`` in arc length), evaluated exactly.
3. **Compliance.** ``C = C_hs + W_A K_A W_A^T + W_B K_B W_B^T``: the half-space
   (Boussinesq) influence of the fine cells of both gears (``contact.halfspace``) and the
   finite-element bending compliance of each gear interpolated to the cells
   (``contact.compliance``).
4. **Load distribution.** The complementarity problem ``C F + g - lam psi >= 0 _|_
   F >= 0``, ``lam . F = T_B`` is solved exactly (``contact.complementarity``), warm
   started from the previous position.
5. **Completeness check.** If a point left out of the contact grid (separation above
   ``s_max``) would have closed under the loaded approach ``lam psi``, ``s_max`` grows
   and the position is solved again, so the result never depends on the first guess.

The loaded transmission error ``psi`` and the mesh stiffness
``k = T_B / ((a_y r_mB)^2 psi)`` (``a_y r_mB``: the lever of the lumped model's mesh,
paper 000 Eq. 2-4) follow at each position.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import RegularGridInterpolator

from ..budget import Estimate
from ..errors import ReducerlabError
from .complementarity import MAX_SET, ContactError, solve_contact
from .flanks import MeshPair, separations

__all__ = [
    "MAX_CANDIDATES",
    "MAX_GRID_CELLS",
    "ContactGrid",
    "PatchWidth",
    "PositionContact",
    "auto_grid",
    "candidate_estimate",
    "flank_size",
    "grid_estimate",
    "loaded_area",
    "loaded_contact",
    "patch_widths",
]

Array = NDArray[np.float64]


#: largest separation (m) the grid is ever widened to before giving up
S_MAX_LIMIT = 1e-3

#: the next position's grid admits separations up to this many times the largest rigid
#: approach ``lam psi`` of the last one (a point farther apart cannot close: its loaded
#: gap ``g - lam psi + (C F)_i`` stays positive); the completeness check widens it
#: where the next position needs more
MARGIN = 1.1


#: fine cells on one flank at most (the documented work bound of the contact grid): 3x
#: the finest automatic grid (``0.01 m_n`` cells) of a flank 15 m_n wide
MAX_GRID_CELLS = 1_000_000

#: bytes per fine cell of the grid set-up, both flanks (cell axes and geometry, the
#: flank-edge distance maps; measured 510 B on ``examples/nutation_surface.toml``)
GRID_BYTES = 640

#: candidate cells of one mesh position at most (the dense compliance matrix among them
#: is made column by column; its contact set is bounded by ``MAX_SET``)
MAX_CANDIDATES = 3 * MAX_SET

#: the setting that sizes the contact grid, as the refusals name it
CELL_CONTROL = "the contact cell (--cell, cell=)"


@dataclass(frozen=True)
class ContactGrid:
    """Resolution of the contact grid.

    Attributes
    ----------
    cell : float
        Fine cell size (m) along the profile and along the face (arc length).
    coarse : int
        Fine cells per coarse cell along each direction (the coarse grid finds the
        potential contact region).
    teeth : tuple of int
        Tooth pairs examined at each position.
    s_max : float
        First guess of the largest separation that can close under load (m); grown
        automatically when too small.
    edge_band : float, optional
        Width of the band along the flank edges whose cells count as edge contact (m);
        default two of the longer cells. Fix it in length when comparing grids.
    face_cell : float, optional
        Fine cell size along the face (m), if other than ``cell`` (which then sizes the
        cells along the profile): a contact line running along the face is narrow
        across the profile and long along the face (``analysis.contact.auto_grid``).
    """

    cell: float
    coarse: int = 4
    teeth: tuple[int, ...] = (-1, 0, 1)
    s_max: float = 1e-6
    edge_band: float | None = None
    face_cell: float | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.cell) and self.cell > 0):
            raise ReducerlabError(f"grid.cell: must be a length > 0; got {self.cell!r}")
        fc = self.face_cell
        if fc is not None and not (isinstance(fc, int | float) and math.isfinite(fc) and fc > 0):
            raise ReducerlabError(f"grid.face_cell: must be a length > 0 or None; got {fc!r}")

    @property
    def cell_v(self) -> float:
        """Fine cell size along the face (m): ``face_cell``, else ``cell``."""
        return self.cell if self.face_cell is None else float(self.face_cell)
        if not (isinstance(self.coarse, int) and 1 <= self.coarse <= 16):
            raise ReducerlabError(f"grid.coarse: must be an integer in 1..16; got {self.coarse!r}")
        if not self.teeth:
            raise ReducerlabError("grid.teeth: needs at least one tooth pair")


#: cells this many times shorter along the profile near a curvature jump of the basic
#: profile (the double arc's transition/convex joint): a pair of teeth out of phase
#: touches in the band between the two flanks' jumps, narrower than a patch
GRADED_FACTOR = 4
#: half-width of the graded band, in cells
GRADED_WINDOW = 2.0
#: growth of the cell length beyond the graded band, per unit length (0.3: each cell at
#: most about 30 % longer than the one before)
GRADED_GROWTH = 0.3


@dataclass(frozen=True)
class _Axis:
    """Fine cell edges of one flank parameter, grouped into coarse cells."""

    edges: Array  # fine cell edges (n+1,)
    coarse_of: NDArray[np.int64]  # coarse cell of each fine cell (n,)
    coarse_edges: Array

    @property
    def centres(self) -> Array:
        return 0.5 * (self.edges[:-1] + self.edges[1:])

    @property
    def coarse_centres(self) -> Array:
        return 0.5 * (self.coarse_edges[:-1] + self.coarse_edges[1:])


def _axis(param: Array, arc: Array, breaks: Sequence[float], cell: float, c: int,
          graded: Sequence[float] = ()) -> _Axis:  # fmt: skip
    """Edges in arc length with ``c`` fine cells per coarse cell, the coarse edges
    landing on the profile's segment breaks (no cell straddles a corner). The cells are
    ``cell`` long, except near the breaks in ``graded`` (curvature jumps): within
    ``GRADED_WINDOW`` cells of one they are ``GRADED_FACTOR`` times shorter, and beyond
    grow back to ``cell`` by at most ``GRADED_GROWTH`` of a cell per cell (an abrupt
    change of the cell size shows in the pressure of a patch across it). A jump within
    the graded band of an end of the axis lies in the flank's edge band: not graded."""
    lo, hi = float(param[0]), float(param[-1])
    inner = np.interp([b for b in breaks if lo < b < hi], param, arc)
    w = GRADED_WINDOW * cell
    ramp = (1.0 - 1.0 / GRADED_FACTOR) * cell / GRADED_GROWTH  # length to grow back
    fine_at = np.interp([b for b in graded if lo < b < hi], param, arc)
    fine_at = fine_at[(fine_at - arc[0] > w + ramp) & (arc[-1] - fine_at > w + ramp)]

    def size(x: Array) -> Array:
        """Target cell length (m) at arc length ``x``."""
        if not fine_at.size:
            return np.full_like(x, cell)
        d = np.min(np.abs(x[:, None] - fine_at[None, :]), axis=1)
        return np.minimum(cell, cell / GRADED_FACTOR + GRADED_GROWTH * np.maximum(d - w, 0.0))

    # breaks closer than half a fine cell to an end or to each other are not cut
    s_cuts = [arc[0]]
    for b in inner:
        if b - s_cuts[-1] > 0.5 * cell and arc[-1] - b > 0.5 * cell:
            s_cuts.append(float(b))
    s_cuts = np.array([*s_cuts, arc[-1]])
    coarse, fine, owner = [s_cuts[0]], [s_cuts[0]], []
    for s0, s1 in itertools.pairwise(s_cuts):
        # fine edges equidistributed in the density 1 / size, a multiple of c of them
        x = np.linspace(s0, s1, 2001)
        dens = 1.0 / size(x)
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (dens[1:] + dens[:-1]) * np.diff(x))])
        n = max(1, round(cum[-1] / c))
        edges = np.interp(np.linspace(0.0, cum[-1], n * c + 1), cum, x)
        edges[0], edges[-1] = s0, s1
        for k in range(n):
            owner += [len(coarse) - 1] * c
            fine += list(edges[k * c + 1 : (k + 1) * c + 1])
            coarse.append(edges[(k + 1) * c])
    to_param = lambda s: np.interp(s, arc, param)  # noqa: E731
    return _Axis(to_param(np.array(fine)), np.array(owner), to_param(np.array(coarse)))


@dataclass(frozen=True)
class PositionContact:
    """The loaded contact at one mesh position (fixed frame of the pair).

    Attributes
    ----------
    phi : float
        Mesh position: gear A's rotation (rad).
    unloaded_te, loaded_te : float
        Rotation of gear B (rad): the unloaded transmission error ``psi_0`` and the
        elastic approach under load (loaded TE = ``psi_0 + loaded_te``).
    torque : float
        ``T_B`` (N m).
    points, normals : ndarray (n, 3)
        Contact grid cells (m) and A's outward normals.
    tooth : ndarray of int (n,)
        Tooth pair of each cell.
    uv : ndarray (n, 2)
        A's flank parameters of the cells.
    area : ndarray (n,)
        Cell areas (m^2).
    separation : ndarray (n,)
        Unloaded separation ``g`` (m).
    force : ndarray (n,)
        Normal force on each cell (N).
    s_max : float
        Largest separation admitted into the grid (m).
    edge : ndarray of bool (n,)
        Cells within ``ContactGrid.edge_band`` of an edge of gear A's flank or opposite
        an edge of gear B's flank: tip, root end of the active flank, toe, heel, or a
        corner of the basic profile (``BasicProfile.corners``: the double arc's
        concave/transition joint).
    lever : ndarray (n,), optional
        Normal approach of each cell per unit rotation of gear B (m/rad).
    """

    phi: float
    unloaded_te: float
    loaded_te: float
    torque: float
    points: Array
    normals: Array
    tooth: NDArray[np.int64]
    uv: Array
    area: Array
    separation: Array
    force: Array
    s_max: float
    edge: NDArray[np.bool_]
    lever: Array | None = None

    @property
    def grid_unloaded_te(self) -> float:
        """Unloaded transmission error of the contact grid's cells (rad):
        ``unloaded_te + min(separation / lever)``, the limit of the loaded TE as the
        load vanishes (``unloaded_te`` is the least over the coarse points too)."""
        if self.lever is None:
            raise ReducerlabError("grid_unloaded_te: the result has no levers")
        return self.unloaded_te + float(np.min(self.separation / self.lever))

    @property
    def interior_peak_pressure(self) -> float:
        """Largest pressure away from the flank edges (Pa): cells outside the edge band
        of either flank (at a square edge the pressure is singular and its computed
        peak grows as the grid is refined); 0 if all load is on edges."""
        p = self.pressure[~self.edge]
        return float(p.max()) if p.size else 0.0

    @property
    def edge_share(self) -> float:
        """Fraction of the load carried by cells on a flank edge (edge contact)."""
        return float(self.force[self.edge].sum() / self.force.sum())

    @property
    def pressure(self) -> Array:
        """Mean pressure on each cell (Pa)."""
        return self.force / self.area

    @property
    def contact_area(self) -> float:
        """Area (m^2) where the pressure field is positive: the boundary of each patch is
        located inside its boundary cells (:func:`loaded_area`), not at whole cells."""
        return loaded_area(self.uv, self.tooth, self.area, self.force)

    @property
    def loaded_cell_area(self) -> float:
        """Area of the loaded cells, whole (m^2): the bound of :attr:`contact_area` from
        above on the grid (a boundary cell counts fully)."""
        return float(self.area[self.force > 0].sum())

    @property
    def force_vector(self) -> Array:
        """Resultant contact force on gear A (N), fixed frame: ``-sum F_i n_i``."""
        return -(self.force[:, None] * self.normals).sum(axis=0)


def _reach(q0: Array, q1: Array, q2: Array) -> Array:
    """How far (in cell spacings, 0..1) beyond the centre of the last loaded cell of a
    grid line the field ``q`` reaches zero, from its values ``q0, q1, q2`` at that cell
    and the next two inward (``nan`` where missing): the zero of the quadratic through
    the three, else of the line through two, else half a cell."""
    c2 = 0.5 * (q0 - 2.0 * q1 + q2)
    c1 = q0 - q1 + c2  # q(s) = q0 + c1 s + c2 s^2 at s = 0, -1, -2 (outward s > 0)
    with np.errstate(all="ignore"):
        disc = c1 * c1 - 4.0 * c2 * q0
        # the smallest positive root of c2 s^2 + c1 s + q0 = 0 (q0 > 0)
        r_plus = (-c1 + np.sqrt(disc)) / (2.0 * c2)
        r_minus = (-c1 - np.sqrt(disc)) / (2.0 * c2)
        roots = np.stack([r_plus, r_minus])
        roots = np.where(np.isfinite(roots) & (roots > 0), roots, np.inf).min(axis=0)
        quad = np.where(np.abs(c2) > 1e-12 * np.abs(q0), roots, q0 / (q1 - q0) * -1.0)
        lin = np.where(q0 < q1, q0 / (q1 - q0), np.inf)
    # a field still rising outward has no zero within reach: the whole next cell
    out = np.where(np.isfinite(q2), quad, np.where(np.isfinite(q1), lin, 0.5))
    return np.clip(np.nan_to_num(out, nan=0.5, posinf=1.0), 0.0, 1.0)


def loaded_area(uv: Array, tooth: NDArray[np.int64], area: Array, force: Array) -> float:
    """Area (m^2) where the pressure field of a contact grid is positive.

    The cells of each tooth pair lie on a tensor grid of flank parameters ``uv``. Along
    every grid line (both directions) each run of loaded cells ends where ``q = p^2``,
    extrapolated from the run's last cells, reaches zero (:func:`_reach`; Hertz:
    ``p^2 = p0^2 (1 - x^2/a^2 - y^2/b^2)`` is a quadratic in position, so polynomial
    extrapolation of ``q`` finds the edge that ``p``, falling like a square root, would
    overshoot), within the boundary cell or the next; a run that ends at the grid's
    edge (the flank's edge) ends with its cell. Each cell contributes its area times the
    fraction of it inside the runs; the area is the mean of the two directions.

    Parameters
    ----------
    uv : ndarray (n, 2)
        Flank parameters of the cell centres (a tensor grid per tooth pair).
    tooth : ndarray of int (n,)
        Tooth pair of each cell.
    area, force : ndarray (n,)
        Cell areas (m^2) and normal forces (N).
    """
    total = 0.0
    loaded_all = force > 0
    for k in np.unique(tooth[loaded_all]):
        m = tooth == k
        _, iu = np.unique(uv[m, 0], return_inverse=True)
        _, iv = np.unique(uv[m, 1], return_inverse=True)
        shape = (int(iu.max()) + 1, int(iv.max()) + 1)
        p = np.zeros(shape)
        a = np.full(shape, np.nan)  # nan: not a cell of the grid
        p[iu, iv] = force[m] / area[m]
        a[iu, iv] = area[m]
        for axis in (0, 1):
            P = np.moveaxis(p, axis, 0)
            A = np.moveaxis(a, axis, 0)
            q = np.where(P > 0, P * P, np.nan)
            frac = np.where(P > 0, 1.0, 0.0)
            n = P.shape[0]
            for step in (1, -1):
                # last loaded cell of a run toward +step: loaded, next one not loaded
                nxt = np.zeros_like(P, dtype=bool)  # next cell exists and is unloaded
                q1 = np.full_like(q, np.nan)
                q2 = np.full_like(q, np.nan)
                if step > 0:
                    nxt[:-1] = np.isfinite(A[1:]) & ~(P[1:] > 0)
                    q1[1:], q2[2:] = q[:-1], q[:-2]
                else:
                    nxt[1:] = np.isfinite(A[:-1]) & ~(P[:-1] > 0)
                    q1[:-1], q2[:-2] = q[1:], q[2:]
                end = (P > 0) & nxt
                r = _reach(q, q1, q2)
                # the end cell's outer half holds min(r, 1/2), the next cell the rest
                frac += np.where(end, np.minimum(r, 0.5) - 0.5, 0.0)
                spill = np.where(end, np.maximum(r - 0.5, 0.0), 0.0)
                if step > 0:
                    frac[1:n] += spill[: n - 1]
                else:
                    frac[: n - 1] += spill[1:n]
            total += 0.5 * float(np.nansum(A * frac))
    return float(total)


def _arc(flank, along_u: bool, fixed: float, n: int = 801) -> tuple[Array, Array]:
    """A parameter axis and the arc length along it on the flank (m)."""
    if along_u:
        p = np.linspace(*flank.u_range, n)
        P, _ = flank.evaluate(p, np.full(n, fixed))
    else:
        p = np.linspace(0.0, 1.0, n)
        P, _ = flank.evaluate(np.full(n, fixed), p)
    return p, np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])


def _edge_distance(flank, ax_u: _Axis, ax_v: _Axis, pu, arc_u, pv, arc_v) -> Array:
    """Distance (m, in arc length on the flank) of each fine cell centre to the edge of
    the real tooth flank: the parameter box or points outside the blank (tip and face
    cones)."""
    from scipy.ndimage import distance_transform_edt

    uu, vv = np.meshgrid(ax_u.centres, ax_v.centres, indexing="ij")
    P, _ = flank.evaluate(uu.ravel(), vv.ravel())
    inside = flank.inside(P).reshape(uu.shape)
    su = np.interp(ax_u.centres, pu, arc_u)
    sv = np.interp(ax_v.centres, pv, arc_v)
    hu = float(np.mean(np.diff(su))) if len(su) > 1 else arc_u[-1]
    hv = float(np.mean(np.diff(sv))) if len(sv) > 1 else arc_v[-1]
    padded = np.pad(inside, 1, constant_values=False)
    # nearest cell off the flank (index metric), its distance in arc length: the cells
    # are graded along the profile near curvature jumps (``_axis``)
    _, (iu, iv) = distance_transform_edt(padded, sampling=(hu, hv), return_indices=True)
    su_p = np.concatenate([[su[0] - hu], su, [su[-1] + hu]])
    sv_p = np.concatenate([[sv[0] - hv], sv, [sv[-1] + hv]])
    iu, iv = iu[1:-1, 1:-1], iv[1:-1, 1:-1]
    d = np.hypot(su[:, None] - su_p[iu], sv[None, :] - sv_p[iv])
    return d - 0.5 * min(hu, hv)  # from the cell centre to the edge, not the next centre


def _corner_distance(ax: _Axis, param: Array, arc: Array, corners: Sequence[float]) -> Array:
    """Distance (m, arc length along the profile at mid-face) of each fine cell centre of
    ``ax`` to the nearest profile corner; ``inf`` without corners. The coarse edges land
    on the corners (``_axis``), so no cell straddles one."""
    s = np.interp(ax.centres, param, arc)
    inner = [c for c in corners if param[0] < c < param[-1]]
    if not inner:
        return np.full(len(s), np.inf)
    sc = np.interp(inner, param, arc)
    return np.min(np.abs(s[:, None] - sc[None, :]), axis=1)


def _cells(flank, u: Array, v: Array, du: Array, dv: Array) -> tuple[Array, ...]:
    """Cell axes, half sides (m) and areas (m^2) from the flank's tangents."""
    h = 1e-6
    P, _ = flank.evaluate(u, v)
    Pu = (flank.evaluate(u + h, v)[0] - P) / h * du[:, None]
    Pv = (flank.evaluate(u, v + h)[0] - P) / h * dv[:, None]
    e1 = Pu / np.linalg.norm(Pu, axis=1)[:, None]
    pv = Pv - np.einsum("ij,ij->i", Pv, e1)[:, None] * e1
    e2 = pv / np.linalg.norm(pv, axis=1)[:, None]
    area = np.linalg.norm(np.cross(Pu, Pv), axis=1)
    hu = 0.5 * np.linalg.norm(Pu, axis=1)
    return e1, e2, hu, area / (4 * hu), area


def flank_size(flank, n: int = 201) -> tuple[float, float]:
    """Arc lengths (m) of a flank along its profile (mid-face) and along its face
    (mid-height)."""
    _, arc_u = _arc(flank, True, 0.5, n)
    _, arc_v = _arc(flank, False, 0.5 * sum(flank.u_range), n)
    return float(arc_u[-1]), float(arc_v[-1])


def grid_estimate(pair: MeshPair, grid: ContactGrid, control: str = CELL_CONTROL) -> Estimate:
    """The fine cells of the contact grid of ``pair`` and the memory of its set-up,
    from the flanks' arc lengths and ``grid.cell`` alone (milliseconds, nothing
    allocated by the cell count): check it before :func:`loaded_contact`.

    Work: fine cells on the larger flank, bounded by :data:`MAX_GRID_CELLS`; memory:
    :data:`GRID_BYTES` per cell, both flanks."""
    cells = []
    prof = getattr(getattr(pair.flank_a, "crown", None), "profile", None)
    lo, hi = pair.flank_a.u_range
    jumps = [b for b in getattr(prof, "breaks", ()) if lo < b < hi]
    jumps = [b for b in jumps if b not in getattr(prof, "corners", ())]
    # rows a graded curvature jump adds (``_axis``): the band's 2 GRADED_WINDOW cells
    # at 1/GRADED_FACTOR, and the ramps back, ln(F)/GROWTH cells where (1 - 1/F)/GROWTH
    # would do, on each side
    F = GRADED_FACTOR
    extra = 2.0 * (GRADED_WINDOW * (F - 1) + (math.log(F) - (1 - 1 / F)) / GRADED_GROWTH)
    for flank in (pair.flank_a, pair.flank_b):
        su, sv = flank_size(flank)
        nu = math.ceil(su / grid.cell) + grid.coarse + math.ceil(extra * len(jumps))
        nv = math.ceil(sv / grid.cell_v) + grid.coarse
        cells.append(float(nu) * float(nv))
    return Estimate(
        f"contact: the grid of {grid.cell * 1e3:.3g} x {grid.cell_v * 1e3:.3g} mm cells "
        "on the flanks",
        GRID_BYTES * sum(cells), max(cells), "fine cells", MAX_GRID_CELLS, control,
    )  # fmt: skip


def candidate_estimate(n: int, phi: float, control: str = CELL_CONTROL) -> Estimate:
    """The compliance matrix among ``n`` candidate cells of one mesh position (dense,
    ``8 n^2`` bytes) and the contact set's block and Cholesky factor (``16 m^2``,
    ``m = min(n, MAX_SET)``); work bounded by :data:`MAX_CANDIDATES`."""
    m = min(n, MAX_SET)
    return Estimate(
        f"contact: the compliance matrix at mesh position {math.degrees(phi):.4g} deg",
        8.0 * n * n + 16.0 * m * m + 400.0 * n, float(n), "candidate cells",
        MAX_CANDIDATES, f"{control} or the load (--power, --torque)",
    )  # fmt: skip


def loaded_contact(
    pair: MeshPair,
    torque: float,
    positions: Array,
    grid: ContactGrid,
    *,
    compliance_a=None,
    compliance_b=None,
    E_star: float,
    progress: Callable[[int, int], None] | None = None,
    torques: Sequence[float] | None = None,
) -> list[PositionContact] | list[list[PositionContact]]:
    """Loaded tooth contact at each mesh position.

    Parameters
    ----------
    pair : MeshPair
    torque : float
        Torque on gear A (N m), > 0; gear B carries ``T_B = torque_ratio * torque``.
    positions : array_like
        Mesh positions (rotations of gear A, rad).
    grid : ContactGrid
    compliance_a, compliance_b : ToothCompliance, optional
        Bending compliance of each gear's teeth (``contact.compliance``); ``None``
        treats that gear's teeth as rigid beyond the half-space (for closed-form checks).
    E_star : float
        Combined modulus ``E*`` of the two bodies (Pa), ``contact.halfspace``.
    progress : callable, optional
        ``progress(done, total)`` after each position.
    torques : sequence of float, optional
        Torques on gear A (N m), each in ``(0, torque]``: a load sweep. At each position
        the separations, the contact grid and the compliance columns are made once, for
        ``torque`` (the largest load), and the complementarity problem is solved for
        each of ``torques`` on them, from the largest down, each warm started from the
        contact set of the one before. Each position's entry of the result is then a
        list of :class:`PositionContact`, one per torque in the order given, equal to
        single-load runs on the same cell to round-off (the grid of the largest load
        holds every cell a smaller load closes: the loaded approach ``psi(T)`` is the
        multiplier of the load constraint of a convex programme, the slope of its convex
        optimal value, so it does not fall as ``T`` rises).
    """
    from .cellmatrix import CellCompliance

    if not (math.isfinite(torque) and torque > 0):
        raise ReducerlabError(f"torque: must be a finite number > 0 (N m); got {torque!r}")
    phis = np.atleast_1d(np.asarray(positions, float))
    if phis.ndim != 1 or not np.all(np.isfinite(phis)):
        raise ReducerlabError("positions: must be a 1-D array of finite angles (rad)")
    if torques is not None:
        sweep = np.atleast_1d(np.asarray(torques, float))
        if sweep.ndim != 1 or sweep.size == 0 or not np.all(np.isfinite(sweep)):
            raise ReducerlabError("torques: must be a non-empty 1-D sequence of torques (N m)")
        if not (np.all(sweep > 0) and np.all(sweep <= torque * (1 + 1e-12))):
            raise ReducerlabError(
                f"torques: each must lie in (0, torque] = (0, {torque:.6g}] N m (the grid is "
                f"made for the largest load); got {sweep.min():.6g} .. {sweep.max():.6g}"
            )
    grid_estimate(pair, grid).check()
    A = pair.flank_a
    pu, arc_u = _arc(A, True, 0.5)
    pv, arc_v = _arc(A, False, 0.5 * sum(A.u_range))
    breaks = list(getattr(getattr(getattr(A, "crown", None), "profile", None), "breaks", ()))
    # a profile corner (tangent discontinuity) is an edge of the flank surface like its
    # boundary; curvature-only breaks are not (``BasicProfile.corners``)
    corners = list(getattr(getattr(getattr(A, "crown", None), "profile", None), "corners", ()))
    graded = [b for b in breaks if b not in corners]
    ax_u = _axis(pu, arc_u, breaks, grid.cell, grid.coarse, graded)
    ax_v = _axis(pv, arc_v, (), grid.cell_v, grid.coarse)
    T_B = torque * pair.torque_ratio
    # fine cell geometry is the same for every tooth (tooth k = tooth 0 turned)
    fu, fv = np.meshgrid(ax_u.centres, ax_v.centres, indexing="ij")
    dfu, dfv = np.meshgrid(np.diff(ax_u.edges), np.diff(ax_v.edges), indexing="ij")
    cu, cv = np.meshgrid(ax_u.coarse_centres, ax_v.coarse_centres, indexing="ij")
    band = grid.edge_band if grid.edge_band is not None else 2.0 * max(grid.cell, grid.cell_v)
    B = pair.flank_b
    dist_a = np.minimum(_edge_distance(A, ax_u, ax_v, pu, arc_u, pv, arc_v),
                        _corner_distance(ax_u, pu, arc_u, corners)[:, None])  # fmt: skip
    edge_a = (dist_a < band).ravel()
    pub, arc_ub = _arc(B, True, 0.5)
    pvb, arc_vb = _arc(B, False, 0.5 * sum(B.u_range))
    bu = _axis(pub, arc_ub, breaks, grid.cell, 1, graded)
    bv = _axis(pvb, arc_vb, (), grid.cell_v, 1)
    dist_b = np.minimum(_edge_distance(B, bu, bv, pub, arc_ub, pvb, arc_vb),
                        _corner_distance(bu, pub, arc_ub, corners)[:, None])  # fmt: skip
    edge_b = RegularGridInterpolator(
        (bu.centres, bv.centres), dist_b, bounds_error=False, fill_value=0.0,
    )  # fmt: skip
    n_cu, n_cv = cu.shape
    fine_coarse = (ax_u.coarse_of[:, None] * n_cv + ax_v.coarse_of[None, :]).ravel()
    geo = _cells(A, fu.ravel(), fv.ravel(), dfu.ravel(), dfv.ravel())
    sign = 0.0
    s_max = grid.s_max
    prev: set[tuple[int, int]] = set()
    out: list[PositionContact] = []
    for j, phi in enumerate(phis):
        coarse = {k: separations(pair, phi, k, cu.ravel(), cv.ravel()) for k in grid.teeth}
        if sign == 0.0:
            lam_all = np.concatenate([s.lever[np.isfinite(s.distance)] for s in coarse.values()])
            if lam_all.size == 0:
                raise ContactError(
                    f"no contact: at mesh position {math.degrees(phi):.4g} deg no point of "
                    "gear A's flank finds gear B's flank (surfaces apart, or wrong flank)"
                )
            sign = 1.0 if np.median(lam_all) > 0 else -1.0
        psi0 = _first_contact(coarse, sign)
        fine_cache: dict[int, object] = {}
        while True:
            sel = _select(pair, phi, coarse, sign, psi0, s_max, fine_cache, fu, fv,
                          fine_coarse, (n_cu, n_cv), grid.teeth)  # fmt: skip
            if sel is None:  # the coarse cells all lie beyond s_max of the first contact
                if s_max > S_MAX_LIMIT:
                    raise ContactError(
                        "no contact: the flanks never come within reach of each other"
                    )
                s_max *= 2.0
                continue
            psi0 = min(psi0, sel["psi0"])
            g = sel["t"] - sel["lam"] * psi0
            keep = g <= s_max
            if not np.any(keep):
                raise ContactError(
                    f"no contact: nothing within {s_max * 1e6:.3g} um at mesh position "
                    f"{math.degrees(phi):.4g} deg"
                )
            idx = sel["fine"][keep]
            teeth = sel["tooth"][keep]
            lam = sel["lam"][keep]
            P, N = sel["P"][keep], sel["N"][keep]
            e1, e2, hu, hv, area = (a[idx] for a in geo)
            # axes of the tooth-k cells are the tooth-0 axes placed like the points
            e1, e2 = sel["rot"](e1, teeth), sel["rot"](e2, teeth)
            uv_b = sel["uv_b"][keep]
            bending = [
                (comp, teeth, uv[0], uv[1])
                for comp, uv in ((compliance_a, (fu.ravel()[idx], fv.ravel()[idx])),
                                 (compliance_b, (uv_b[:, 0], uv_b[:, 1])))
                if comp is not None
            ]  # fmt: skip
            candidate_estimate(len(P), float(phi)).check()
            C = CellCompliance(P, e1, e2, hu, hv, E_star, teeth, bending)
            keys = list(zip(teeth.tolist(), idx.tolist(), strict=True))
            start = np.array([k in prev for k in keys])
            sol = solve_contact(C, g[keep], lam, T_B, start=start if start.any() else None)
            approach = sol.approach
            prev = {k for k, a in zip(keys, sol.active, strict=True) if a}  # next start
            # completeness: points left out must stay open under the rigid approach
            left = sel["left_gap"] - sel["left_lam"] * (psi0 + approach)
            out_g = g[~keep] - sel["lam"][~keep] * approach
            worst = min(left.min(initial=np.inf), out_g.min(initial=np.inf))
            if worst > 0:
                break
            if s_max > S_MAX_LIMIT:
                raise ContactError(
                    f"contact: at mesh position {math.degrees(phi):.4g} deg the load closes "
                    f"gaps wider than {S_MAX_LIMIT * 1e3:.3g} mm (elastic approach "
                    f"{float(np.max(lam * approach)) * 1e3:.3g} mm): far beyond what the "
                    "teeth carry elastically; lower the load (--power, --torque)"
                )
            s_max *= 2.0
        edge = edge_a[idx] | (edge_b(sel["uv_b"][keep]) < band)
        solved = [(sol, T_B)]
        if torques is not None:  # the load sweep on this grid, largest first, warm started
            by_torque, active = {}, sol.active
            for t in sorted(set(sweep.tolist()), reverse=True):
                s_t = sol if t >= torque else solve_contact(
                    C, g[keep], lam, t * pair.torque_ratio, start=active
                )  # fmt: skip
                by_torque[t], active = s_t, s_t.active
            solved = [(by_torque[t], t * pair.torque_ratio) for t in sweep.tolist()]
        cases = [
            PositionContact(
                float(phi), float(psi0), float(s_t.approach), t_b, P, N, teeth,
                np.stack([fu.ravel()[idx], fv.ravel()[idx]], 1), area, g[keep], s_t.force,
                s_max, edge, lam,
            )
            for s_t, t_b in solved
        ]  # fmt: skip
        out.append(cases[0] if torques is None else cases)
        # next position: a grid just large enough for this one's approach, with a margin
        # (the completeness check grows it again where the next position needs more)
        s_max = max(grid.s_max, MARGIN * float(np.max(lam * approach)))
        if progress is not None:
            progress(j + 1, len(phis))
    return out


def _dip(g: Array) -> Array:
    """Bound (m) on how far the gap inside each coarse cell falls below its value ``g``
    at the centre, from the neighbouring centres: over half a cell a quadratic model
    falls by at most ``|g'| h/2 + |g''| h^2/8`` per direction, with the first
    difference (steepest side) and the second difference standing for ``g' h`` and
    ``g'' h^2``. Neighbours off the flank (``inf``) give no information (0)."""
    drop = np.zeros_like(g)
    for axis in (0, 1):
        gm = np.moveaxis(g, axis, 0)
        lo = np.full_like(gm, np.nan)
        hi = np.full_like(gm, np.nan)
        lo[1:] = gm[:-1]
        hi[:-1] = gm[1:]
        with np.errstate(invalid="ignore"):
            d_lo = np.abs(gm - lo)
            d_hi = np.abs(hi - gm)
            d2 = np.abs(hi - 2.0 * gm + lo)
        first = np.fmax(np.where(np.isfinite(d_lo), d_lo, np.nan),
                        np.where(np.isfinite(d_hi), d_hi, np.nan))  # fmt: skip
        second = np.where(np.isfinite(d2), d2, np.nan)
        part = 0.5 * np.nan_to_num(first, nan=0.0) + 0.125 * np.nan_to_num(second, nan=0.0)
        drop += np.moveaxis(part, 0, axis)
    return np.where(np.isfinite(g), drop, 0.0)


def _first_contact(coarse: dict, sign: float) -> float:
    psi = np.inf
    for s in coarse.values():
        lam = sign * s.lever
        ok = np.isfinite(s.distance) & (lam > 0)
        if np.any(ok):
            psi = min(psi, float(np.min(s.distance[ok] / lam[ok])))
    if not np.isfinite(psi):
        raise ContactError("no contact: no point of the flanks can close under the load")
    return psi


def _select(pair, phi, coarse, sign, psi0, s_max, cache, fu, fv, fine_coarse, cshape, teeth):
    """Fine cells (exact separations) inside the coarse cells that may close, with
    their neighbours; and the coarse points left out, for the completeness check."""
    n_cu, n_cv = cshape
    Ps, Ns, ts, lams, uvb, fines, tooth_of = [], [], [], [], [], [], []
    left_gap, left_lam = [], []
    psi_min = np.inf
    for k in teeth:
        s = coarse[k]
        lam = sign * s.lever
        ok = np.isfinite(s.distance) & (lam > 0)
        g = np.where(ok, s.distance - lam * psi0, np.inf).reshape(n_cu, n_cv)
        # the gap can be lower inside a coarse cell than at its centre (a contact band
        # thinner than a coarse cell may lie between centres): bound it from below
        drop = _dip(g)
        near = g - drop <= s_max
        # and dilate by one coarse cell, diagonals included
        grown = near.copy()
        grown[1:] |= near[:-1]
        grown[:-1] |= near[1:]
        row = grown.copy()
        grown[:, 1:] |= row[:, :-1]
        grown[:, :-1] |= row[:, 1:]
        left = ~grown.ravel() & ok
        left_gap.append(s.distance[left] - drop.ravel()[left])
        left_lam.append(lam[left])
        cells = np.flatnonzero(grown.ravel()[fine_coarse])
        if cells.size == 0:
            continue
        key = (k, cells.tobytes())
        if key not in cache:
            cache[key] = separations(pair, phi, k, fu.ravel()[cells], fv.ravel()[cells])
        f = cache[key]
        flam = sign * f.lever
        fok = np.isfinite(f.distance) & (flam > 0)
        if np.any(fok):
            psi_min = min(psi_min, float(np.min(f.distance[fok] / flam[fok])))
        Ps.append(f.points[fok])
        Ns.append(f.normals[fok])
        ts.append(f.distance[fok])
        lams.append(flam[fok])
        uvb.append(f.uv_b[fok])
        fines.append(cells[fok])
        tooth_of.append(np.full(int(fok.sum()), k))
    if not ts:
        return None
    pa, _ = pair.poses(phi)
    R0 = pa.rotation

    def rot(vec: Array, tooth: NDArray[np.int64]) -> Array:
        out = np.empty_like(vec)
        for k in np.unique(tooth):
            a = pair.tooth_angles(int(k))[0]
            c, s_ = math.cos(a), math.sin(a)
            Rz = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]])
            m = tooth == k
            out[m] = vec[m] @ (R0 @ Rz).T
        return out

    return {
        "P": np.concatenate(Ps), "N": np.concatenate(Ns), "t": np.concatenate(ts),
        "lam": np.concatenate(lams), "uv_b": np.concatenate(uvb),
        "fine": np.concatenate(fines), "tooth": np.concatenate(tooth_of),
        "psi0": psi_min, "rot": rot,
        "left_gap": np.concatenate(left_gap), "left_lam": np.concatenate(left_lam),
    }  # fmt: skip


@dataclass(frozen=True)
class PatchWidth:
    """Hertz estimate of one loaded contact patch (one tooth pair at one position).

    Attributes
    ----------
    tooth : int
        Tooth pair.
    force : float
        Normal force the pair carries (N).
    length : float
        Length of the patch along its long axis (m).
    radius : float
        Relative radius of curvature across the patch ``R`` (m), from the gap.
    half_width : float
        Hertz line-contact half-width ``b = sqrt(4 w R / (pi E*))`` at the mean line
        load ``w = force / length`` (m) (Johnson 1985 §4.3).
    p0 : float
        Its peak pressure ``2 w / (pi b)`` (Pa).
    across : tuple of float
        Components of the unit minor axis (across the patch) along gear A's profile and
        face directions at the patch, absolute values.
    centre : tuple of float
        Gear A's flank parameters ``(u, v)`` of the patch's load centre.
    """

    tooth: int
    force: float
    length: float
    radius: float
    half_width: float
    p0: float
    across: tuple[float, float]
    centre: tuple[float, float] = (math.nan, math.nan)


#: half-span of the stencil on which ``patch_widths`` fits the gap, m (and its steps):
#: well inside an involute's radius of curvature near the root (several mm), wider
#: than Newton's tolerance of the separations (1e-11 m) over its quadratic (1e-9 m)
STENCIL = 0.2e-3


def patch_widths(pair: MeshPair, run: PositionContact, E_star: float) -> list[PatchWidth]:
    """Hertz minor half-width of every loaded patch of a (coarse) contact run.

    The width of a patch narrower than the run's cells cannot be read off its loaded
    cells; the Hertz half-width follows from what a coarse grid does resolve: the force
    the tooth pair carries, the patch's length along its long axis (its loaded cells'
    extent plus a cell), and the relative curvature across it. The exact gap
    (``contact.flanks.separations``, less the lever times the unloaded TE) on a 5 x 5
    stencil of ``+-STENCIL`` around the patch's load centre is fitted by a quadratic in
    the tangent plane (``g = c + d.x + x.H.x / 2``); ``1/R`` is the larger eigenvalue of
    ``H`` (the gap of two bodies is ``x^2 / (2 R)`` across the contact, Johnson 1985
    §4.1). Then ``b = sqrt(4 w R / (pi E*))`` at the mean line load ``w = F / L``
    (Johnson 1985 §4.3). For an elliptical patch of major axis ``L`` the line load at
    its centre is ``3 F / (2 L)``: the mean underrates ``b`` by up to ``sqrt(2/3)``, on
    the side of finer cells.

    Parameters
    ----------
    pair : MeshPair
        The pair the run was computed for.
    run : PositionContact
    E_star : float
        Combined modulus ``E*`` (Pa).

    Returns
    -------
    list of PatchWidth
        One per tooth pair carrying load whose gap has a positive curvature across it.
    """
    if not (math.isfinite(E_star) and E_star > 0):
        raise ReducerlabError(f"E_star: must be a modulus > 0 (Pa); got {E_star!r}")
    out = []
    loaded = run.force > 0
    for k in np.unique(run.tooth[loaded]):
        m = (run.tooth == k) & loaded
        F = float(run.force[m].sum())
        wt = run.force[m] / F
        c = wt @ run.points[m]
        n = wt @ run.normals[m]
        n /= np.linalg.norm(n)
        h = math.sqrt(float(np.median(run.area[m])))
        d = run.points[m] - c
        d -= (d @ n)[:, None] * n  # into the tangent plane
        if len(d) > 1 and np.ptp(d, axis=0).max() > 0:
            e1 = np.linalg.svd(d - d.mean(axis=0), full_matrices=False)[2][0]
            length = float(np.ptp(d @ e1)) + h
        else:
            length = h
        # the stencil in flank parameters: steps of STENCIL / 2 in arc length
        uv0 = wt @ run.uv[m]
        fa = pair.flank_a
        du, dv = 1e-4 * (fa.u_range[1] - fa.u_range[0]), 1e-4
        P0, _ = fa.evaluate(np.array([uv0[0], uv0[0] + du, uv0[0]]),
                            np.array([uv0[1], uv0[1], uv0[1] + dv]))  # fmt: skip
        su = 0.5 * STENCIL * du / float(np.linalg.norm(P0[1] - P0[0]))
        sv = 0.5 * STENCIL * dv / float(np.linalg.norm(P0[2] - P0[0]))
        iu, iv = np.meshgrid(np.arange(-2, 3), np.arange(-2, 3), indexing="ij")
        u = np.clip(uv0[0] + su * iu.ravel(), *fa.u_range)
        v = np.clip(uv0[1] + sv * iv.ravel(), 0.0, 1.0)
        s = separations(pair, run.phi, int(k), u, v)
        ok = np.isfinite(s.distance)
        if ok.sum() < 6:
            continue
        g = s.distance[ok] - s.lever[ok] * run.unloaded_te
        x3 = s.points[ok] - c
        x3 -= (x3 @ n)[:, None] * n
        t1 = x3[np.argmax(np.linalg.norm(x3, axis=1))]
        t1 = t1 / np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        X, Y = x3 @ t1, x3 @ t2
        M = np.column_stack([np.ones_like(X), X, Y, 0.5 * X * X, X * Y, 0.5 * Y * Y])
        coef = np.linalg.lstsq(M, g, rcond=None)[0]
        lam, vec = np.linalg.eigh([[coef[3], coef[4]], [coef[4], coef[5]]])
        if not lam[-1] > 0:
            continue
        minor = vec[0, -1] * t1 + vec[1, -1] * t2
        # the flank's profile and face directions at the patch, from the stencil's rows
        dirs = []
        for step, fixed in ((iu.ravel(), iv.ravel()), (iv.ravel(), iu.ravel())):
            row = np.flatnonzero(ok & (fixed == 0))
            if row.size < 2:  # unknown: as if the minor axis ran this way (finer cells)
                dirs.append(1.0)
                continue
            i0, i1 = row[np.argmin(step[row])], row[np.argmax(step[row])]
            t = s.points[i1] - s.points[i0]
            dirs.append(abs(float(minor @ t)) / max(float(np.linalg.norm(t)), 1e-300))
        R = 1.0 / float(lam[-1])
        w = F / length
        b = math.sqrt(4.0 * w * R / (math.pi * E_star))
        out.append(PatchWidth(int(k), F, length, R, b, 2.0 * w / (math.pi * b),
                              (dirs[0], dirs[1]), (float(uv0[0]), float(uv0[1]))))  # fmt: skip
    return out


#: cells across the Hertz half-width of the narrowest patch of the cycle (``auto_grid``):
#: a cell's mean of ``p0 sqrt(1 - x^2/b^2)`` falls short of ``p0`` by up to ``h^2 /
#: (6 b^2)`` (a cell with the peak at its edge; ``h^2 / (24 b^2)`` centred), so halving
#: ``h = b/3`` moves the peak by at most ``3/4`` of ``1/54``: 1.4 %, under issue 29's 2 %
HALF_WIDTH_CELLS = 3.0
#: cells along the shortest sized patch's long axis (``auto_grid``)
ALONG = 40.0
#: patches whose Hertz peak reaches this share of their position's highest are sized
#: (a lighter one, entering or leaving mesh, cannot carry the position's peak pressure)
RESOLVE = 0.5


def auto_grid(
    pair: MeshPair, runs: Sequence[PositionContact], E_star: float, start: float,
    bounds: tuple[float, float], max_cells: int | None = None,
) -> tuple[float, float]:  # fmt: skip
    """Fine cell sizes (m) along the profile and along the face, from coarse pilot runs
    at the analysed positions.

    At every position each loaded patch whose Hertz peak reaches ``RESOLVE`` of that
    position's highest is sized (:func:`patch_widths`: half-width ``b`` from the gap's
    curvature, the pair's force and the patch length ``L``; a pilot cell of ``0.1 m_n``
    cannot measure a patch 0.1 mm wide, the curvature it can). Over those patches the
    profile cell is the least of ``b / (HALF_WIDTH_CELLS c_u)`` and ``L / ALONG``, the
    face cell the least of ``b / (HALF_WIDTH_CELLS c_v)`` and ``L / ALONG`` (``c_u,
    c_v``: the minor axis's components along the profile and the face), each within
    ``bounds``. A patch within the graded band of a curvature jump of the profile (its
    centre within ``GRADED_WINDOW`` of the jump's cells plus a half-width) has cells
    ``GRADED_FACTOR`` times shorter there already (``_axis``): its profile cell is
    sized ``GRADED_FACTOR`` times longer. A contact line along the face so gets cells
    narrow across the profile and long along the face: the narrowest patch of the
    cycle (a spur pair's two-pair zone, near a root) has ``HALF_WIDTH_CELLS`` cells
    across its half-width (unless a bound stops it) at the cost of a line.

    Parameters
    ----------
    pair : MeshPair
    runs : sequence of PositionContact
        The pilot runs (one per analysed position).
    E_star : float
        Combined modulus (Pa).
    start : float
        Cell size (m) with no patch to size (the pilot's).
    bounds : tuple of float
        Least and largest cell (m).
    max_cells : int, optional
        Loaded cells at most at any position (its contact area, :func:`loaded_area`,
        over a cell's area): beyond, both cells grow by the square root of the excess,
        and the cells per half-width fall below ``HALF_WIDTH_CELLS`` (a wide conformal
        patch, the double arc's, beside a narrow one).
    """
    lo, hi = bounds
    if not (0 < lo <= hi and math.isfinite(hi)):
        raise ReducerlabError(f"bounds: must be lengths 0 < lo <= hi (m); got {bounds!r}")
    A = pair.flank_a
    prof = getattr(getattr(A, "crown", None), "profile", None)
    u_lo, u_hi = A.u_range
    jumps = [b for b in getattr(prof, "breaks", ()) if u_lo < b < u_hi]
    jumps = [b for b in jumps if b not in getattr(prof, "corners", ())]
    h_u = h_v = float(start)
    for r in runs:
        ps = patch_widths(pair, r, E_star)
        top = max((p.p0 for p in ps), default=0.0)
        for p in ps:
            if p.p0 < RESOLVE * top:
                continue
            along = p.length / ALONG
            c_u, c_v = p.across
            need = p.half_width / (HALF_WIDTH_CELLS * max(c_u, 1e-9))
            if jumps:  # a patch at a curvature jump lies in its graded band (``_axis``)
                u0, v0 = p.centre
                P, _ = A.evaluate(np.array([u0, *jumps]), np.full(len(jumps) + 1, v0))
                gap = float(np.min(np.linalg.norm(P[1:] - P[0], axis=1)))
                if gap <= GRADED_WINDOW * GRADED_FACTOR * need + p.half_width:
                    need *= GRADED_FACTOR
            h_u = min(h_u, along, need)
            h_v = min(h_v, along, p.half_width / (HALF_WIDTH_CELLS * max(c_v, 1e-9)))
    h_u, h_v = float(np.clip(h_u, lo, hi)), float(np.clip(h_v, lo, hi))
    if max_cells is not None and runs:
        n = max(r.contact_area for r in runs) / (h_u * h_v)
        if n > max_cells:
            f = math.sqrt(n / max_cells)
            h_u, h_v = min(f * h_u, hi), min(f * h_v, hi)
    return h_u, h_v
