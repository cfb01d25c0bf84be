"""A hand-written SIMD RK4 kernel of the KHV drive, against the package kernel (issue 28).

The reference integrates the same model as ``benchmarks/bifurcation.py`` (the KHV drive
over ``gears.x1``, its flat :class:`~reducerlab.model.NonlinearSystem` arrays after
rigid-motion removal: the same ``M^-1 K``, ``M^-1 C``, ``M^-1 G^T``, backlash dead zone,
line damping, the law table of :func:`reducerlab.dynamics.kernel_laws.tabulate` built
once per block) the fastest straightforward way for SIMD: numba
``njit(parallel=True, fastmath=True)``, blocks of 64 members, members innermost and
contiguous, the model size a compile-time constant (the RK4 step is generated as
straight-line code for the given ``n`` and ``L``: every state component, stage and force
a scalar local that stays in a register within a member's step), fixed steps, **no
crossing location** and no divergence check.

FLOPs per member-step are counted the same way for both kernels
(:func:`bifurcation.flops_per_trajectory` per step, which is the package's count: the
right-hand side ``4 n^2 + L (4 n + 10 + 2 n)``, four of them, ``3 x 2 (2n)`` for the
stage states, ``8 (2n)`` for the update and ``2 (2n)`` for the divergence check, which
the reference does not do and is not counted for it). The reference's count is also
checked against its generated source (every binary ``+ - *`` and every ``min``/``max``
of the step body counts one): printed as "source count".

Checks: on the KHV drive without backlash (no contact change anywhere, so the package
does no location) both kernels give the same Poincaré points to ``1e-9`` relative with
the same steps; with backlash the two differ by the reference's first-order error at
the kinks (printed, not asserted).

Timing: both kernels side by side, interleaved, best of ``REPEAT``, on 2 threads, 1000
members x 600 periods x 32 steps (the bifurcation benchmark's run), load average before
and after; the wall time and the CPU time of all threads (the machine is shared: the
CPU time is less disturbed by other processes than the wall time); and the package
kernel on the same members with the backlash removed (no contact change, nothing to
locate: the cost of its step alone).
Run: ``.venv/bin/python benchmarks/simd_reference.py [N_VALUES]``.
"""

from __future__ import annotations

import ast
import datetime as dt
import os
import platform
import sys
import time
from pathlib import Path

import numba as nb
import numpy as np

from reducerlab.dynamics.coordinates import static_state
from reducerlab.dynamics.kernel import rk4_ensemble
from reducerlab.dynamics.kernel_laws import tabulate
from reducerlab.dynamics.prepare import linear_lines, prepare

sys.path.insert(0, os.path.dirname(__file__))
from bifurcation import flops_per_trajectory, systems_for

PERIODS, KEEP, REPEAT, BLOCK = 600, 100, 5, 64


