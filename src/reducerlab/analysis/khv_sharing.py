"""Load sharing of the KHV internal pair against torque (issue 30).

In an internal pair with a tooth-number difference of a few teeth the pairs next to the
ones in mesh stand a few micrometres apart (``contact.internal_pair.
tooth_pair_clearances``), so as the torque rises more tooth pairs take load and the mesh
stiffens. :func:`load_sharing` runs the loaded tooth contact analysis of a ``khv``
design's planet-ring pair over one mesh cycle at several torques and reports, per
torque and mesh position, the tooth pairs in contact, each pair's share of the load,
the mesh stiffness ``k = T_ring / (r_b2^2 psi)`` (secant, as ``contact_analysis``
gives it), the tangent stiffness ``dT_ring / dpsi / r_b2^2`` and the loaded
transmission error.

1. **Which tooth pairs.** The unloaded drive-flank clearances of the pairs
   ``-SCAN ... SCAN`` (SCAN = ``z1 // 3``) are found at every analysed position (rigid
   teeth). Before the finite-element work, the loaded approach at the largest torque is
   estimated from ISO 6336-1's single-pair stiffness with ``z_n2 = inf`` (below the
   contact analysis's by 15 %, docs/contact.md: the estimate errs long), added to the
   unloaded transmission error; every pair whose least clearance lies within
   ``contact.internal_pair.loaded_pairs``'s margin of it is examined. After the run
   the same rule is applied to the measured largest loaded transmission error; a pair
   it adds is examined in a second run, and one beyond the modelled pairs ``-2 ... 2``
   is refused, never dropped.
2. **The sweep.** ``analysis.te_sweep.te_sweep`` on those pairs (one finite-element
   tooth compliance, extended beyond teeth -1, 0, 1 by ``contact.compliance.
   extend_teeth``; at each position one contact grid and compliance for all torques),
   each loaded position's force per tooth pair read as it comes.

The shares at zero torque are the limit of light load: not computed (NaN).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError, names_source
from ..numformat import Column, Table, fmt
from ..results import Result
from ..threads import with_compute_threads

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["SharingResult", "approach_estimate", "load_sharing", "scan_pairs"]

Array = NDArray[np.float64]

#: N/(mm um) per N/m of stiffness per metre of face width (ISO 6336's unit)
PER_FACE = 1e-9


class SharingResult(Result):
    """Load sharing of the KHV planet-ring pair over a mesh cycle against torque.

    ``data`` holds every variable of :class:`~reducerlab.analysis.te_sweep.
    TESweepResult` (``te``, ``stiffness``, ``pairs``, ...; dimensions ``torque`` and
    ``position``) and: ``share`` (torque, position, ``pair``: the fraction of the load
    on each examined tooth pair; NaN at zero torque), ``tangent_stiffness`` (torque,
    position; N/m, ``dT_ring/dpsi / r_b2^2`` by finite differences over the torques),
    ``mean_stiffness`` and ``mean_tangent_stiffness`` (torque; N/m, the means over the
    cycle), ``clearance`` (position, ``scan_pair``; m, the unloaded drive-flank
    clearance ``r_b2 psi`` of each scanned pair, inf where it never faces).
    """

    kind: ClassVar[str] = "khv-sharing"

    @property
    def torques(self) -> Array:
        """Torques on the planet (N m)."""
        return np.asarray(self.data["torque"].values, float)

    @property
    def pairs(self) -> list[int]:
        """The tooth pairs examined."""
        return [int(k) for k in self.data["pair"].values]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes, positions, and one row a torque."""
        ds = self.data
        b = float(ds.attrs["face_width_m"])
        rows = []
        for i, t in enumerate(self.torques):
            share = ds["share"].values[i]
            rows.append({
                "torque_N_m": float(t),
                "pairs_in_contact": [int(v) for v in ds["pairs"].values[i]],
                "share": {f"{k:+d}": [None if not np.isfinite(v) else float(v)
                                      for v in share[:, j]]
                          for j, k in enumerate(self.pairs)},
                "stiffness_N_per_mm_um": _listed(ds["stiffness"].values[i] * PER_FACE / b),
                "mean_stiffness_N_per_m": _num(ds["mean_stiffness"].values[i]),
                "mean_tangent_stiffness_N_per_m": _num(ds["mean_tangent_stiffness"].values[i]),
                "te_um": _listed(1e6 * ds["te"].values[i]),
                "peak_to_peak_um": 1e6 * float(ds["peak_to_peak"].values[i]),
            })  # fmt: skip
        out = {k: (v.item() if hasattr(v, "item") else v) for k, v in ds.attrs.items()
               if k != "design"}  # fmt: skip
        out["angle_deg"] = [float(v) for v in np.degrees(ds["angle"].values)]
        out["least_clearance_um"] = {
            f"{int(k):+d}": _num(1e6 * ds["least_clearance"].values[j])
            for j, k in enumerate(ds["scan_pair"].values)
        }
        out["torques"] = rows
        return out

    def table(self) -> str:
        """Plain-text table: one row a torque."""
        ds = self.data
        a = ds.attrs
        b = float(a["face_width_m"])
        ks = self.pairs
        kpb = "N/(mm um)"
        t = Table([Column("T_pl", "N m", "torque"), Column("pairs", kind="text"),
                   Column("mean k", kpb, "stiffness"), Column("k min", kpb, "stiffness"),
                   Column("k max", kpb, "stiffness"), Column("tangent", kpb, "stiffness"),
                   Column("p-p TE", "um", "length"),
                   *(Column(f"max share {k:+d}", kind="share") for k in ks)], title=(
            f"KHV pair load sharing over one mesh cycle ({ds.sizes['position']} positions); "
            f"tooth pairs examined {ks}; design load {fmt(a['design_torque'], 'torque')} N m "
            f"on the planet; k per face width b = {fmt(b * 1e3, 'length')} mm"))  # fmt: skip
        for i, tq in enumerate(self.torques):
            if tq <= 0:
                continue
            n = ds["pairs"].values[i]
            k = ds["stiffness"].values[i] * PER_FACE / b
            share = ds["share"].values[i]
            t.add(tq, f"{int(np.nanmin(n))}-{int(np.nanmax(n))}",
                  float(ds["mean_stiffness"].values[i]) * PER_FACE / b, np.nanmin(k),
                  np.nanmax(k), float(ds["mean_tangent_stiffness"].values[i]) * PER_FACE / b,
                  1e6 * float(ds["peak_to_peak"].values[i]),
                  *(np.nanmax(share[:, j]) for j in range(len(ks))))  # fmt: skip
        lines = [t.text()]
        least = ds["least_clearance"].values
        far = [f"{int(k):+d}: {fmt(1e6 * c, 'length')} um"
               for k, c in zip(ds["scan_pair"].values, least, strict=True)
               if int(k) not in ks and np.isfinite(c)]  # fmt: skip
        lines.append("least clearance of the pairs not examined: " + (", ".join(far) or "none"))
        return "\n".join(lines)

    def figure(self) -> Figure:
        """Shares against position for a few torques; pairs in contact and mean k
        against torque (``plot.khv.plot_load_sharing``)."""
        from ..plot.khv import plot_load_sharing

        return plot_load_sharing(self)

    plot = figure


