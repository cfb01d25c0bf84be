"""The torsional stiffness test of a reducer as a bench runs it (issue 31, first part).

``torsion_test(design)`` holds the drive's input, applies an output torque stepped
quasi-statically ``0 -> +T_rated -> -T_rated -> 0`` and finds at each step the static
equilibrium of the whole drive model (:func:`reducerlab.drives.build_model`): every mesh
line with its backlash (dead zone), its load exponent (``model.system.power_force``) and
cubic term, the supports, shafts and couplings of ``K``, each line's mean stiffness law
(or its value at a stated time ``position``). The output twist against the torque is
the hysteresis loop from which :mod:`.datasheet` reads the catalogue numbers.

The equations, for the free DOFs ``q`` (the held ones at zero):
``K q + G^T F(G q - e) = b T``, with ``F`` the lines' elastic forces
(``F_m = k_m (d_m/p_m) sgn(f)(|f|/d_m)^p_m + k3_m f^3``, ``f`` the deflection beyond the
half backlash ``h_m``) and ``b`` the generalised force of a unit output torque (``1/r``
on an equivalent displacement ``u = r theta``, 1 on a rotation). The solver is a
semi-smooth Newton iteration whose active set is the contact side of each line at the
current iterate (apart: no force, no stiffness), with a backtracking line search on the
residual norm, continued in the torque from the previous step (a step that fails is
halved). At zero torque a frictionless drive rests anywhere inside its backlash: the
test reports the limit of each branch (every line loaded on the branch's side just
touching, found as the least-strain state with those contacts closed), so the loop
crosses zero torque by a vertical jump: the backlash.

No friction is modelled yet: loading and unloading follow the same curve and the loop
encloses no area (a later part adds Coulomb friction at the contacts, which opens it).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..budget import Estimate
from ..errors import ReducerlabError
from ..model.laws import evaluate_flat, flat_mean
from ..numformat import Table, fmt, quantity_table
from ..results import Result, provenance
from .datasheet import LoopNumbers, loop_numbers

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..model import Model, NonlinearSystem

__all__ = [
    "BenchEnds",
    "TorsionTestResult",
    "bench_ends",
    "loop_torques",
    "torsion_estimate",
    "torsion_test",
]

Array = NDArray[np.float64]
ARCMIN = math.pi / (180.0 * 60.0)  # rad per arc minute
#: Largest ``steps`` a test takes (each is a Newton solve on every branch).
MAX_STEPS = 10000
#: Branches of the loop in test order (0 -> +T -> 0 -> -T -> 0).
BRANCHES = ("loading +", "unloading +", "loading -", "unloading -")


@dataclass(frozen=True)
class BenchEnds:
    """Where the bench holds and loads a drive model.

    Attributes
    ----------
    held : tuple of str
        DOFs held at zero: the input (and the housing member where the model carries
        the drive's rigid rotation on it); empty where the model grounds it already.
    output : str
        The output DOF, loaded by the test torque.
    radius : float or None
        Radius (m) of the output DOF when it is an equivalent displacement
        ``u = r theta``; None for a rotation (rad).
    note : str
        How the ends were chosen (for the result's attributes).
    """

    held: tuple[str, ...]
    output: str
    radius: float | None
    note: str


def bench_ends(design: Any, model: Model) -> BenchEnds:
    """The held and loaded DOFs of each drive type's model.

    * nutation: the output gear's rotation (``g4.rz`` double-sided, ``g13.rz``
      single-sided); the input crank is no DOF of the model (its frame is the mesh
      frame), so holding it leaves the drive's rigid rotation, which turns the fixed
      gear ``g2.rz`` with the others: the test holds ``g2.rz`` (a rigid housing) unless a
      torsional support of gear 2 (``fixed_gear_torsional_stiffness``) grounds it;
    * KHV: ``drive.u`` held, ``load.u`` loaded;
    * cycloid ball: ``input_shaft.u`` held, ``centre_disc.u`` loaded; for a planetary
      output the centre disc is held too and ``end_cover_disc.u`` loaded (the model's
      torsional support of the end cover, ``k5u``, then acts in parallel with the drive);
    * gear pair: ``pinion.rz`` held, ``gear.rz`` loaded;
    * lumped designs name no input or output: give ``held`` and ``output`` to
      :func:`torsion_test`.

    Raises
    ------
    ReducerlabError
        For a design type without a known input and output.
    """
    kind = getattr(design, "type", None)
    if kind == "nutation":
        out = "g4.rz" if design.sides == "double" else "g13.rz"
        grounded = design.fixed_gear_torsional_stiffness > 0
        held: tuple[str, ...] = () if grounded else ("g2.rz",)
        note = "nutation: input crank locked (mesh frame fixed); " + (
            "gear 2 on its torsional support" if grounded else "gear 2 held (rigid housing)"
        )
    elif kind == "khv":
        out, held, note = "load.u", ("drive.u",), "KHV: drive shaft held, load shaft loaded"
    elif kind == "cycloid_ball" and design.output == "planetary":
        # the centre disc is the held member of a planetary-disc output
        out, held = "end_cover_disc.u", ("input_shaft.u", "centre_disc.u")
        note = ("cycloid ball (planetary output): input shaft and centre disc held, end "
                "cover loaded (its torsional support k5u acts in parallel)")  # fmt: skip
    elif kind == "cycloid_ball":
        out = "centre_disc.u"
        held, note = ("input_shaft.u",), "cycloid ball: input shaft held, centre disc loaded"
    elif kind == "gear_pair":
        out, held, note = "gear.rz", ("pinion.rz",), "gear pair: pinion held, gear loaded"
    else:
        raise ReducerlabError(
            f"torsion test: a {kind!r} design names no input and output; give the DOFs "
            "to hold and the output DOF (held=..., output=...)"
        )
    return _ends(model, held, out, note)


def _ends(model: Model, held: tuple[str, ...], output: str, note: str) -> BenchEnds:
    dofs = {d.name: d for d in model.dofs}
    for name in (*held, output):
        if name not in dofs:
            raise ReducerlabError(
                f"torsion test: the model has no DOF {name!r} (DOFs: {', '.join(dofs)})"
            )
    if output in held:
        raise ReducerlabError(f"torsion test: the output DOF {output!r} is also held")
    d = dofs[output]
    if d.kind not in ("rz", "rx", "ry", "u"):
        raise ReducerlabError(
            f"torsion test: the output DOF {output!r} is a translation, not a rotation"
        )
    return BenchEnds(tuple(held), output, d.radius if d.kind == "u" else None, note)


@dataclass(frozen=True)
class _Bench:
    """The free-DOF arrays of the test (SI)."""

    K: Array  # (n, n) linear stiffness of the free DOFs
    G: Array  # (lines, n)
    k: Array  # line stiffness (N/m) at the stated position or mean
    e: Array  # line error (m)
    h: Array  # half backlash (m)
    k3: Array
    p: Array
    d: Array
    b: Array  # generalised force of a unit output torque
    c: Array  # output twist (rad) per q

    friction = False  # no Coulomb friction (analysis.torsion_friction adds it)

    @property
    def frictionless(self) -> _Bench:
        return self

    def start(self, q: Array) -> None:
        """A branch starts at ``q`` (no state to reset without friction)."""

    def commit(self, q: Array) -> None:
        """Accept a solved state (no state to advance without friction)."""

    def forces(self, q: Array) -> tuple[Array, Array, Array]:
        """Line forces (N), their slopes (N/m; 0 apart) and the deflection beyond the
        backlash ``f`` (m) at ``q``."""
        delta = self.G @ q - self.e
        f = delta - np.clip(delta, -self.h, self.h)
        a = np.abs(f)
        lin = self.p == 1.0
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(lin, 1.0, a / np.where(self.d > 0, self.d, 1.0))
            force = np.where(lin, self.k * f, np.sign(f) * self.k * self.d / self.p * ratio**self.p)
            slope = np.where(lin, self.k, self.k * ratio ** (self.p - 1.0))
        force = force + self.k3 * f**3
        # closed (at or beyond the backlash, to round-off): the one-sided slope, k for
        # a linear line that just touches (the branch's zero-torque limit)
        closed = np.abs(delta) >= self.h * (1.0 - 1e-9)
        slope = np.where(closed, slope + 3.0 * self.k3 * f * f, 0.0)
        return force, slope, f

    def residual(self, q: Array, T: float) -> Array:
        return self.K @ q + self.G.T @ self.forces(q)[0] - self.b * T

    def jacobian(self, q: Array, floor: float = 0.0) -> Array:
        slope = self.forces(q)[1]
        return self.K + self.G.T @ (self.G * np.maximum(slope, floor * self.k)[:, None])


def _bench(s: NonlinearSystem, ends: BenchEnds, position: float | None) -> tuple[_Bench, list]:
    names = list(s.dof_names)
    held = [names.index(n) for n in ends.held]
    free = [i for i in range(len(names)) if i not in held]
    o = free.index(names.index(ends.output))
    lines = range(s.G.shape[0])
    if position is None:
        k = np.array([flat_mean(int(s.k_kind[m]), s.k_params[m]) for m in lines])
        e = np.array([flat_mean(int(s.e_kind[m]), s.e_params[m]) for m in lines])
    else:
        k = np.array([evaluate_flat(int(s.k_kind[m]), s.k_params[m], position)[0] for m in lines])
        e = np.array([evaluate_flat(int(s.e_kind[m]), s.e_params[m], position)[0] for m in lines])
    r = 1.0 if ends.radius is None else ends.radius
    b = np.zeros(len(free))
    b[o] = 1.0 / r
    c = np.zeros(len(free))
    c[o] = 1.0 / r
    ix = np.ix_(free, free)
    bench = _Bench(
        K=s.K[ix], G=s.G[:, free], k=k, e=e, h=np.asarray(s.half_backlash, float),
        k3=np.asarray(s.line_cubic, float), p=s.line_power[:, 0].copy(),
        d=s.line_power[:, 1].copy(), b=b, c=c,
    )  # fmt: skip
    return bench, [names[i] for i in free]


def _with_friction(
    design: Any, model: Model, s: NonlinearSystem, bench: _Bench, free: list, mu: float | None
) -> tuple[Any, float, str]:
    """The bench with Coulomb friction on its sliding lines (:mod:`.torsion_friction`),
    the coefficient and a note saying what slides."""
    from .efficiency import friction_coefficient
    from .torsion_friction import friction_bench, mindlin_ratio, sliding_matrix

    mu = friction_coefficient(design, mu)
    names = list(s.dof_names)
    S = sliding_matrix(model, list(s.line_names))[:, [names.index(n) for n in free]]
    nu = getattr(getattr(design, "material", None), "poisson_ratio", None)
    kappa = mindlin_ratio(0.3 if nu is None else float(nu))
    fb = friction_bench(bench, S, mu, kappa)
    if fb is None:
        why = "mu = 0" if mu == 0 else "no line slides (rolling contacts)"
        return bench, mu, f"none ({why}: the loop encloses no area)"
    lines = [n for n, row in zip(s.line_names, S, strict=True) if np.any(row)]
    return (
        fb,
        mu,
        (f"Coulomb mu = {mu:g} at {', '.join(lines)} (Jenkins elements, k_t = {kappa:.3f} k)"),
    )


def torsion_estimate(steps: int, dofs: int, lines: int) -> Estimate:
    """Work (static solves: four branches of ``steps + 5`` torques) and memory (the
    states, line forces and one Jacobian) of a torsion test; at most
    :data:`MAX_STEPS` steps."""
    points = 4 * (steps + 5)
    memory = 8.0 * (points * (dofs + lines + 4) + 4 * dofs * dofs)
    return Estimate(
        f"torsion test: {points} states of {dofs} DOFs, {lines} mesh lines", memory,
        float(steps), "torque steps", float(MAX_STEPS), "--steps",
    )  # fmt: skip


def loop_torques(rated: float, steps: int, fractions: tuple[float, ...] = ()) -> Array:
    """Torque fractions of one branch ``0 .. 1`` (ascending): ``steps`` equal steps plus
    the ``fractions`` the datasheet reads (3 %, 4 %, T1/T2), so that every number is read
    at a solved point, not interpolated."""
    grid = np.union1d(np.linspace(0.0, 1.0, steps + 1), np.asarray(fractions, float))
    return rated * grid


def _newton(bench: _Bench, T: float, q0: Array, scale: float) -> Array | None:
    """Equilibrium at torque ``T`` from ``q0`` (None if not converged): semi-smooth
    Newton (the contact side of each line from the iterate) with a backtracking line
    search on ``|r|``. The Jacobian's line slopes have a floor of ``1e-9 k`` so that a
    line apart, or a power-law line at zero deflection, leaves it regular; the floor
    changes the search direction only, never the residual that is converged."""
    q = q0.copy()
    r = bench.residual(q, T)
    for _ in range(200):
        if np.abs(r).max() <= _tolerance(bench, q, scale):
            return q
        try:
            dq = np.linalg.solve(bench.jacobian(q, 1e-9), -r)
        except np.linalg.LinAlgError:
            dq = np.linalg.lstsq(bench.jacobian(q, 1e-9), -r, rcond=None)[0]
        norm, t = np.linalg.norm(r), 1.0
        while t > 1e-10:
            r_new = bench.residual(q + t * dq, T)
            if np.linalg.norm(r_new) < (1.0 - 1e-4 * t) * norm:
                break
            t *= 0.5
        else:
            return None
        q, r = q + t * dq, r_new
    return q if np.abs(r).max() <= _tolerance(bench, q, scale) else None


def _tolerance(bench: _Bench, q: Array, scale: float) -> float:
    """Converged residual (N): ``1e-10`` of the load scale plus ``1e-12`` of the
    largest term of ``K q + G^T F`` (their round-off: stiffnesses of 1e9 N/m times
    motions of 1e-4 m cancel to a few 1e-11 of 1e5 N)."""
    terms = np.abs(bench.K) @ np.abs(q) + np.abs(bench.G.T) @ np.abs(bench.forces(q)[0])
    return 1e-10 * scale + 1e-12 * float(terms.max(initial=0.0))


def _solve(bench: _Bench, T: float, T0: float, q0: Array, scale: float, depth: int = 0) -> Array:
    """Continuation from the equilibrium ``q0`` at ``T0`` to ``T``, halving a step
    whose Newton iteration fails (at most 30 halvings)."""
    q = _newton(bench, T, q0, scale)
    if q is not None:
        return q
    if depth >= 30:
        raise ReducerlabError(
            f"torsion test: no static equilibrium found at {T:.6g} N m (Newton failed after "
            "30 halvings of the torque step); is the output held through the meshes?"
        )
    mid = 0.5 * (T + T0)
    q_mid = _solve(bench, mid, T0, q0, scale, depth + 1)
    return _solve(bench, T, mid, q_mid, scale, depth + 1)


def _contact_limit(bench: _Bench, side: Array) -> Array:
    """The state a branch tends to as its torque goes to zero: the lines loaded on the
    branch (``side`` +1/-1; 0 apart) just touch (``G q - e = side h``), everything else
    at least strain (``min q^T K q / 2`` under those contacts: a KKT system solved in
    the least-squares sense, so that a DOF left free by both has zero motion)."""
    A = side != 0
    GA = bench.G[A]
    n, m = bench.K.shape[0], int(A.sum())
    kkt = np.zeros((n + m, n + m))
    kkt[:n, :n] = bench.K
    # constraint rows scaled to the stiffness (same q; a better conditioned system)
    c = (np.abs(bench.K).max(initial=0.0) or 1.0) / (np.abs(GA).max(initial=0.0) or 1.0)
    kkt[:n, n:] = c * GA.T
    kkt[n:, :n] = c * GA
    rhs = np.concatenate([np.zeros(n), c * (bench.e[A] + side[A] * bench.h[A])])
    return np.linalg.lstsq(kkt, rhs, rcond=None)[0][:n]


def _tangent(bench: _Bench, q: Array) -> float:
    """Tangent torsional stiffness ``dT/dtheta = 1 / (c^T J^-1 b)`` (N m/rad) at ``q``,
    with the lines' true slopes; NaN where the Jacobian is singular (a line apart)."""
    J = bench.jacobian(q)
    try:
        x = np.linalg.solve(J, bench.b)
    except np.linalg.LinAlgError:
        return math.nan
    flex = float(bench.c @ x)
    if not np.all(np.isfinite(x)) or np.linalg.cond(J) > 1e14 or flex <= 0:
        return math.nan
    return 1.0 / flex


class TorsionTestResult(Result):
    """The torsion test's loop and the datasheet numbers read from it.

    ``data`` has the dimension ``point`` (the solved states in test order) with
    variables ``torque`` (N m on the output), ``twist`` (rad of the output), ``branch``
    (0..3: :data:`BRANCHES`), ``tangent_stiffness`` (N m/rad; NaN at the zero-torque
    limits) and ``line_force`` (point, ``line``; N), and the datasheet numbers as
    attributes (SI: rad, N m, N m/rad; see :mod:`.datasheet`).
    """

    kind: ClassVar[str] = "torsion-test"

    @property
    def numbers(self) -> LoopNumbers:
        """The datasheet numbers (SI)."""
        a = self.data.attrs
        return LoopNumbers(**{k: float(a[k]) for k in LoopNumbers.FIELDS})

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: the numbers in catalogue units and the loop."""
        a = self.data.attrs
        out: dict[str, Any] = {k: (v.item() if hasattr(v, "item") else v)
                               for k, v in a.items() if k != "design"}  # fmt: skip
        out["datasheet"] = self.numbers.catalogue()
        out["loop"] = {
            "torque_N_m": [float(v) for v in self.data["torque"].values],
            "twist_arcmin": [float(v) / ARCMIN for v in self.data["twist"].values],
            "branch": [BRANCHES[int(b)] for b in self.data["branch"].values],
        }
        return out

    def table_data(self, more: Sequence[tuple[str, float, str]] = ()) -> Table:
        """The datasheet numbers (quantity, value, unit; N m, arcmin, N m/arcmin) and
        ``more`` rows after them, under a line naming the test."""
        a = self.data.attrs
        head = (
            f"Torsion test: {a['ends']}; output {a['output_dof']}, rated torque "
            f"{fmt(a['rated_torque'], 'torque')} N m, {a['points']} states; friction: "
            f"{a['friction']}"
        )
        return quantity_table([*self.numbers.rows(), *more], title=head)

    def table(self) -> str:
        """Plain-text datasheet table (N m, arcmin, N m/arcmin)."""
        return self.table_data().text()

    def figure(self) -> Figure:
        """The loop: twist (arcmin) against torque (N m) with K1/K2/K3 and the
        lost-motion band."""
        from ..plot.torsion import plot_torsion_loop

        return plot_torsion_loop(self)

    plot = figure


def torsion_test(
    design: Any,
    *,
    rated: float | None = None,
    steps: int = 10,
    t1: float = 0.2,
    t2: float = 0.7,
    position: float | None = None,
    held: tuple[str, ...] | None = None,
    output: str | None = None,
    model: Model | None = None,
    mu: float | None = None,
) -> TorsionTestResult:
    """The quasi-static torsion test of a drive, input held.

    Parameters
    ----------
    design : Design
        A drive design (``reducerlab.drives.load_design``).
    rated : float, optional
        Rated output torque ``T_rated`` (N m, > 0); default the design's output torque
        at its operating point.
    steps : int
        Equal torque steps from 0 to ``T_rated`` on each branch (>= 3).
    t1, t2 : float
        ``T1 / T_rated`` and ``T2 / T_rated`` of the K1/K2/K3 fit, ``0 < t1 < t2 < 1``
        (:func:`.datasheet.loop_numbers`).
    position : float, optional
        Time (s) at which the mesh stiffness and error laws are read (a stated mesh
        position); default their time means.
    held, output : optional
        The DOFs to hold and the output DOF, for a design type without a known input
        and output (lumped), or to override :func:`bench_ends`.
    model : Model, optional
        The design's model when the caller has built it.
    mu : float, optional
        Coulomb coefficient at the sliding mesh contacts (``[0, 0.3]``; 0: no friction,
        the loop encloses no area); default the design's
        ``material.friction_coefficient``, else 0.05 (:mod:`.torsion_friction`).

    Returns
    -------
    TorsionTestResult
    """
    from ..drives import build_model

    t0 = time.perf_counter()
    if not isinstance(steps, int) or isinstance(steps, bool) or steps < 3:
        raise ReducerlabError(f"torsion test: steps must be an integer >= 3; got {steps!r}")
    if not (0.0 < t1 < t2 < 1.0):
        raise ReducerlabError(f"torsion test: need 0 < t1 < t2 < 1; got t1={t1}, t2={t2}")
    model = build_model(design) if model is None else model
    if output is not None or held is not None:
        if output is None:
            raise ReducerlabError("torsion test: give the output DOF with the held DOFs")
        ends = _ends(model, tuple(held or ()), output, "as given")
    else:
        ends = bench_ends(design, model)
    if rated is None:
        rated = float(design.operating_point().output_torque)
        if not rated > 0:
            raise ReducerlabError(
                "torsion test: the design has no output torque at its operating point; "
                "give the rated torque (N m)"
            )
    elif not (isinstance(rated, int | float) and math.isfinite(rated) and rated > 0):
        raise ReducerlabError(f"torsion test: the rated torque must be > 0 N m; got {rated!r}")
    s = model.nonlinear()
    torsion_estimate(steps, len(s.dof_names), len(s.line_names)).check()
    bench, free = _bench(s, ends, position)
    bench, mu, friction = _with_friction(design, model, s, bench, free, mu)
    fractions = (0.03, 0.04, t1, t2)
    up = loop_torques(float(rated), steps, fractions)
    torque, branch, states = _run_loop(bench, up, float(rated))
    twist = np.array([bench.c @ q for q in states])
    forces = np.array([bench.forces(q)[0] for q in states])
    tangent = np.array([_tangent(bench, q) if T != 0 else math.nan
                        for T, q in zip(torque, states, strict=True)])  # fmt: skip
    at_rated = np.abs(np.abs(torque) - rated) <= 1e-12 * rated
    nums = loop_numbers(torque, twist, branch, float(rated), t1 * rated, t2 * rated,
                        float(np.nanmean(tangent[at_rated])))  # fmt: skip
    ds = xr.Dataset(
        {
            "torque": ("point", torque, {"units": "N m"}),
            "twist": ("point", twist, {"units": "rad"}),
            "branch": ("point", branch),
            "tangent_stiffness": ("point", tangent, {"units": "N m/rad"}),
            "line_force": (("point", "line"), forces, {"units": "N"}),
        },
        coords={"point": np.arange(len(torque)), "line": list(s.line_names)},
        attrs={"title": "Torsion test (input held)", **provenance(model.metadata)},
    )
    ds.attrs.update(
        ends=ends.note, output_dof=ends.output, held=",".join(ends.held) or "(none)",
        output_radius_m=0.0 if ends.radius is None else ends.radius,
        rated_torque=float(rated), steps=int(steps), t1_fraction=float(t1),
        t2_fraction=float(t2), points=len(torque),
        position="mean laws" if position is None else f"t = {position:.6g} s",
        friction=friction, mu=mu, friction_work=float(getattr(bench, "work", 0.0)),
        free_dofs=",".join(free),
        seconds=time.perf_counter() - t0, **nums.attrs(),
    )  # fmt: skip
    return TorsionTestResult(ds)


def _run_loop(bench: _Bench, up: Array, rated: float) -> tuple[Array, Array, list[Array]]:
    """Solve the four branches; returns torques, branch indices and states. A branch
    that starts at zero torque is solved from its first nonzero torque (started from
    the state with every line closed on the side that torque loads); every
    zero-torque state is the limit of its branch's nonzero states (:func:`_zero_limit`)."""
    scale = float(np.abs(bench.b).max() * rated)
    torque: list[float] = []
    branch: list[int] = []
    states: list[Array] = []
    for j, (sign, order) in enumerate(((1, up), (1, up[::-1]), (-1, up), (-1, up[::-1]))):
        Ts = [sign * float(v) for v in order]
        nonzero = [T for T in Ts if T != 0.0]
        rest = None  # the branch's zero-torque start, when friction needs it first
        if j in (1, 3):  # continuing the loop: from the previous branch's last state
            T_prev, q_prev = torque[-1], states[-1]
        else:
            T_prev = nonzero[0]
            plain = bench.frictionless
            q_prev = _solve(plain, T_prev, 0.0, _closed_guess(bench, T_prev), scale)
            if bench.friction:  # at rest with every slider let go, then loaded
                rest = _zero_limit(plain, T_prev, q_prev, scale)
                bench.start(rest)
                q_prev = _solve(bench, T_prev, 0.0, rest, scale)
        solved: dict[float, Array] = {}
        for T in nonzero:
            q_prev = _solve(bench, T, T_prev, q_prev, scale)
            bench.commit(q_prev)
            T_prev, solved[T] = T, q_prev
        near = min(nonzero, key=abs)
        for T in Ts:
            if T != 0.0:
                q = solved[T]
            else:
                q = rest if rest is not None else _zero_limit(bench, near, solved[near], scale)
            torque.append(T)
            branch.append(j)
            states.append(q)
    return np.array(torque), np.array(branch), states


def _closed_guess(bench: _Bench, T: float) -> Array:
    """A start for the torque ``T``: every line closed on the side that the linear
    solution with all lines engaged loads, at its secant stiffness ``k / p`` at the
    reference deflection (``k`` for a linear line)."""
    J = bench.K + bench.G.T @ (bench.G * bench.k[:, None])
    x = np.linalg.lstsq(J, bench.b * T, rcond=None)[0]
    g = bench.G @ x
    side = np.sign(np.round(g / (np.abs(g).max(initial=0.0) or 1.0), 12))
    k_sec = bench.k / bench.p
    J_sec = bench.K + bench.G.T @ (bench.G * k_sec[:, None])
    rhs = bench.b * T + bench.G.T @ (k_sec * (bench.e + side * bench.h))
    return np.linalg.lstsq(J_sec, rhs, rcond=None)[0]


def _zero_limit(bench: _Bench, T: float, q: Array, scale: float) -> Array:
    """The state a branch tends to as its torque goes to zero from ``T`` (solved state
    ``q``). The lines loaded in that limit are found by continuing the solution to
    ``T 10^-3`` and ``T 10^-6`` (a line that closes only above a finite torque opens on
    the way; the lines are piecewise smooth, so the set loaded at ``1e-6 T``, still
    resolved 1e4 times above the solver's tolerance, is the limit's unless a line
    closes below it), then the limit itself is solved exactly
    (:func:`_contact_limit`): those lines just touching, least strain elsewhere."""
    for k in (3, 6):
        q = _solve(bench, T * 10.0**-k, T * 10.0 ** (3 - k), q, scale)
    return _contact_limit(bench, np.sign(bench.forces(q)[2]))