def step_source(n: int, L: int) -> str:
    """Straight-line source of one RK4 step of member ``b`` (its state ``y_0 ..
    y_{2n-1}`` in locals, the law rows ``r, r + 1, r + 2`` of ``tab``). Every array is
    read through a flat view with literal offsets (row ``k`` of a block array at
    ``k * BLOCK + b``), so that the compiler knows that the rows of ``Y`` it reads and
    writes do not overlap, and vectorises the member loop."""
    out: list[str] = []
    W = 3 * L + n

    def at(name: str, k: int) -> str:
        return f"{name}f[{k * BLOCK} + b]"

    def tab(row: str, col: int) -> str:
        return f"tf[(({row}) * {W} + {col}) * {BLOCK} + b]"

    def rhs(row: str, y: list[str], k: str) -> None:
        q, v = y[:n], y[n:]
        fm = []
        for m in range(L):
            d = " + ".join(f"{at('G', m * n + i)} * {q[i]}" for i in range(n))
            w = " + ".join(f"{at('G', m * n + i)} * {v[i]}" for i in range(n))
            out.append(f"d_{m} = {d} - {tab(row, L + m)}")
            out.append(f"w_{m} = {w} - {tab(row, 2 * L + m)}")
            out.append(f"f_{m} = d_{m} - min(max(d_{m}, -{at('H', m)}), {at('H', m)})")
            out.append(f"g_{m} = {tab(row, m)} * f_{m} + {at('CM', m)} * w_{m}")
            fm.append(f"g_{m}")
        for i in range(n):
            out.append(f"{k}_{i} = {v[i]}")
        for i in range(n):
            terms = [f"{at('MK', i * n + j)} * {q[j]} + {at('MC', i * n + j)} * {v[j]}"
                     for j in range(n)]  # fmt: skip
            terms += [f"{at('MG', i * L + m)} * {fm[m]}" for m in range(L)]
            out.append(f"{k}_{n + i} = {tab(row, 3 * L + i)} - ({' + '.join(terms)})")

    n2 = 2 * n
    y = [f"y_{i}" for i in range(n2)]
    out.append("h = dtb[q, b]")
    out.append("hh = 0.5 * h")
    out += [f"y_{i} = {at('Y', i)}" for i in range(n2)]
    rhs("r", y, "a")
    out += [f"s_{i} = y_{i} + hh * a_{i}" for i in range(n2)]
    rhs("r + 1", [f"s_{i}" for i in range(n2)], "c")
    out += [f"s_{i} = y_{i} + hh * c_{i}" for i in range(n2)]
    rhs("r + 1", [f"s_{i}" for i in range(n2)], "e")
    out += [f"s_{i} = y_{i} + h * e_{i}" for i in range(n2)]
    rhs("r + 2", [f"s_{i}" for i in range(n2)], "k")
    out += [
        f"{at('Y', i)} = y_{i} + (h / 6.0) * (a_{i} + 2.0 * c_{i} + 2.0 * e_{i} + k_{i})"
        for i in range(n2)
    ]
    return "\n".join(out)


def source_flops(n: int, L: int) -> int:
    """Floating-point operations of the generated step: every binary ``+ - * /`` and
    every ``min``/``max`` outside an index (the ``0.5 * h`` and ``h / 6.0`` per member
    and step included)."""

    class Count(ast.NodeVisitor):
        flops = 0

        def visit_Subscript(self, node: ast.Subscript) -> None:
            pass  # index arithmetic is no flop

        def visit_BinOp(self, node: ast.BinOp) -> None:
            self.flops += 1
            self.generic_visit(node)

        def visit_Call(self, node: ast.Call) -> None:
            self.flops += getattr(node.func, "id", "") in ("min", "max")
            self.generic_visit(node)

        def visit_UnaryOp(self, node: ast.UnaryOp) -> None:
            self.flops += 1
            self.generic_visit(node)

    counter = Count()
    counter.visit(ast.parse(step_source(n, L)))
    return counter.flops


