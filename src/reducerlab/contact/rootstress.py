"""Tooth-root stress from the finite-element tooth models under the contact load.

The tooth compliance (:mod:`reducerlab.contact.compliance`) loads ``n_u x n_v`` unit
normal "bumps" on the flank of each modelled tooth and factorises the stiffness matrix
once. Asked for (``root_stress=True``), the same build also solves the displacements of
every bump (the backward substitution of the same Cholesky factor) and recovers their
stresses at the nodes of the root fillets (:func:`reducerlab.fe.stress.surface_stress_operator`,
averaged nodal stress): ``S[j, :, l]``, the stress tensor (Voigt, Pa) at fillet node
``j`` under unit bump ``l`` (N). A :class:`FilletInfluence` holds them.

The root stress under any flank load is then linear in the bump amplitudes: the contact
analysis carries the normal force ``f_i`` of each contact cell at flank parameters
``(u_i, v_i)`` of tooth pair ``k_i``, and the compliance interpolates a cell from the
load points with the bilinear stencil ``ToothCompliance.stencil`` (columns ``c_i4``,
weights ``w_i4``); the same stencil spreads the cell force onto the bumps,
``a_l = sum_i sum_{c_i4 = l} w_i4 f_i`` (the load that is work-conjugate to the
interpolated compliance), and ``sigma_j = sum_l S[j, :, l] a_l``. The largest principal
stress on the loaded flank's fillet is the tooth-root (tensile) stress; the most
negative principal stress on the opposite fillet the compressive side.

Sides: the loaded flank's fillet (side +1) is the tension side of a tooth in bending,
the other fillet (side -1) the compression side.

Face ends: the flank loads are bumps of radius ``a`` (``ToothCompliance.radius``, two
tooth elements) on a grid inset by ``a`` from the flank's edges; a load nearer a face
end than that is extrapolated from the grid (the same stencil as the compliance), so
that its force and moment are right but not its local spread, and the fillet meets the
end face in an edge. The fillet stress there need not converge: on the nutation
drive's internal gear (pair 1 of ``examples/nutation_surface.toml``, a line load over
the face, its former root without a fillet) the fillet maximum within 2 mm (one module)
of the end faces rose by 27-53 % from tooth elements of 0.3 to 0.25 m_n, while beyond it
the face slices of those two meshes agreed to 10 % (docs/contact.md).
:func:`tooth_root_stress` takes the tensile and compressive root stresses from the
fillet nodes at least ``FilletInfluence.end_margin`` (one normal module) from the end
faces (``FilletInfluence.end_distance``) and reports the largest principal stress of the
end zones apart (``ToothRootStress.end_tensile``: not a converged root stress, for
information).

Units: SI (m, N, Pa, rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..fe.stress import principal_stresses

__all__ = [
    "FilletInfluence",
    "PairRootStress",
    "ToothRootStress",
    "bump_amplitudes",
    "contact_root_stress",
    "line_load_root_stress",
    "tooth_root_stress",
    "von_mises",
]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class FilletInfluence:
    """Stress influence coefficients of the flank load bumps at the root-fillet nodes.

    Attributes
    ----------
    points : ndarray (n, 3)
        Fillet nodes (m), gear frame of the tooth model.
    normals : ndarray (n, 3)
        Outward surface normals there.
    tooth : ndarray of int (n,)
        Tooth block of the compliance (``ToothCompliance.teeth``) each node belongs to.
    side : ndarray of int (n,)
        +1: fillet of the loaded flank (tension side); -1: the opposite fillet.
    radius : ndarray (n,)
        Distance from the gear axis (m).
    face : ndarray (n,)
        Position across the face from the mid-face (m; spur gear: ``z``).
    angle : ndarray (n,)
        Angle between the fillet's tangent in the transverse section and the tooth
        centre line (rad): 0 along the flank, ``pi/2`` at the root circle; ISO 6336-3's
        critical section is where it is 30 deg.
    matrix : ndarray (n, 6, T L)
        Stress (Voigt order ``xx, yy, zz, yz, xz, xy``, Pa) at each node per unit bump
        (N): Pa/N, bumps in the compliance's column order.
    end_distance : ndarray (n,), optional
        Distance from the nearer end face along the face (m); None: not known (every
        node counts as inside the face).
    end_margin : float
        Nodes nearer an end face than this (m; the builders: one normal module) are the
        face-end zones (module docstring).
    """

    points: Array
    normals: Array
    tooth: NDArray[np.int64]
    side: NDArray[np.int64]
    radius: Array
    face: Array
    angle: Array
    matrix: Array
    end_distance: Array | None = None
    end_margin: float = 0.0

    def stress(self, amplitudes: Array) -> Array:
        """Stress (n, 6) (Pa) at the fillet nodes under bump amplitudes (T L,) (N)."""
        a = np.asarray(amplitudes, dtype=float)
        if a.shape != (self.matrix.shape[2],):
            raise ReducerlabError(
                f"amplitudes: need {self.matrix.shape[2]} bump amplitudes; got shape {a.shape}"
            )
        return self.matrix @ a

    def reversed_teeth(self, teeth: tuple[int, ...], block: int) -> FilletInfluence:
        """The influence with tooth block ``k`` taken from block ``-k`` (the wheel of a
        pair of two equal gears): ``teeth`` the blocks (symmetric about 0), ``block``
        bumps per tooth."""
        order = np.concatenate([np.arange(block) + teeth.index(-k) * block for k in teeth])
        return FilletInfluence(self.points, self.normals, -self.tooth, self.side, self.radius,
                               self.face, self.angle, self.matrix[:, :, order],
                               self.end_distance, self.end_margin)  # fmt: skip

    @property
    def memory(self) -> int:
        """Bytes held by the influence coefficients."""
        return int(self.matrix.nbytes)


@dataclass(frozen=True)
class ToothRootStress:
    """Root stresses of one gear's modelled teeth under one flank load.

    Attributes
    ----------
    teeth : tuple of int
        Tooth blocks (tooth pairs of the contact analysis).
    tensile : ndarray (T,)
        Largest principal stress on the loaded flank's fillet of each tooth (Pa); NaN
        (and NaN locations) for a fillet the tooth model does not hold.
    tensile_radius, tensile_face, tensile_angle : ndarray (T,)
        Where: radius from the axis (m), position across the face from mid-face (m),
        fillet tangent angle to the tooth centre line (rad, :class:`FilletInfluence`).
    compressive : ndarray (T,)
        Most negative principal stress on the opposite fillet (Pa, < 0 in compression).
    compressive_radius, compressive_face, compressive_angle : ndarray (T,)
        Where, as for the tensile side.
    von_mises : ndarray (T,)
        Largest von Mises stress on either fillet of the tooth (Pa).
    end_tensile : ndarray (T,)
        Largest principal stress on the loaded flank's fillet within
        ``FilletInfluence.end_margin`` of the end faces (Pa; module docstring: not
        converged, excluded from the others; NaN where the fillet has no such nodes).
    """

    teeth: tuple[int, ...]
    tensile: Array
    tensile_radius: Array
    tensile_face: Array
    tensile_angle: Array
    compressive: Array
    compressive_radius: Array
    compressive_face: Array
    compressive_angle: Array
    von_mises: Array
    end_tensile: Array


def von_mises(sigma: Array) -> Array:
    """Von Mises stress (Pa) of Voigt stress vectors (..., 6) (``fe.stress.VOIGT``):
    ``sqrt(((s1 - s2)^2 + (s2 - s3)^2 + (s3 - s1)^2) / 2 + 3 (t23^2 + t13^2 + t12^2))``."""
    s = np.asarray(sigma, dtype=float)
    d = (s[..., 0] - s[..., 1]) ** 2 + (s[..., 1] - s[..., 2]) ** 2 + (s[..., 2] - s[..., 0]) ** 2
    return np.sqrt(0.5 * d + 3.0 * np.sum(s[..., 3:] ** 2, axis=-1))


def bump_amplitudes(compliance, tooth: Array, u: Array, v: Array, force: Array) -> Array:
    """Bump amplitudes (T L,) (N) of point forces ``force`` (N, along the flank's inward
    normal) at flank parameters ``(u, v)`` of tooth blocks ``tooth``: each force spread
    on the load points with the compliance's interpolation stencil (module docstring).
    """
    f = np.asarray(force, dtype=float).ravel()
    if not np.all(np.isfinite(f)):
        raise ReducerlabError("force: must be finite (N)")
    cols, w = compliance.stencil(np.asarray(tooth, int).ravel(), np.asarray(u, float).ravel(),
                                 np.asarray(v, float).ravel())  # fmt: skip
    if cols.shape[0] != f.size:
        raise ReducerlabError(f"force: need one force per point ({cols.shape[0]}); got {f.size}")
    a = np.zeros(compliance.matrix.shape[0])
    np.add.at(a, cols.ravel(), (w * f[:, None]).ravel())
    return a


def _influence(compliance) -> FilletInfluence:
    inf = getattr(compliance, "fillet", None)
    if inf is None:
        raise ReducerlabError(
            "root stress: the tooth compliance was built without its root-stress "
            "influence; build it with root_stress=True"
        )
    return inf


def tooth_root_stress(
    compliance, tooth: Array, u: Array, v: Array, force: Array
) -> ToothRootStress:
    """Root stresses of a gear's modelled teeth under point forces on its flanks.

    Parameters
    ----------
    compliance : ToothCompliance
        Built with ``root_stress=True`` (its :class:`FilletInfluence`).
    tooth : array of int (n,)
        Tooth block of each force (among ``compliance.teeth``).
    u, v : ndarray (n,)
        Flank parameters of the forces (the compliance's flank).
    force : ndarray (n,)
        Normal forces pressing on the flank (N).

    Returns
    -------
    ToothRootStress
        The fillet nodes within ``end_margin`` of the end faces excluded from all but
        ``end_tensile`` (module docstring).
    """
    inf = _influence(compliance)
    sigma = inf.stress(bump_amplitudes(compliance, tooth, u, v, force))
    p = principal_stresses(sigma)  # (n, 3) ascending
    vm = von_mises(sigma)
    teeth = tuple(int(k) for k in compliance.teeth)
    inner = np.ones(len(p), dtype=bool)
    if inf.end_distance is not None:
        inner = inf.end_distance >= inf.end_margin
    out: dict[str, list[float]] = {k: [] for k in ("t", "tr", "tf", "ta", "c", "cr", "cf", "ca")}
    out["vm"], out["e"] = [], []
    for k in teeth:
        out["vm"].append(float(vm[(inf.tooth == k) & inner].max(initial=0.0)))
        ends = (inf.tooth == k) & (inf.side == 1) & ~inner
        out["e"].append(float(p[ends, 2].max()) if ends.any() else math.nan)
        for side, key, val in ((1, "t", p[:, 2]), (-1, "c", p[:, 0])):
            idx = np.flatnonzero((inf.tooth == k) & (inf.side == side) & inner)
            if idx.size == 0:  # a fillet outside the model (cut by a sector's end wall)
                for suffix in ("", "r", "f", "a"):
                    out[key + suffix].append(math.nan)
                continue
            j = idx[np.argmax(val[idx])] if side == 1 else idx[np.argmin(val[idx])]
            out[key].append(float(val[j]))
            out[key + "r"].append(float(inf.radius[j]))
            out[key + "f"].append(float(inf.face[j]))
            out[key + "a"].append(float(inf.angle[j]))
    a = {k: np.array(v) for k, v in out.items()}
    return ToothRootStress(teeth, a["t"], a["tr"], a["tf"], a["ta"], a["c"], a["cr"], a["cf"],
                           a["ca"], a["vm"], a["e"])  # fmt: skip


def line_load_root_stress(
    compliance, tooth: int, u: float, force: float, points: int = 81
) -> ToothRootStress:
    """Root stresses under a uniform line load across the whole face at profile
    parameter ``u`` of one tooth (total normal force ``force``, N): ``points`` equal
    forces at the midpoints of equal face intervals (``v`` in ``(0, 1)``). The load of
    ISO 6336-3's nominal tooth-root stress at one point of the profile."""
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise ReducerlabError(f"points: must be an integer >= 2; got {points!r}")
    if not (math.isfinite(force) and force > 0):
        raise ReducerlabError(f"force: must be a finite force > 0 (N); got {force!r}")
    v = (np.arange(points) + 0.5) / points
    return tooth_root_stress(compliance, np.full(points, int(tooth)), np.full(points, float(u)), v,
                             np.full(points, force / points))  # fmt: skip


@dataclass(frozen=True)
class PairRootStress:
    """Root stresses of both gears of a pair at each mesh position of a contact run.

    Arrays are (gear, position, tooth): gear 0 is A (pinion), 1 is B; tooth ``k`` is
    tooth pair ``k`` of the contact analysis (A's tooth ``k`` and the B tooth it meets).
    Quantities as :class:`ToothRootStress` (Pa, m, rad).
    """

    teeth: tuple[int, ...]
    positions: Array
    tensile: Array
    tensile_radius: Array
    tensile_face: Array
    tensile_angle: Array
    compressive: Array
    compressive_radius: Array
    compressive_face: Array
    compressive_angle: Array
    von_mises: Array
    end_tensile: Array

    def peak(self) -> dict[str, float | int]:
        """The largest tensile root stress of the run and where: ``gear`` (0 A, 1 B),
        ``position`` index, ``tooth``, ``stress`` (Pa), ``radius``, ``face`` (m),
        ``angle`` (rad)."""
        g, p, t = np.unravel_index(int(np.nanargmax(self.tensile)), self.tensile.shape)
        return {
            "gear": int(g), "position": int(p), "tooth": int(self.teeth[t]),
            "stress": float(self.tensile[g, p, t]), "radius": float(self.tensile_radius[g, p, t]),
            "face": float(self.tensile_face[g, p, t]), "angle": float(self.tensile_angle[g, p, t]),
        }  # fmt: skip


def contact_root_stress(pair, contacts, compliance_a, compliance_b) -> PairRootStress:
    """Root stresses of both gears at each position of a loaded contact run.

    Parameters
    ----------
    pair : MeshPair
        The pair of the run (gear B's flank parameters of the cells are found again as
        the contact analysis found them, ``contact.flanks.separations``).
    contacts : sequence of PositionContact
        ``contact.ltca.loaded_contact``'s result.
    compliance_a, compliance_b : ToothCompliance
        The compliances of the run, built with ``root_stress=True``.

    Returns
    -------
    PairRootStress
    """
    from .flanks import separations

    if len(contacts) == 0:
        raise ReducerlabError("contacts: no mesh positions")
    teeth = tuple(int(k) for k in compliance_a.teeth)
    if tuple(int(k) for k in compliance_b.teeth) != teeth:
        raise ReducerlabError("compliance_b: must model the same tooth pairs as compliance_a")
    rows: list[list[ToothRootStress]] = [[], []]
    for c in contacts:
        loaded = c.force > 0
        tooth, uv, f = c.tooth[loaded], c.uv[loaded], c.force[loaded]
        uv_b = np.empty_like(uv)
        for k in np.unique(tooth):
            m = tooth == k
            uv_b[m] = separations(pair, c.phi, int(k), uv[m, 0], uv[m, 1]).uv_b
        rows[0].append(tooth_root_stress(compliance_a, tooth, uv[:, 0], uv[:, 1], f))
        rows[1].append(tooth_root_stress(compliance_b, tooth, uv_b[:, 0], uv_b[:, 1], f))

    def grab(name: str) -> Array:
        return np.array([[getattr(r, name) for r in g] for g in rows])

    names = ("tensile", "tensile_radius", "tensile_face", "tensile_angle", "compressive",
             "compressive_radius", "compressive_face", "compressive_angle",
             "von_mises", "end_tensile")  # fmt: skip
    return PairRootStress(teeth, np.array([c.phi for c in contacts]),
                          *(grab(n) for n in names))  # fmt: skip
