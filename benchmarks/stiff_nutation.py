"""Benchmark: the 12-DOF nutation drive is stiff (issue 16): what accuracy costs, and
what makes it cheaper.

1. One-period maps (``ensemble(method="maps")``, the default where they apply) against
   the RK4 kernel on every period (``method="rk4"``), side by side, equal step counts
   (the default's accuracy-driven count), the largest difference of the Poincaré points
   relative to the state scale:

   * the case of ``benchmarks/bifurcation.py``: ``examples/nutation_double_sided.toml``
     as bundled, 100 values of ``mesh1.stiffness`` x 600 mesh periods;
   * loaded and time-varying: the same drive with the input and output torques of a
     3 kW, 1500 rpm operating point, the mesh variation below, 10 um backlash and 5 um
     error on both pairs (teeth in contact), 16 values x 300 periods of 7 mesh periods
     (the common period of its 650 Hz and 742.9 Hz meshes).

The drive of ``examples/nutation_double_sided.toml`` with a time-varying mesh stiffness
(harmonics 2e7 and 1e7 N/m on a 2.1e8 N/m mean), 2000 N s/m mesh damping, 10 um backlash
and a 5 um transmission error on both pairs (11 elastic DOF after rigid-motion removal,
modes 2.2-9.4 kHz against a 650 Hz mesh frequency). Errors of the Poincaré points over
periods 40-59 against the kernel at 2640 steps per period, relative to the state scale
(``state_bounds``):

* the RK4 kernel at N steps per period (the default picks N for ``accuracy = 1e-6``);
* ETDRK4 (Cox and Matthews 2002, the coefficients of Kassam and Trefethen 2005),
  prototyped here in numpy: the mean linear part (structure, mean mesh stiffness, mesh
  damping) propagated exactly in its eigenbasis, the rest (stiffness variation, backlash,
  error, loads) by the fourth-order exponential Runge-Kutta stages. It would remove the
  step limit of the highest modes if the rest were weak.

2. What RK4's step count buys on the time-varying drive, and the exponential
   integrator prototype below.

Run: ``.venv/bin/python benchmarks/stiff_nutation.py``.
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import time

import numpy as np

from reducerlab.analysis.members import axis_members
from reducerlab.analysis.parameters import Axis, Evaluator, resolve
from reducerlab.drives import build_model, load_design
from reducerlab.dynamics.coordinates import static_states
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.guards import state_bounds
from reducerlab.dynamics.systems import forcing_period
from reducerlab.examples import example_dir
from reducerlab.model.laws import evaluate_flat, flat_mean

SETS = [
    f"mesh{i}.{k}"
    for i in (1, 2)
    for k in ("harmonics=[2e7, 1e7]", "damping=2000", "backlash=10e-6", "error_amplitude=5e-6")
]
PERIODS, KEEP = 60, 20


# 3 kW at 1500 rpm, i = 105: 2005 N m on gear 4 and, from the torque flow, its reaction
# on the fixed gear 2 (the model applies both; issue 27 retired input_torque)
LOADS = ["output_torque=0", "output_power=3 kW"]
COMMON = 7 / 650  # s: 7 periods of mesh 1, 8 of mesh 2


def system():
    d = load_design(example_dir() / "nutation_double_sided.toml", SETS)
    values, members, _ = axis_members(d, build_model(d), Axis("mesh1.stiffness", (2e8,)), "b")
    return members(values)[0]


def members_of(sets: list[str], count: int):
    d = load_design(example_dir() / "nutation_double_sided.toml", sets)
    axis = Axis.linspace("mesh1.stiffness", 1.5e8, 3e8, count)
    values, members, _ = axis_members(d, build_model(d), axis, "benchmark")
    return members(values)


def maps_against_rk4(label: str, systems, periods: int, period: float | None) -> None:
    # from static equilibrium under the mean loads, as bifurcation() starts
    kw = dict(periods=periods, keep=100, period=period, y0=static_states(systems))
    ensemble(systems[:2], periods=30, keep=1, period=period, method="maps")  # compile
    ensemble(systems[:2], periods=2, keep=1, period=period, method="rk4")
    t = time.perf_counter()
    fast = ensemble(systems, method="maps", **kw)
    t_maps = time.perf_counter() - t
    t = time.perf_counter()
    slow = ensemble(systems, method="rk4", **kw)
    t_rk4 = time.perf_counter() - t
    scale = state_bounds(systems, kw["y0"], slow.period, factor=1.0)
    diff = float(np.nanmax(np.abs(fast.poincare - slow.poincare) / scale[:, None, :]))
    print(f"| {label} | {len(systems)} x {periods} | {slow.steps_per_period} | {t_rk4:.2f} | "
          f"{t_maps:.2f} ({int(fast.mapped.sum())} mapped) | {t_rk4 / t_maps:.1f}x | "
          f"{diff:.1e} |")  # fmt: skip


class ETD4:
    """ETDRK4 on ``y' = A y + N(y, t)``, ``A`` the mean linear part, in A's eigenbasis."""

    def __init__(self, s) -> None:
        n = s.n
        self.s = s
        Minv = np.linalg.inv(s.M)
        self.kbar = np.array([flat_mean(int(k), p) for k, p in zip(s.k_kind, s.k_params,
                                                                     strict=True)])  # fmt: skip
        K = s.K + s.G.T @ np.diag(self.kbar) @ s.G
        C = s.C + s.G.T @ np.diag(s.line_damping) @ s.G
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
        self.lam, self.V = np.linalg.eig(A)
        self.Vi = np.linalg.inv(self.V)
        self.Vq, self.GVv = self.V[:n], s.G @ self.V[n:]
        self.W = self.Vi[:, n:] @ (Minv @ s.G.T)
        self.WB = self.Vi[:, n:] @ (Minv @ s.load_matrix)

    def N(self, z, t):
        s = self.s
        q = (self.Vq @ z).real
        d = s.G @ q
        k = np.array([evaluate_flat(int(a), p, t)[0] for a, p in zip(s.k_kind, s.k_params,
                                                                      strict=True)])  # fmt: skip
        e = np.array([evaluate_flat(int(a), p, t) for a, p in zip(s.e_kind, s.e_params,
                                                                   strict=True)])  # fmt: skip
        dd = d - e[:, 0]
        f = dd - np.clip(dd, -s.half_backlash, s.half_backlash)
        rest = k * f - self.kbar * d - s.line_damping * e[:, 1]
        laws = zip(s.f_kind, s.f_params, strict=True)
        loads = np.array([evaluate_flat(int(a), p, t)[0] for a, p in laws])
        return -self.W @ rest + self.WB @ loads

    def run(self, y0, T: float, steps: int, periods: int) -> np.ndarray:
        h = T / steps
        z = h * self.lam
        E, E2 = np.exp(z), np.exp(z / 2)
        Q = h * (E2 - 1) / z
        f1 = h * (-4 - z + E * (4 - 3 * z + z * z)) / z**3
        f2 = h * (2 + z + E * (z - 2)) / z**3
        f3 = h * (-4 - 3 * z - z * z + E * (4 - z)) / z**3
        v, t, out = self.Vi @ y0, 0.0, []
        for _ in range(periods):
            out.append((self.V @ v).real)
            for _ in range(steps):
                Nv = self.N(v, t)
                a = E2 * v + Q * Nv
                Na = self.N(a, t + h / 2)
                b = E2 * v + Q * Na
                Nb = self.N(b, t + h / 2)
                c = E2 * a + Q * (2 * Nb - Nv)
                Nc = self.N(c, t + h)
                v = E * v + f1 * Nv + 2 * f2 * (Na + Nb) + f3 * Nc
                t += h
        out.append((self.V @ v).real)
        return np.array(out)


def main() -> None:
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")  # fmt: skip
    print("| case | values x periods | steps/period | RK4 every period (s) | maps (s) | "
          "speed-up | largest difference |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    bundled = Evaluator  # the systems of benchmarks/bifurcation.py
    d = load_design(example_dir() / "nutation_double_sided.toml")
    ev = bundled(d, build_model(d), (resolve(d, build_model(d), "mesh1.stiffness"),))
    from reducerlab.dynamics.coordinates import to_system

    plain = [to_system(ev.model_at([v])) for v in np.linspace(1.5e8, 3e8, 100)]
    maps_against_rk4("bundled (constant stiffness, no load)", plain, 600, None)
    maps_against_rk4("loaded, time-varying, backlash", members_of(SETS + LOADS, 16), 300,
                     COMMON)  # fmt: skip
    s = system()
    T = forcing_period(s)
    y0 = static_states([s])
    ref = ensemble([s], periods=PERIODS, keep=PERIODS, y0=y0, steps_per_period=2640).poincare[0]
    scale = state_bounds([s], y0, np.array([T]), factor=1.0)[0]
    sl = slice(PERIODS - KEEP, PERIODS)

    def err(P: np.ndarray) -> float:
        return float(np.max(np.abs(P[sl] - ref[sl]) / scale))

    auto = ensemble([s], periods=PERIODS, keep=PERIODS, y0=y0)
    print(f"default RK4 step count (accuracy 1e-6): {auto.steps_per_period}; "
          f"error {err(auto.poincare[0]):.1e}")  # fmt: skip
    print("| integrator | steps/period | error | time per period (ms, one member) |")
    print("|---|---|---|---|")
    for n in (64, 128, 330, 660):
        t = time.perf_counter()
        P = ensemble([s], periods=PERIODS, keep=PERIODS, y0=y0, steps_per_period=n).poincare[0]
        ms = 1e3 * (time.perf_counter() - t) / PERIODS
        print(f"| RK4 kernel | {n} | {err(P):.1e} | {ms:.2f} |")
    etd = ETD4(s)
    print(f"(ETD eigenbasis: condition number {np.linalg.cond(etd.V):.1e})")
    for n in (32, 64, 128, 256):
        t = time.perf_counter()
        P = etd.run(y0[0], T, n, PERIODS)
        ms = 1e3 * (time.perf_counter() - t) / PERIODS
        print(f"| ETDRK4 numpy prototype | {n} | {err(P):.1e} | {ms:.1f} (Python) |")


if __name__ == "__main__":
    main()
