"""How much gyroscopic, Coriolis and circulatory terms move the natural frequencies of
paper 000's nutation drive and paper 003's cycloid ball drive (issue 17).

For each drive and speed the damped frequencies of the complex modes with the speed
terms are compared with those of the same model without them (sorted elastic
frequencies side by side). Run from the repository root::

    python examples/gyroscopic_effects.py

The numbers are recorded in docs/assumptions.md ("Gyroscopic terms in the drives").
"""

from __future__ import annotations

import math

import numpy as np

import reducerlab as rl
from reducerlab.analysis.complex_modal import complex_modes

RPM = 2 * math.pi / 60
SPEEDS_RPM = np.linspace(0.0, 6000.0, 13)

#: Tilt stiffness of the nutating gear on its crank: two bearings of paper 000's radial
#: stiffness 1.7e8 N/m, 30 mm apart (k L^2 / 2); paper 000 gives no tilt stiffness.
TILT = ["tilt13.k_rx=7.65e4 N*m/rad", "tilt13.k_ry=7.65e4 N*m/rad"]


def elastic(model, speed: float) -> np.ndarray:
    r = complex_modes(model.with_speed(speed))
    return np.sort(r.frequencies[r.data.whirl.values != "rigid"])


def shifts(with_terms, without, speeds) -> np.ndarray:
    """Largest |f_with - f_without| (Hz) and relative shift at each speed."""
    out = []
    for w in speeds:
        a, b = elastic(with_terms, w), elastic(without, w)
        d = np.abs(a - b)
        out.append((d.max(), (d / b).max()))
    return np.array(out)


def report(title: str, with_terms, without, design_speed: float) -> None:
    speeds = SPEEDS_RPM * RPM
    table = shifts(with_terms, without, speeds)
    at_design = shifts(with_terms, without, [design_speed])[0]
    print(f"\n{title}")
    print(f"  design speed {design_speed / RPM:.0f} rpm: largest shift {at_design[0]:.2f} Hz "
          f"({100 * at_design[1]:.3f} %)")  # fmt: skip
    for rpm, (hz, rel) in zip(SPEEDS_RPM, table, strict=True):
        print(f"  {rpm:6.0f} rpm  {hz:8.2f} Hz  {100 * rel:7.3f} %")


def main() -> None:
    nut = "examples/nutation_double_sided.toml"
    full = rl.build_model(rl.load_design(nut, [*TILT, "rotating_frame=true"]))
    plain = rl.build_model(rl.load_design(nut, [*TILT, "gyroscopic=false"]))
    speed = rl.load_design(nut).input_speed
    report("nutation drive (paper 000) with tilts: nutating-body terms + mesh frame",
           full, plain, speed)  # fmt: skip
    gyro_only = rl.build_model(rl.load_design(nut, TILT))
    report("nutation drive (paper 000) with tilts: nutating-body terms (crank frame) only",
           gyro_only, plain, speed)  # fmt: skip
    paper = rl.build_model(rl.load_design(nut))
    frame = rl.build_model(rl.load_design(nut, ["rotating_frame=true"]))
    report("nutation drive (paper 000, 12 DOFs): mesh-frame Coriolis + circulatory terms",
           frame, paper, speed)  # fmt: skip
    cyc = "examples/cycloid_ball.toml"
    design = rl.load_design(cyc, ["coriolis=true"])
    model = rl.build_model(design)
    # without: the same 10 DOFs, Coriolis and circulatory terms dropped
    bare = model.__class__(
        model.dofs,
        [e for e in model.elements if not e.name.startswith(("coriolis", "stationary"))],
        speed=model.speed,
        name=model.name,
    )
    title = "cycloid ball drive (paper 003, 10 DOFs): Coriolis (undamped: no circulatory term)"
    report(title, model, bare, design.input_speed)


if __name__ == "__main__":
    main()
