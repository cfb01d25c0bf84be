"""Gyroscopic, Coriolis and circulatory terms in the drives of papers 000 and 003
(issue 17): the nutating gear's tilts and steady precession, the turning mesh frame,
and the cycloid ball drive completed in its rotating frame.

Oracles: the paper models themselves (the new terms vanish at zero speed and leave the
papers' frequencies where the added DOFs do not couple), the spinning-body whirl rule
(a gyroscopic pair splits into a forward and a backward branch, Friswell et al. 2010,
Sec. 3.4) and the geometry of the contact normal (paper 000 Eq. 2 and 4).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import reducerlab as rl
from reducerlab.analysis.complex_modal import complex_modes
from reducerlab.analysis.modal import modal
from reducerlab.drives.nutation_mesh import contact_normal, contact_point, tilt_lever
from reducerlab.errors import DesignError

NUT = "examples/nutation_double_sided.toml"
CYC = "examples/cycloid_ball.toml"
TILT = ["tilt13.k_rx=7.65e4 N*m/rad", "tilt13.k_ry=7.65e4 N*m/rad"]


def _model(path: str, overrides=()):
    return rl.build_model(rl.load_design(path, list(overrides)))


def _tilt_modes(result, model) -> list[int]:
    """Modes whose kinetic energy is mostly in the nutating gear's tilts."""
    names = list(result.data.dof.values)
    i = [names.index("g13.rx"), names.index("g13.ry")]
    shapes = result.data.shape_real.values + 1j * result.data.shape_imag.values
    energy = np.diag(model.matrices().M)[:, None] * np.abs(shapes) ** 2
    share = energy[i].sum(axis=0) / energy.sum(axis=0)
    return [j for j in range(share.size) if share[j] > 0.5]


def test_paper_model_is_unchanged_by_default():
    m = _model(NUT)
    assert m.n == 12 and not any(n.endswith((".rx", ".ry")) for n in m.dof_names)


def test_tilted_nutating_gear_whirls_forward_and_backward():
    """Without gyroscopic terms the two tilting modes are planar; with the steady
    precession they split into one forward and one backward whirl, and the split grows
    with speed."""
    mp, mg = _model(NUT, [*TILT, "gyroscopic=false"]), _model(NUT, TILT)
    plain, gyro = complex_modes(mp), complex_modes(mg)
    tp, tg = _tilt_modes(plain, mp), _tilt_modes(gyro, mg)
    assert len(tp) == len(tg) == 2
    assert set(plain.data.whirl.values[tp]) == {"planar"}
    assert sorted(gyro.data.whirl.values[tg]) == ["backward", "forward"]
    mf = _model(NUT, [*TILT, "input_speed=6000 rpm"])
    fast = complex_modes(mf)
    split = [np.ptp(r.frequencies[_tilt_modes(r, m)]) for r, m in ((gyro, mg), (fast, mf))]
    assert split[1] > split[0]


def test_tilt_terms_vanish_at_rest():
    """At zero speed the gyroscopic and frame terms are zero: complex modes of the full
    model equal those of the model without them (damping the same)."""
    full = _model(NUT, [*TILT, "rotating_frame=true"]).with_speed(0.0)
    bare = _model(NUT, [*TILT, "gyroscopic=false"]).with_speed(0.0)
    np.testing.assert_allclose(complex_modes(full).frequencies, complex_modes(bare).frequencies,
                               rtol=1e-10)  # fmt: skip


def test_lever_acts_at_the_contact_point_of_both_cones():
    """The tilt lever ``p x n`` uses the pair's mean contact point: turned into the mesh
    frame (R_y(theta)) it is the central gear's mean pitch point, on its pitch cone at the
    common cone distance (paper 000 Eq. 4's frames; apex at the nutation centre)."""
    d = rl.load_design(NUT)
    th = d.theta
    R = d.cone_distances(th)[1]
    for dn, dc in d.cones(th):
        p = np.array(contact_point(dc, th, R))
        c, s_ = math.cos(th), math.sin(th)
        mesh = np.array([c * p[0] + s_ * p[2], 0.0, -s_ * p[0] + c * p[2]])
        assert np.linalg.norm(mesh) == pytest.approx(R, rel=1e-14)
        assert math.atan2(mesh[0], mesh[2]) == pytest.approx(dc, rel=1e-14)
        b, a = d.helix_angle, d.normal_pressure_angle
        lever = np.cross(p, contact_normal(dn, b, a))
        np.testing.assert_allclose(tilt_lever(dn, dc, b, a, th, R), lever[:2], rtol=1e-14)