def _row_mean(a: Array) -> Array:
    """Mean of each row over its finite entries (NaN for a row with none)."""
    ok = np.isfinite(a)
    n = ok.sum(axis=1)
    return np.where(n > 0, np.where(ok, a, 0.0).sum(axis=1) / np.maximum(n, 1), np.nan)


def _num(v: float) -> float | None:
    return float(v) if np.isfinite(v) else None


def _listed(a: Array) -> list[float | None]:
    return [_num(v) for v in np.asarray(a, float)]


def scan_pairs(mp: Any) -> list[int]:
    """The tooth pairs whose clearances are scanned: ``-z1 // 3 ... z1 // 3`` (a third
    of the planet round either way: in examples/khv.toml the tips pass at pair
    +8, the pairs beyond never face on the drive flanks)."""
    n = max(3, mp.planet.teeth // 3)
    return list(range(-n, n + 1))


def approach_estimate(mp: Any, torque: float) -> float:
    """Elastic approach ``r_b2 psi`` (m) of one tooth pair alone under the planet torque
    ``torque`` (N m): ``F_n / (c' b)``, ``F_n = T_ring / r_b2``, ISO 6336-1's
    single-pair stiffness ``c' = C_B / q'`` read with ``z_n2 = inf`` (docs/assumptions.md,
    "KHV internal pair in the LTCA"; the contact analysis measures 15 % more, so this
    errs long)."""
    from ..contact.iso6336 import ISO_STIFFNESS_TO_SI, basic_rack_factor, iso6336_q

    p, r = mp.planet, mp.ring
    c_b = 0.5 * (basic_rack_factor(p.dedendum, p.pressure_angle)
                 + basic_rack_factor(r.dedendum, r.pressure_angle))  # fmt: skip
    c = c_b / iso6336_q(p.teeth, math.inf, p.shift, r.shift) * ISO_STIFFNESS_TO_SI
    return torque * mp.torque_ratio / r.base_radius / (c * p.face_width)


@names_source
@with_compute_threads
def load_sharing(
    design: Any,
    *,
    loads: int = 6,
    top: float = 1.5,
    torques: Sequence[float] | None = None,
    power: float | None = None,
    torque: float | None = None,
    positions: int = 24,
    cell: float | None = None,
    tooth_size: float | None = None,
    compliance: tuple[Any, Any] | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
    partial: Callable[[SharingResult], None] | None = None,
) -> SharingResult:
    """Tooth pairs in contact, load shares, mesh stiffness and loaded TE of a KHV
    design's planet-ring pair over one mesh cycle against torque (module docstring).

    Parameters
    ----------
    design : KHVDesign
    loads, top, torques, power, torque : optional
        The torques on the planet, as :func:`~reducerlab.analysis.te_sweep.te_sweep`:
        ``loads`` from 0 to ``top`` times the design load, or ``torques`` (N m).
    positions : int
        Positions over one mesh cycle (``>= 3``).
    cell : float, optional
        Contact cell (m); default from a pilot position at the design load.
    tooth_size : float, optional
        Finite-element tooth elements (m).
    compliance : (ToothCompliance, ToothCompliance), optional
        The planet's and the ring's tooth compliances (teeth -1, 0, 1) from an earlier
        run of the same pair (``PairSetup.compliances``; ``reducerlab run``'s
        compliance stage), unmodified teeth: no finite-element model is built.
    stage, progress : callable, optional
        ``stage(text)`` per step; ``progress(done, total)`` per position.
    partial : callable, optional
        ``partial(result)`` with the positions done so far (the others NaN), after each
        chunk of positions (``te_sweep``'s ``partial``: about an eighth of them; a
        second run on more tooth pairs starts again from none).

    Returns
    -------
    SharingResult

    Raises
    ------
    ReducerlabError
        Not a ``khv`` design, bad torques or positions (named), a ``compliance`` that is
        not a pair of tooth compliances, or a tooth pair beyond
        ``-2 ... 2`` that the largest torque would close
        (``contact.internal_pair.loaded_pairs``).
    """
    from ..contact.internal_pair import loaded_pairs, tooth_pair_clearances
    from .contact_setup import pair_setup
    from .te_sweep import te_sweep, torque_list

    if getattr(design, "type", None) != "khv":
        raise ReducerlabError(
            f"design: the load sharing is of a khv design's internal pair; got type "
            f"{getattr(design, 'type', type(design).__name__)!r}"
        )
    if isinstance(positions, bool) or not isinstance(positions, int) or positions < 3:
        raise ReducerlabError(f"positions: must be an integer >= 3; got {positions!r}")
    say = stage or (lambda _s: None)
    reference, T = torque_list(design, 1, loads, top, torques, power, torque)
    if compliance is not None:
        _check_compliance(compliance)
    setup = pair_setup(design)
    mp = setup.mesh_pair
    phis = setup.start + setup.pitch * np.arange(positions) / positions
    rolls = np.array([mp.contact_roll(float(p)) for p in phis])
    scan = scan_pairs(mp)
    say(f"unloaded clearances of tooth pairs {scan[0]} ... {scan[-1]}")
    _, clear = tooth_pair_clearances(mp, scan, points=201, rolls=rolls)
    unloaded = np.min(np.where(np.isfinite(clear), clear, np.inf), axis=1)  # the TCA's TE
    guess = float(np.max(unloaded)) + approach_estimate(mp, float(T[-1]))
    teeth = loaded_pairs(scan, clear, guess)
    if compliance is None:
        setup.compliance_estimate(tooth_size).check()
        compliance = setup.compliances(tooth_size, say, None)
    while True:
        forces: dict[tuple[int, int], Array] = {}

        def observe(
            i: int, j: int, run: Any, ks: tuple[int, ...] = teeth, out: dict = forces
        ) -> None:
            out[i, j] = np.array([run.force[run.tooth == k].sum() for k in ks])

        def so_far(
            res: Any, ks: tuple[int, ...] = teeth, out: dict = forces, sink: Any = partial
        ) -> None:  # the positions done so far: their forces are all in ``out``
            sink(_result(res, mp, ks, dict(out), scan, clear, reference))

        res = te_sweep(design, torques=T, positions=positions, cell=cell,
                       tooth_size=tooth_size, compliance=compliance, teeth=teeth,
                       observe=observe, stage=stage, progress=progress,
                       harmonics=1, partial=None if partial is None else so_far)  # fmt: skip
        te_max = float(np.nanmax(res.data["te"].values[-1]))
        need = loaded_pairs(scan, clear, te_max)
        if set(need) <= set(teeth):
            break
        say(f"tooth pairs {sorted(set(need) - set(teeth))} come within reach: again")
        teeth = tuple(sorted(set(teeth) | set(need)))
        cell = float(res.data.attrs["cell_m"])
    return _result(res, mp, teeth, forces, scan, clear, reference)


def _check_compliance(compliance: Any) -> None:
    """Refuse a ``compliance`` other than two tooth compliances (planet, ring) of the
    modelled teeth -1, 0, 1."""
    from ..contact.compliance import ToothCompliance

    ok = (
        isinstance(compliance, tuple | list)
        and len(compliance) == 2
        and all(isinstance(c, ToothCompliance) for c in compliance)
    )
    if not ok:
        raise ReducerlabError(
            "compliance: must be the planet's and the ring's ToothCompliance (a pair, "
            f"as PairSetup.compliances gives them); got {type(compliance).__name__}"
        )
    for name, c in zip(("planet", "ring"), compliance, strict=True):
        if not {-1, 0, 1} <= set(c.teeth):
            raise ReducerlabError(
                f"compliance: the {name}'s must model teeth -1, 0, 1; it models {list(c.teeth)}"
            )


def _result(res, mp, teeth, forces, scan, clear, reference) -> SharingResult:
    """The :class:`SharingResult` from the sweep and the per-pair forces."""
    ds = res.data.copy()
    T = np.asarray(ds["torque"].values, float)
    n_pos = ds.sizes["position"]
    share = np.full((T.size, n_pos, len(teeth)), np.nan)
    for (i, j), f in forces.items():
        share[i, j] = f / f.sum()
    r_b2 = mp.ring.base_radius
    psi = ds["te_rotation"].values  # rad of the ring, unloaded TE included
    T_ring = T * mp.torque_ratio
    tangent = np.full_like(psi, np.nan)
    if T.size >= 2:
        with np.errstate(divide="ignore", invalid="ignore"):
            dT = np.gradient(T_ring, axis=0)[:, None] * np.ones_like(psi)
            tangent = dT / np.gradient(psi, axis=0) / r_b2**2
    k = ds["stiffness"].values
    ds["share"] = (("torque", "position", "pair"), share)
    ds["tangent_stiffness"] = (("torque", "position"), tangent, {"units": "N/m"})
    ds["mean_stiffness"] = ("torque", _row_mean(k), {"units": "N/m"})
    ds["mean_tangent_stiffness"] = ("torque", _row_mean(tangent), {"units": "N/m"})
    ds["clearance"] = (("position", "scan_pair"), clear, {"units": "m"})
    least = np.min(np.where(np.isfinite(clear), clear, np.inf), axis=0)
    ds["least_clearance"] = ("scan_pair", least, {"units": "m"})
    ds = ds.assign_coords(pair=("pair", list(teeth)), scan_pair=("scan_pair", list(scan)))
    ds.attrs.update(
        title="KHV internal pair: load sharing against torque",
        pairs_examined=",".join(f"{k:+d}" for k in teeth), design_torque=float(reference),
        face_width_m=float(mp.planet.face_width), base_radius_ring_m=float(r_b2),
        contact_ratio=float(mp.contact_ratio),
    )  # fmt: skip
    return SharingResult(ds)
