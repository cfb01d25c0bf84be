"""Bevel pairs rated on their virtual cylindrical gears (ISO 10300-1:2014 virtual gears,
ISO 6336-2/-3:2019 method B): limits and relations that the virtual gears must keep.

* ISO 10300-1: for a shaft angle of 90 deg the virtual pair's ratio is ``u_v = u^2``
  (``d_v = d_m / cos(delta)``, ``tan(delta_1) = 1 / u``).
* As the pitch cones flatten (``delta -> 0``) a bevel gear becomes a cylindrical gear: a
  straight bevel pair then rates exactly as the spur pair of the same teeth (external)
  or as the internal spur pair (internal), through independent code paths
  (``rate_spur_pair`` builds the generated SpurGear teeth, ``rate_internal_pair`` the
  InternalGearPair).
"""

from __future__ import annotations

import math

import pytest

from reducerlab.analysis.rating import load_capacity
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.geometry.internal_pair import InternalGearPair
from reducerlab.geometry.spur import SpurGear, SpurPair
from reducerlab.rating.bevel import rate_bevel_pair, virtual_pair
from reducerlab.rating.cylindrical import rate_internal_pair, rate_spur_pair

M, B, A = 0.003, 0.02, math.radians(20.0)
FLAT = 1e-7  # rad: a pitch cone this flat is a cylinder to 1e-14 (1 - cos)


def test_ratio_of_the_virtual_pair_at_ninety_degrees():
    u = 2.5
    d1 = math.atan(1 / u)
    v = virtual_pair(
        teeth=(20, 50), mean_radii=(0.03, 0.075), cone_angles=(d1, math.pi / 2 - d1),
        normal_module=M, spiral_angle=0.0, pressure_angle=A, internal=False,
    )  # fmt: skip
    assert v["d_v2"] / v["d_v1"] == pytest.approx(u**2, rel=1e-12)
    assert v["z_v2"] / v["z_v1"] == pytest.approx(u**2, rel=1e-12)


@pytest.mark.parametrize("internal", [False, True])
def test_flat_cones_rate_as_the_cylindrical_pair(internal):
    # 30 in 80 internal: a feasible unshifted internal pair with eps_alpha = 1.94 < 2
    z1, z2 = (30, 80) if internal else (20, 40)
    common = dict(
        teeth=(z1, z2), mean_radii=(M * z1 / 2, M * z2 / 2), cone_angles=(FLAT, FLAT),
        normal_module=M, spiral_angle=0.0, pressure_angle=A, face_width=B, torque=80.0,
        speed=150.0, internal=internal,
    )  # fmt: skip
    bevel = rate_bevel_pair(**common)
    if internal:
        ref = rate_internal_pair(InternalGearPair(z1, z2, M, 0.0, 0.0, face_width=B), 80.0, 150.0)
    else:
        ref = rate_spur_pair(SpurPair(SpurGear(z1, M, B), SpurGear(z2, M, B)), 80.0, 150.0)
    # the same equations on the same numbers: agreement to rounding
    for k in range(2):
        assert bevel.S_H[k] == pytest.approx(ref.S_H[k], rel=1e-12)
        assert bevel.S_F[k] == pytest.approx(ref.S_F[k], rel=1e-12)
    for sym in ("Y_F", "Y_S", "h_Fe", "s_Fn", "rho_F"):
        for g in ("1", "2"):
            assert bevel.value(sym, g) == pytest.approx(ref.value(sym, g), rel=1e-12)
    assert "not ISO 10300 method B1" in bevel.standard


def test_outside_the_scope_of_iso_10300_refused():
    # ISO 10300-2:2014 scope: virtual transverse contact ratio below 2 (the internal
    # 20 in 40 pair has 2.15)
    with pytest.raises(ReducerlabError, match="ISO 10300-2:2014 scope"):
        rate_bevel_pair(
            teeth=(20, 40), mean_radii=(M * 10, M * 20), cone_angles=(FLAT, FLAT),
            normal_module=M, spiral_angle=0.0, pressure_angle=A, face_width=B, torque=80.0,
            speed=150.0, internal=True,
        )  # fmt: skip


def test_nutation_design_rated_and_double_arc_refused():
    d = load_design(example_dir() / "nutation_surface.toml")
    r = load_capacity(d)
    p = r.pairs()["pair 1"]
    assert p["gears"] == ["gear 2", "gear 1"]
    # the torque flow's 1942 N on the external gear's mean radius (mesh1's force)
    assert r.value("F_t") == pytest.approx(55.714285714 / 0.0286878, rel=1e-9)
    assert r.value("Z_D", "2") == 1.0
    assert all(s > 1 for s in p["S_H"] + p["S_F"])
    arcs = d.with_values({"surface.profile": "double-arc"})
    with pytest.raises(ReducerlabError, match=r"surface\.profile: .*method A"):
        load_capacity(arcs, method="B")  # method A (the default "auto"): test_rating_ltca
    # a torque on the input shaft: the flow's output is i times it
    half = load_capacity(d, torque=60.0 / abs(d.kinematics().ratio) / 2)
    assert half.value("F_t") == pytest.approx(r.value("F_t") / 2, rel=1e-9)


def test_rating_limits_are_no_input_of_the_body_and_contact_results():
    # sigma_Hlim, sigma_Flim and the treatment do not change a gear body's modes or the
    # loaded contact: cached results stay valid when only the limits change
    import json

    from reducerlab.inputs import inputs_of

    d = load_design(example_dir() / "nutation_surface.toml")
    dump = json.loads(d.provenance["design"])
    for kind, attrs in (("body-modal", {"gear": 1}), ("contact", {"pair": 1})):
        rec = inputs_of(kind, dump, attrs)
        assert "material.youngs_modulus" in rec and "material.density" in rec
        assert not any(k.startswith(("material.sigma", "material.treatment")) for k in rec)
