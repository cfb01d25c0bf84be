"""Paper 004's KHV model on its internal pair's contact-derived k(t), beside the ISO one.

For each profile shift x1 on the paper's M-N line, the internal pair's loaded tooth
contact at the operating torque (``contact_analysis``: the planet's 50 N m of
``examples/khv.toml``) gives k(t) over a mesh cycle; the design takes its mean and
mesh harmonics (``[mesh] stiffness``, as ``reducerlab run`` does for ``stiffness =
"contact"``) and the same 4-DOF model (paper 004 Eq. 1-2) is run on it and on the
ISO 6336 law (Eq. 7-9), and on the contact's power law (``[mesh] exponent =
"contact"``: the load exponent from the contact at 0.9 of the torque, the tangent
``p k(t)``; issue 30). Printed: the mean stiffness and its first three harmonics,
the natural frequencies of both models (at the example's x1), and a coarse regime map
(input speed x x1, one row per x1: the contact's k(t) changes with x1, so each row
is its own model), ascending sweep, for both. The findings are in docs/contact.md
("The KHV model on the contact's k(t)").

Run: ``python examples/khv_contact_stiffness.py [SPEEDS] [X1 ...]`` (defaults 20
speeds from 100 to 2000 rpm, x1 = 0.416, 0.626, 0.835; 77 s on one core).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from reducerlab.analysis.contact import contact_analysis, design_with_contact
from reducerlab.analysis.modal import modal
from reducerlab.analysis.parameters import Axis, parse_values
from reducerlab.analysis.regime_map import regime_map
from reducerlab.contact.meshstiffness import fit_fourier
from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir

#: the contact grid: 24 positions, Eq. 8 to order 7 (paper 000), FE tooth elements of
#: 0.35 m (the defaults' 0.3 m moves c' by 0.2 %, tests/test_internal_ltca.py)
CONTACT = {"positions": 24, "order": 7, "tooth_size": 0.35 * 3.5e-3, "workers": 1}


def iso_harmonics(design, n: int = 240, order: int = 3) -> tuple[float, list[float]]:
    """Mean and first ``order`` harmonic amplitudes (N/m) of the ISO law over a period."""
    law = design.stiffness_law()
    t = law.period * np.arange(n) / n
    fit = fit_fourier(law(t), order)
    return fit.mean, list(fit.amplitudes)


def main(
    speeds: int = 20,
    shifts: tuple[float, ...] = (0.416, 0.626, 0.835),
    periods: int = 600,
    contact: dict | None = None,
) -> dict[str, list]:
    """Print the comparison; return ``{"iso": [...], "contact": [...], "power": [...]}``
    (the ISO law, the contact's linear k(t), the contact's power law with its load
    exponent), per x1 the model design and its regime-map row. ``contact``:
    ``contact_analysis``'s keyword arguments (default :data:`CONTACT`)."""
    base = load_design(example_dir() / "khv.toml")
    x = parse_values("input_speed", f"lin:100 rpm:2000 rpm:{speeds}")
    print(f"{'x1':>6} {'model':<8} {'k_m (N/m)':>11} {'k_1':>10} {'k_2':>10} {'k_3':>10}")
    rows: dict[str, list] = {"iso": [], "contact": [], "power": []}
    designs: dict[str, list] = {"iso": [], "contact": [], "power": []}
    for x1 in shifts:
        iso = base.with_shift(x1)
        t0 = time.perf_counter()
        torque = iso.operating_point().output_torque
        res = contact_analysis(iso, torque=torque, **(CONTACT if contact is None else contact))
        cont = design_with_contact(iso.with_values({"mesh.stiffness": "contact"}), [res])
        # the contact's power law: its load exponent, the tangent p k(t) (issue 30)
        power = design_with_contact(
            iso.with_values({"mesh.stiffness": "contact", "mesh.exponent": "contact"}), [res]
        )
        km, amps = iso_harmonics(iso)
        print(f"{x1:6.3f} {'iso':<8} {km:11.4g} " + " ".join(f"{a:10.4g}" for a in amps))
        pairs = res.data["pairs"].values
        print(f"{x1:6.3f} {'contact':<8} {res.mean_stiffness:11.4g} "
              + " ".join(f"{a:10.4g}" for a in res.harmonics()[0][:3])
              + f"   (contact {time.perf_counter() - t0:.0f} s, "
              f"pairs {pairs.min()}-{pairs.max()}, load exponent "
              f"{power.mesh.exponent:.3f})")  # fmt: skip
        if abs(x1 - base.gears.x1) < 1e-9:
            for name, d in (("iso", iso), ("contact", cont), ("power", power)):
                f = [v for v in modal(build_model(d)).frequencies if v > 1e-6]
                print(f"       natural frequencies, {name}: " + ", ".join(f"{v:.1f}" for v in f))
        for name, d in (("iso", iso), ("contact", cont), ("power", power)):
            y = Axis("gears.x1", (x1,))
            keep = min(64, periods // 2)
            rows[name].append(regime_map(d, x, y, periods=periods, keep=keep, continuation="up"))
            designs[name].append(d)
    rpm = [float(v) * 30 / np.pi for v in rows["iso"][0].data["p0"].values]
    for name, maps in rows.items():
        print(f"\nregime map, {name} k(t) (ascending sweep): motion / teeth")
        for x1, m in zip(shifts, maps, strict=True):
            lab, imp = m.labels()[0, 0], m.impacts()[0, 0]
            short = [a.replace("period-", "P").replace("quasi-periodic", "QP") for a in lab]
            cells = [f"{r:.0f}:{a}/{b.split()[0][:6]}"
                     for r, a, b in zip(rpm, short, imp, strict=True)]  # fmt: skip
            print(f"  x1 = {x1:.3f}: " + " ".join(cells))
    return {name: list(zip(designs[name], rows[name], strict=True)) for name in rows}


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    xs = tuple(float(v) for v in sys.argv[2:]) or (0.416, 0.626, 0.835)
    main(n, xs)
