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
from reducerlab.drives.nutation import _lever, contact_normal
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


def test_lever_arm_matches_the_torsional_coefficient():
    """The tilt lever ``p x n`` uses the same contact point as paper 000 Eq. 2's
    torsional term: its axial component would be ``r_m n_y``; and it is normal to n."""
    d, b, a, R = math.radians(80.0), math.radians(25.0), math.radians(24.0), 0.05
    gx, gy = _lever(d, b, a, R)
    n = np.array(contact_normal(d, b, a))
    p = R * np.array([math.sin(d), 0.0, math.cos(d)])
    lever = np.cross(p, n)
    np.testing.assert_allclose([gx, gy], lever[:2], rtol=1e-14)
    assert lever[2] == pytest.approx(R * math.sin(d) * n[1], rel=1e-14)


def test_rotating_frame_needs_isotropic_supports():
    with pytest.raises(DesignError, match=r"support2\.k_y"):
        rl.load_design(NUT, ["rotating_frame=true", "support2.k_y=2.0e8 N/m"])


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
    from reducerlab.analysis.campbell import resonance_check

    paper = resonance_check(rl.load_design(CYC))
    assert paper["frequencies"] == "undamped"
    report = resonance_check(rl.load_design("examples/spinning_disc.toml"))
    assert report["frequencies"].startswith("complex")
    assert report["crossings"] and all("whirl" in c for c in report["crossings"])
    assert "backward" in {c["whirl"] for c in report["crossings"]}
    cyc = resonance_check(rl.load_design(CYC, ["coriolis=true"]))
    assert cyc["frequencies"].startswith("complex")
    assert cyc["stability"]["least_damped"]["damping_ratio"] == 0.0  # undamped design