def make_reference(n: int, L: int):
    """Compile the reference for ``n`` DOFs and ``L`` lines; returns ``run(prep, Y0,
    periods, keep)`` giving the Poincaré states (E, keep + 1, 2n)."""
    body = "\n".join(" " * 20 + line for line in step_source(n, L).splitlines())
    src = f"""
def kernel(MKa, MCa, MGa, Ga, Ha, CMa, k_kind, k_par, e_kind, e_par, MB, f_kind, f_par,
           Y0, period, offs, dts, periods, keep):
    E = Y0.shape[0]
    N = offs.shape[1]
    out = np.full((E, keep + 1, {2 * n}), np.nan)
    nblk = (E + {BLOCK} - 1) // {BLOCK}
    for blk in nb.prange(nblk):
        lo = blk * {BLOCK}
        hi = min(E, lo + {BLOCK})
        MK = np.empty(({n * n}, {BLOCK}))
        MC = np.empty(({n * n}, {BLOCK}))
        MG = np.empty(({n * L}, {BLOCK}))
        G = np.empty(({L * n}, {BLOCK}))
        H = np.empty(({L}, {BLOCK}))
        CM = np.empty(({L}, {BLOCK}))
        Y = np.empty(({2 * n}, {BLOCK}))
        dtb = np.empty((N, {BLOCK}))
        for b in range({BLOCK}):
            e = min(lo + b, hi - 1)
            for i in range({n * n}):
                MK[i, b] = MKa[e, i]
                MC[i, b] = MCa[e, i]
            for i in range({n * L}):
                MG[i, b] = MGa[e, i]
                G[i, b] = Ga[e, i]
            for m in range({L}):
                H[m, b] = Ha[e, m]
                CM[m, b] = CMa[e, m]
            for i in range({2 * n}):
                Y[i, b] = Y0[e, i]
            for q in range(N):
                dtb[q, b] = dts[e, q]
        tab = np.zeros((3 * N, {3 * L + n}, {BLOCK}))
        t_base = np.zeros(E)
        tabulate(tab, lo, hi, t_base, offs, dts, k_kind, k_par, e_kind, e_par,
                 MB[lo:hi], f_kind, f_par)
        for b in range(hi - lo, {BLOCK}):
            tab[:, :, b] = tab[:, :, hi - lo - 1]
        MKf, MCf, MGf, Gf, Hf, CMf, Yf = (MK.reshape(MK.size), MC.reshape(MC.size),
                                         MG.reshape(MG.size), G.reshape(G.size),
                                         H.reshape(H.size), CM.reshape(CM.size),
                                         Y.reshape(Y.size))
        tf = tab.reshape(tab.size)
        for p in range(periods):
            if p >= periods - keep:
                for b in range(hi - lo):
                    for i in range({2 * n}):
                        out[lo + b, p - (periods - keep), i] = Yf[i * {BLOCK} + b]
            for q in range(N):
                r = 3 * q
                for b in range({BLOCK}):
{body}
        for b in range(hi - lo):
            for i in range({2 * n}):
                out[lo + b, keep, i] = Yf[i * {BLOCK} + b]
    return out
"""
    scope = {"np": np, "nb": nb, "tabulate": tabulate}
    exec(compile(src, f"<simd_reference n={n} L={L}>", "exec"), scope)
    kernel = nb.njit(parallel=True, fastmath=True)(scope["kernel"])

    def run(prep, Y0: np.ndarray, periods: int, keep: int) -> np.ndarray:
        a = prep.arrays
        if not linear_lines(a):
            raise ValueError("the reference has no cubic or power-law line term")
        E = Y0.shape[0]
        MK = np.einsum("eij,ejk->eik", a.Minv, a.K).reshape(E, n * n)
        MC = np.einsum("eij,ejk->eik", a.Minv, a.C).reshape(E, n * n)
        MG = np.einsum("eij,emj->eim", a.Minv, a.G).reshape(E, n * L)
        MB = np.einsum("eij,ejk->eik", a.Minv, a.B)
        return kernel(MK, MC, MG, a.G.reshape(E, L * n).copy(), a.hb, a.cm, a.k_kind,
                      a.k_par, a.e_kind, a.e_par, MB, a.f_kind, a.f_par, Y0, prep.period,
                      prep.offs, prep.dts, periods, keep)  # fmt: skip

    return run, kernel


def package(prep, Y0: np.ndarray, periods: int, keep: int) -> np.ndarray:
    """The package kernel on the same members and steps (no divergence bound)."""
    E = Y0.shape[0]
    limit = np.full((E, Y0.shape[1]), np.inf)
    P, _, _, _ = rk4_ensemble(
        *prep.arrays, Y0, np.zeros(E), prep.period, prep.offs, prep.dts, prep.periodic,
        periods, keep, 0, limit, BLOCK if E >= 2 * BLOCK else 8, -1, 0.0,
    )  # fmt: skip
    return P


def timed(fn) -> tuple[float, float]:
    """Wall and CPU time (s, all threads) of one call."""
    w, c = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - w, time.process_time() - c