def test_tilt_inertia_is_about_the_nutation_centre():
    """By default the gears' own J_x, J_y gain their parallel-axis terms (the tilts turn
    about the nutation centre); given J_x, J_y are used as they are."""
    m = _model(NUT, TILT)
    own = sum(rl.load_design(NUT).model_dump()[g]["J_x"] for g in ("gear1", "gear3"))
    J = m.matrices().M[m.index["g13.rx"], m.index["g13.rx"]]
    assert 1.5 * own < J  # the gears' mass lies ~30 mm from the centre
    given = _model(NUT, [*TILT, "tilt13.J_x=2e-3 kg*m^2", "tilt13.J_y=2e-3 kg*m^2"])
    assert given.matrices().M[given.index["g13.rx"], given.index["g13.rx"]] == 2e-3


def test_rotating_frame_needs_isotropic_housing_supports():
    with pytest.raises(DesignError, match=r"support2\.k_y"):
        rl.load_design(NUT, ["rotating_frame=true", "support2.k_y=2.0e8 N/m"])
    # the nutating gear's bearings turn with the crank: no restriction
    rl.load_design(NUT, ["rotating_frame=true", "support13.k_y=2.0e8 N/m"])
    with pytest.raises(DesignError, match="centripetal"):
        rl.load_design(CYC, ["coriolis=true", "centripetal=false"])


def test_cycloid_rotating_frame_keeps_paper_frequencies():
    """The added y DOFs couple to paper 003's x and u only through Coriolis and
    circulatory terms, which undamped modal analysis leaves out: its frequencies are the
    paper model's plus those of the y system (1e-9: two eigen-solves of the same
    blocks)."""
    paper = modal(_model(CYC)).frequencies
    full = modal(_model(CYC, ["coriolis=true"]))
    assert full.data.attrs["skew_velocity_terms"] == 1
    f = full.frequencies
    for x in paper[1:]:
        assert np.min(np.abs(f - x)) <= 1e-9 * x
    c = complex_modes(_model(CYC, ["coriolis=true"]))
    whirls = set(c.data.whirl.values)
    assert {"forward", "backward"} <= whirls
    assert c.data.stable.values.all()


def test_resonance_check_uses_complex_branches_with_speed_terms():
    """With Coriolis terms the verdict is taken on the damped, whirl-split frequencies
    and its crossings carry their whirl; the paper model keeps the undamped ones."""
    from reducerlab.analysis.resonance import resonance_check

    paper = resonance_check(rl.load_design(CYC))
    assert paper["frequencies"] == "undamped"
    report = resonance_check(rl.load_design("examples/spinning_disc.toml"))
    assert report["frequencies"].startswith("complex")
    assert report["crossings"] and all("whirl" in c for c in report["crossings"])
    assert "backward" in {c["whirl"] for c in report["crossings"]}
    cyc = resonance_check(rl.load_design(CYC, ["coriolis=true"]))
    assert cyc["frequencies"].startswith("complex")
    assert cyc["stability"]["least_damped"]["damping_ratio"] == 0.0  # undamped design


def test_cycloid_housing_bearing_damping_turns_circulatory_in_the_rotating_frame():
    """With damped housing bearings the rotating-frame model carries their circulatory
    terms (and only theirs: the planetary disc's eccentric bearing turns with the
    frame); the damped modes stay stable and decay as the fixed-frame damper says at
    rest (the terms vanish at zero speed)."""
    fields = ("input_shaft.radial", "centre_disc.radial", "planetary_disc.bearing")
    sets = ["coriolis=true"] + [f"{f}_damping=800 N*s/m" for f in fields]
    m = _model(CYC, sets)
    names = {e.name for e in m.elements if e.name.startswith("stationary_damping")}
    assert names == {"stationary_damping_input_shaft", "stationary_damping_centre_disc"}
    c = complex_modes(m)
    assert c.data.stable.values.all() and c.data.damping_ratio.values[1:].min() > 0
    rest = complex_modes(m.with_speed(0.0)).frequencies
    bare = m.__class__(m.dofs, [e for e in m.elements if not e.name.startswith(
        ("coriolis", "stationary"))], speed=0.0)  # fmt: skip
    np.testing.assert_allclose(rest, complex_modes(bare).frequencies, rtol=1e-10)
