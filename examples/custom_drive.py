"""Compose a drive that no builder knows, from reducerlab's core elements alone.

A motor drives a pinion through a flexible coupling; the pinion meshes with a gear
whose rotation is written as an equivalent linear displacement ``u = r theta`` (the
way papers 003 and 004 write their models); the gear rides on a carrier that spins with
the input, so its radial DOF feels the centripetal softening ``-m Omega^2``; the output
shaft ties the gear to a load inertia. Run it with ``python examples/custom_drive.py``.
"""

from __future__ import annotations

import math

from reducerlab.analysis.modal import frequency_sensitivity, modal
from reducerlab.model import (
    Backlash,
    Centripetal,
    Coupling,
    Dof,
    Fourier,
    Inertia,
    Load,
    Mesh,
    Model,
    Support,
)


def build(speed_rpm: float = 3000.0) -> Model:
    """The custom drive at an input speed (rpm)."""
    omega = speed_rpm * 2 * math.pi / 60  # rad/s, SI inside
    r_pinion, r_gear = 0.012, 0.045  # base radii (m)
    z_pinion = 16
    dofs = [
        Dof("motor", "rz"),
        Dof("pinion", "rz"),
        Dof("gear", "u", radius=r_gear),  # u = r_gear * theta_gear
        Dof("gear", "x"),  # radial, in the carrier frame
        Dof("load", "rz"),
    ]
    elements = [
        Inertia("motor.rz", 4.0e-4),  # kg m^2
        Inertia("pinion.rz", 6.0e-5),
        Inertia("gear.u", 2.2e-3),  # a moment of inertia: J / r^2 is applied for u
        Inertia("gear.x", 0.9),  # kg
        Inertia("load.rz", 8.0e-3),
        Coupling({"motor.rz": 1.0, "pinion.rz": -1.0}, 2.5e3, 0.05, name="coupling"),
        Mesh(
            # delta = r_p theta_p + u_g + sin(20 deg) x_g  (m)
            {"pinion.rz": r_pinion, "gear.u": 1.0, "gear.x": math.sin(math.radians(20))},
            stiffness=Fourier(
                mean=2.4e8, amplitudes=(3.0e7, 8.0e6), phases=(0.0, 0.5), omega=z_pinion * omega
            ),
            damping=400.0,
            backlash=Backlash.full(60e-6),
            name="mesh",
        ),
        Support("gear.x", 3.0e8, 800.0, name="carrier_bearing"),
        Centripetal("gear.x", 0.9),
        # output shaft on the gear's rotation: its stretch theta_g - theta_l is
        # (1 / r_gear) u_g - theta_l (rad)
        Coupling({"gear.u": 1 / r_gear, "load.rz": -1.0}, 1.8e4, 0.2, name="output_shaft"),
        Load("motor.rz", 2.0, name="motor_torque"),  # N m
        Load("load.rz", -2.0 * r_gear / r_pinion, name="load_torque"),
    ]
    return Model(dofs, elements, speed=omega, name="custom motor-pinion-gear-load drive")


def main() -> None:
    model = build()
    result = modal(model)
    print(result.table())
    sens = frequency_sensitivity(
        model, ["mesh.stiffness", "coupling.stiffness", "output_shaft.stiffness", "speed"], result
    )
    print()
    print(sens.table())


if __name__ == "__main__":
    main()