def main() -> None:
    n_values = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    nb.set_num_threads(min(2, nb.config.NUMBA_NUM_THREADS))
    systems = systems_for("khv.toml", "gears.x1", np.linspace(0.416, 0.835, n_values))
    prep = prepare(systems, 32, None)
    s0 = systems[0]
    n, L, N = s0.n, s0.G.shape[0], prep.steps
    Y0 = np.array([static_state(s) for s in systems])
    run, _ = make_reference(n, L)
    # agreement without backlash: no contact change, no location in the package kernel
    lin = prep.__class__(**{**prep.__dict__, "arrays": prep.arrays._replace(
        hb=np.zeros_like(prep.arrays.hb))})  # fmt: skip
    sub = slice(0, min(n_values, 128))
    few = prep.__class__(**{**lin.__dict__, "arrays": lin.arrays.__class__(
        *(x if x.ndim == 1 else x[sub] for x in lin.arrays)), "period": lin.period[sub],
        "offs": lin.offs[sub], "dts": lin.dts[sub]})  # fmt: skip
    Pr, Pp = run(few, Y0[sub], 60, 10), package(few, Y0[sub], 60, 10)
    scale = np.max(np.abs(Pp), axis=(0, 1))
    lin_err = float(np.max(np.abs(Pr - Pp) / scale))
    fews = prep.__class__(**{**few.__dict__, "arrays": few.arrays._replace(hb=prep.arrays.hb[sub])})
    Ir, Ip = run(fews, Y0[sub], 60, 10), package(fews, Y0[sub], 60, 10)
    imp_err = float(np.max(np.abs(Ir - Ip) / np.max(np.abs(Ip), axis=(0, 1))))
    # timing, interleaved: best wall time and best CPU time (other agents share the CPU)
    load0 = Path("/proc/loadavg").read_text().split()[:3]
    ref, pkg, flat = np.full(2, np.inf), np.full(2, np.inf), np.full(2, np.inf)
    for _ in range(REPEAT):
        ref = np.minimum(ref, timed(lambda: run(prep, Y0, PERIODS, KEEP)))
        pkg = np.minimum(pkg, timed(lambda: package(prep, Y0, PERIODS, KEEP)))
        flat = np.minimum(flat, timed(lambda: package(lin, Y0, PERIODS, KEEP)))
    load1 = Path("/proc/loadavg").read_text().split()[:3]
    t_ref, t_pkg = ref[0], pkg[0]
    member_steps = n_values * PERIODS * N
    per_step = flops_per_trajectory(s0, N) / (PERIODS * N)
    f_pkg = per_step
    f_ref = per_step - 2 * (2 * n)  # no divergence check in the reference
    g_ref = f_ref * member_steps / t_ref / 1e9
    g_pkg = f_pkg * member_steps / t_pkg / 1e9
    print(f"date: {dt.datetime.now(dt.UTC).isoformat(timespec='minutes')}")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numba {nb.__version__}, "
          f"{nb.get_num_threads()} threads")  # fmt: skip
    print(f"load average before / after: {' '.join(load0)} / {' '.join(load1)}")
    print(f"KHV drive, n = {n}, L = {L}: {n_values} members x {PERIODS} periods x {N} steps, "
          f"best of {REPEAT}, interleaved")  # fmt: skip
    print(f"agreement without backlash (60 periods, {Pr.shape[0]} members): "
          f"max relative difference {lin_err:.1e}")  # fmt: skip
    print(f"with backlash (reference: no crossing location): {imp_err:.1e}")
    print(f"flops per member-step: package {f_pkg:.0f}, reference {f_ref:.0f} "
          f"(source count {source_flops(n, L)})")  # fmt: skip
    for name, (w, c), g in (("reference", ref, g_ref), ("package", pkg, g_pkg)):
        print(f"{name:9s}: {w:.3f} s wall, {1e9 * w / member_steps:.2f} ns/member-step "
              f"(2 threads), {g:.1f} GFLOP/s; CPU {1e9 * c / member_steps:.2f} "
              f"ns/member-step")  # fmt: skip
    print(f"package without backlash (no crossing to locate, same steps): "
          f"{1e9 * flat[0] / member_steps:.2f} ns/member-step wall, "
          f"{f_pkg * member_steps / flat[0] / 1e9:.1f} GFLOP/s; CPU "
          f"{1e9 * flat[1] / member_steps:.2f} ns/member-step")  # fmt: skip
    print(f"package / reference: {100 * g_pkg / g_ref:.0f} % of the GFLOP/s (wall), "
          f"{100 * (f_pkg / pkg[1]) / (f_ref / ref[1]):.0f} % (CPU time); "
          f"{t_pkg / t_ref:.2f}x the wall time per member-step, "
          f"{pkg[1] / ref[1]:.2f}x the CPU time")  # fmt: skip


if __name__ == "__main__":
    main()
