"""Modal analysis against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import chain
from reducerlab.analysis.modal import modal
from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir
from reducerlab.model import Centripetal, Dof, Inertia, Mesh, Model, Support

# eigh on a well-conditioned 2..6 DOF problem is accurate to ~1e-14 relative; 1e-10
# leaves room for the conditioning of the examples without hiding a wrong formula.
RTOL = 1e-10


def test_torsional_gear_pair_closed_form(pair):
    # omega^2 = k (r1^2/J1 + r2^2/J2)
    J1, J2, r1, r2, k = 2.0e-3, 5.0e-2, 0.03, 0.09, 3.0e8
    res = modal(pair)
    expected = math.sqrt(k * (r1**2 / J1 + r2**2 / J2)) / (2 * math.pi)
    assert res.frequencies[0] == 0.0  # rigid rotation reported exactly
    assert res.frequencies[1] == pytest.approx(expected, rel=RTOL)
    # rigid mode: r1 theta1 + r2 theta2 = 0
    phi = res.shapes[:, 0]
    assert r1 * phi[0] + r2 * phi[1] == pytest.approx(0.0, abs=1e-12)
    assert res.classifications[1].startswith("torsional")


def test_three_mass_free_chain():
    # free-free m-k-m-k-m: lambda = 0, k/m, 3k/m
    m, k = 1.7, 4.2e6
    res = modal(chain([m, m, m], [k, k]))
    lam = res.data["eigenvalue"].values
    assert lam[0] == 0.0
    assert lam[1:] == pytest.approx([k / m, 3 * k / m], rel=RTOL)
    # mode 2 is antisymmetric with a still middle mass
    assert res.shapes[1, 1] == pytest.approx(0.0, abs=1e-9)


def test_three_mass_grounded_chain():
    # ground-k-m-k-m-k-m (last free): lambda = (k/m) * 2(1 - cos((2j-1) pi / 7)), j=1..3
    m, k = 0.9, 1.0e6
    res = modal(chain([m, m, m], [k, k], grounded=True))
    j = np.arange(1, 4)
    expected = (k / m) * 2 * (1 - np.cos((2 * j - 1) * np.pi / 7))
    assert res.data["eigenvalue"].values == pytest.approx(expected, rel=RTOL)


def test_rigid_body_count_of_free_gear_pair():
    # two planar gears (x, y, rz each) joined only by one mesh: K has rank 1,
    # so 5 rigid-body modes at exactly 0 Hz
    dofs = [Dof(b, k) for b in ("p", "g") for k in ("x", "y", "rz")]
    els = [Inertia(d.name, 1.0 if d.kind != "rz" else 1e-3) for d in dofs]
    els.append(
        Mesh(
            {"p.x": 0.34, "p.y": 0.94, "p.rz": 0.03, "g.x": -0.34, "g.y": -0.94, "g.rz": 0.06},
            stiffness=2e8,
        )
    )
    res = modal(Model(dofs, els))
    assert int(res.data["rigid"].sum()) == 5
    assert np.all(res.frequencies[:5] == 0.0)
    assert res.frequencies[5] > 0


def test_equivalent_linear_displacement_uses_J_over_r2():
    # a rotation written as u = r theta: mass J/r^2, spring to ground k_u on u
    J, r, k = 3e-3, 0.05, 1e7
    m = Model([Dof("disc", "u", radius=r)], [Inertia("disc.u", J), Support("disc.u", k)])
    res = modal(m)
    assert res.data["eigenvalue"].values[0] == pytest.approx(k * r**2 / J, rel=RTOL)


def test_centripetal_softening_and_divergence():
    # m x'' + (k - m Omega^2) x = 0 in a frame rotating at Omega
    m_, k = 2.0, 8.0e4
    base = [Dof("b", "x")]
    els = [Inertia("b.x", m_), Support("b.x", k), Centripetal("b.x", m_)]
    slow = modal(Model(base, els, speed=100.0))
    assert slow.data["eigenvalue"].values[0] == pytest.approx(k / m_ - 100.0**2, rel=RTOL)
    fast = modal(Model(base, els, speed=300.0))  # Omega^2 = 9e4 > k/m = 4e4
    lam = fast.data["eigenvalue"].values[0]
    assert lam == pytest.approx(k / m_ - 300.0**2, rel=RTOL)
    assert lam < 0  # reported, not clipped
    assert fast.frequencies[0] == pytest.approx(-math.sqrt(-lam) / (2 * math.pi), rel=RTOL)
    assert bool(fast.data["unstable"].values[0])
    assert fast.classifications[0].startswith("divergent")


def test_gear_pair_example_tends_to_torsional_formula_with_rigid_bearings():
    design = load_design(example_dir() / "gear_pair.toml")
    stiff = design.model_copy(
        update={
            "pinion": design.pinion.model_copy(
                update={
                    "bearing": design.pinion.bearing.model_copy(
                        update={"stiffness_x": 1e16, "stiffness_y": 1e16}
                    )
                }
            ),
            "gear": design.gear.model_copy(
                update={
                    "bearing": design.gear.bearing.model_copy(
                        update={"stiffness_x": 1e16, "stiffness_y": 1e16}
                    )
                }
            ),
        }
    )
    res = modal(build_model(stiff), rigid_tol=1e-14)
    rp, rg = stiff.base_radius("pinion"), stiff.base_radius("gear")
    k = stiff.mesh.stiffness
    f = math.sqrt(
        k * (rp**2 / stiff.pinion.moment_of_inertia + rg**2 / stiff.gear.moment_of_inertia)
    )
    f /= 2 * math.pi
    torsional = [
        fr for fr, c in zip(res.frequencies, res.classifications, strict=True) if "torsional" in c
    ]
    # bearings 1e16 N/m vs mesh 3.8e8 N/m: the coupling correction is ~k_mesh/k_bearing
    assert any(abs(fr / f - 1) < 1e-6 for fr in torsional)


def test_massless_dof_is_a_clear_error():
    from reducerlab.errors import ModelError

    m = Model([Dof("a", "x"), Dof("b", "x")], [Inertia("a.x", 1.0), Support("b.x", 1.0)])
    with pytest.raises(ModelError, match=r"b\.x.*no inertia"):
        modal(m)
