"""Complex modes with damping and gyroscopic terms (issue 17, first part).

Oracles: closed forms of rotordynamics textbooks — a rigid disc on isotropic tilt
springs spinning at Omega (Friswell, Penny, Garvey and Lees, *Dynamics of Rotating
Machines*, 2010, Sec. 3.4; Genta, *Dynamics of Rotating Systems*, 2005, Ch. 4):
``omega_{b,f} = sqrt(omega_n^2 + (gamma Omega / 2)^2) -/+ gamma Omega / 2`` with
``gamma = J_p / J_d``, the higher one whirling forward; a mass on an isotropic spring
seen in a frame rotating at Omega (Coriolis and centripetal terms, the rotating-carrier
terms of Lin and Parker 1999): ``omega_n -/+ Omega``; the damped oscillator's
``omega_d = omega_n sqrt(1 - zeta^2)`` and log decrement; and the undamped modal
analysis, which complex modes must reproduce when C = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from conftest import chain
from reducerlab.analysis.complex_modal import ComplexModalResult, complex_modes
from reducerlab.analysis.modal import modal
from reducerlab.errors import ModelError
from reducerlab.model import (
    Centripetal,
    Contribution,
    Coriolis,
    Dof,
    Element,
    Gyroscopic,
    Inertia,
    Model,
    Support,
)
from reducerlab.results import Result

JD, JP, KT = 0.02, 0.03, 1e4  # kg m^2, kg m^2, N m/rad


@dataclass(frozen=True)
class NegativeDamper(Element):
    """A destabilising velocity term on ``a.x`` (Support refuses negative damping, as it
    should for user input; cross-coupled bearings or rubbing act this way)."""

    name: str = "negative damper"

    @property
    def dofs(self) -> tuple[str, ...]:
        return ("a.x",)

    def contribution(self, dofs, speed) -> Contribution:
        return Contribution(damping=np.array([[-4.0]]))


def disc(rpm: float, spin_ratio: float = 1.0) -> Model:
    return Model(
        [Dof("disc", "rx"), Dof("disc", "ry")],
        [Inertia("disc.rx", JD), Inertia("disc.ry", JD), Support("disc.rx", KT),
         Support("disc.ry", KT), Gyroscopic(("disc.rx", "disc.ry"), JP, spin_ratio)],
        speed=rpm * math.pi / 30, name="disc",
    )  # fmt: skip


@pytest.mark.parametrize("rpm", [1000.0, 3000.0, 6000.0])
def test_spinning_disc_splits_into_forward_and_backward_whirl(rpm):
    res = complex_modes(disc(rpm))
    half = JP / JD * rpm * math.pi / 30 / 2
    wn = math.sqrt(KT / JD)
    back, fwd = math.sqrt(wn**2 + half**2) - half, math.sqrt(wn**2 + half**2) + half
    # eigenvalues of a 4x4 state matrix: relative round-off ~1e-15; asserted 1e-10
    np.testing.assert_allclose(res.frequencies, [back / (2 * math.pi), fwd / (2 * math.pi)],
                               rtol=1e-10)  # fmt: skip
    assert res.data["whirl"].values.tolist() == ["backward", "forward"]
    assert np.all(res.data["stable"].values) and np.allclose(res.data["damping_ratio"], 0)


def test_whirl_follows_the_spin_direction():
    # the same disc spinning the other way: the split is the same, and the mode that
    # whirls with the spin (now clockwise) is the forward one
    a, b = complex_modes(disc(3000.0)), complex_modes(disc(3000.0, spin_ratio=-1.0))
    np.testing.assert_allclose(a.frequencies, b.frequencies, rtol=1e-12)
    assert b.data["whirl"].values.tolist() == ["backward", "forward"]
    # at rest: one double frequency, no whirl sense to name
    rest = complex_modes(disc(0.0))
    assert rest.frequencies[0] == pytest.approx(rest.frequencies[1], rel=1e-12)


def test_rotating_frame_mass_has_frequencies_omega_n_minus_and_plus_omega():
    W, m, k = 50.0, 2.0, 8e3
    model = Model(
        [Dof("p", "x"), Dof("p", "y")],
        [Inertia("p.x", m), Inertia("p.y", m), Support("p.x", k), Support("p.y", k),
         Coriolis(("p.x", "p.y"), m), Centripetal("p.x", m), Centripetal("p.y", m)],
        speed=W,
    )  # fmt: skip
    res = complex_modes(model)
    wn = math.sqrt(k / m)
    np.testing.assert_allclose(res.frequencies, [(wn - W) / (2 * math.pi),
                                                 (wn + W) / (2 * math.pi)], rtol=1e-10)  # fmt: skip
    # in the rotating frame the lower one whirls with the rotation
    assert res.data["whirl"].values.tolist() == ["forward", "backward"]


def test_damped_oscillator_frequency_ratio_and_log_decrement():
    m, k, zeta = 1.5, 6e4, 0.07
    c = 2 * zeta * math.sqrt(k * m)
    res = complex_modes(Model([Dof("a", "x")], [Inertia("a.x", m), Support("a.x", k, c)]))
    wn = math.sqrt(k / m)
    assert res.frequencies[0] == pytest.approx(wn * math.sqrt(1 - zeta**2) / (2 * math.pi),
                                               rel=1e-12)  # fmt: skip
    assert res.data["natural_frequency"].values[0] == pytest.approx(wn / (2 * math.pi), rel=1e-12)
    assert res.data["damping_ratio"].values[0] == pytest.approx(zeta, rel=1e-12)
    assert res.data["log_decrement"].values[0] == pytest.approx(
        2 * math.pi * zeta / math.sqrt(1 - zeta**2), rel=1e-12
    )


def test_negative_damping_is_reported_unstable():
    # the mode grows at Re(lambda) = 4 / (2 m) = 2 1/s and is never reported as a
    # normal frequency
    res = complex_modes(Model([Dof("a", "x")], [Inertia("a.x", 1.0), Support("a.x", 1e4, 0.0),
                                                NegativeDamper()]))  # fmt: skip
    assert not res.data["stable"].values[0]
    assert res.data["growth_rate"].values[0] == pytest.approx(2.0, rel=1e-9)
    assert "UNSTABLE" in res.table()


def test_without_damping_and_gyroscopics_it_is_the_undamped_modal_analysis():
    model = chain([1.0, 2.0, 0.5, 3.0], [1e4, 3e4, 2e4])  # free: one rigid mode
    real, cplx = modal(model), complex_modes(model)
    # state-space eigenvalues against the symmetric solver: both ~1e-15 |lambda|
    np.testing.assert_allclose(cplx.frequencies, real.frequencies, rtol=1e-9, atol=1e-9)
    assert cplx.data["whirl"].values[0] == "rigid" and cplx.data.attrs["rigid_modes"] == 1
    # and the real shapes up to sign (largest component 1 in both)
    np.testing.assert_allclose(np.abs(cplx.data["shape_real"].values[:, 1:]),
                               np.abs(real.data["shape_max"].values[:, 1:]), atol=1e-8)  # fmt: skip
    assert np.allclose(cplx.data["shape_imag"].values, 0, atol=1e-10)


def test_result_round_trip_and_figure(tmp_path):
    res = complex_modes(disc(3000.0))
    back = Result.load(res.save(tmp_path / "c.nc"))
    assert isinstance(back, ComplexModalResult)
    assert back.data["whirl"].values.tolist() == ["backward", "forward"]
    assert res.to_dict()["stable"] == [True, True]
    assert len(res.plot().axes) == 2


def test_elements_name_their_dofs_and_parameters():
    with pytest.raises(ModelError, match=r"gyroscopic:disc: gyroscopic moments act on one "):
        Model([Dof("disc", "x"), Dof("disc", "y")],
              [Inertia("disc.x", 1.0), Inertia("disc.y", 1.0),
               Gyroscopic(("disc.x", "disc.y"), JP)]).matrices()  # fmt: skip
    with pytest.raises(ModelError, match="polar must be a finite number >= 0"):
        Gyroscopic(("d.rx", "d.ry"), -1.0)
    with pytest.raises(ModelError, match="ratio must be a finite number"):
        Coriolis(("d.x", "d.y"), 1.0, float("nan"))
    # the polar inertia is a model parameter: exact derivative of the velocity matrix
    m = disc(3000.0)
    d = m.derivative("gyroscopic:disc.polar")
    W = 3000 * math.pi / 30
    np.testing.assert_allclose(d.C, [[0.0, W], [-W, 0.0]], rtol=1e-12)


def test_undamped_modal_flags_skew_terms_it_leaves_out():
    assert modal(disc(3000.0)).data.attrs["skew_velocity_terms"] == 1
    assert modal(disc(0.0)).data.attrs["skew_velocity_terms"] == 0


def test_cli_modal_complex(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app
    from reducerlab.examples import example_dir

    r = CliRunner().invoke(
        app, ["modal", str(example_dir() / "gear_pair.toml"), "--complex", "-o", str(tmp_path)]
    )
    assert r.exit_code == 0, r.output
    assert "complex modes:" in r.output and "damping ratio" in r.output
    for name in ("complex_modes.nc", "complex_modes.png", "complex_modes.json", "modal.nc"):
        assert (tmp_path / name).is_file()


def test_campbell_critical_speeds_of_the_spinning_disc():
    # synchronous (1x) crossings of a gyroscopic disc: backward whirl at
    # Omega = omega_n / sqrt(1 + gamma), forward at omega_n / sqrt(1 - gamma) for
    # gamma = J_p / J_d < 1 (Friswell et al. 2010, Sec. 3.5: critical speeds); the
    # crossings are refined by root finding (brentq, 1e-12): asserted 1e-9
    from reducerlab.analysis.complex_modal import ComplexCampbellResult, complex_campbell

    jp = 0.015
    m = Model(
        [Dof("disc", "rx"), Dof("disc", "ry")],
        [Inertia("disc.rx", JD), Inertia("disc.ry", JD), Support("disc.rx", KT),
         Support("disc.ry", KT), Gyroscopic(("disc.rx", "disc.ry"), jp)],
    )  # fmt: skip
    res = complex_campbell(m, np.linspace(0.0, 3000.0, 41), orders={"1x": 1.0})
    wn, g = math.sqrt(KT / JD), jp / JD
    cr = res.crossings()
    assert [c["whirl"] for c in cr] == ["backward", "forward"]
    rpm = [c["speed_rpm"] for c in cr]
    np.testing.assert_allclose(rpm, [wn / math.sqrt(1 + g) * 30 / math.pi,
                                     wn / math.sqrt(1 - g) * 30 / math.pi], rtol=1e-9)  # fmt: skip
    assert res.unstable_speeds() == [] and "every mode is stable" in res.table()
    # the diagram and its colour bar (damping: logarithmic decrement)
    assert isinstance(res, ComplexCampbellResult) and len(res.plot().axes) == 2


def test_campbell_reports_the_speeds_where_a_mode_grows():
    # a rotating-frame mass whose frame speed exceeds its natural frequency without
    # the Coriolis term (centripetal softening only): divergence beyond Omega = omega_n
    # is reported as unstable, never drawn as a normal frequency
    from reducerlab.analysis.complex_modal import complex_campbell

    m, k = 1.0, 100.0  # omega_n = 10 rad/s
    model = Model([Dof("p", "x")], [Inertia("p.x", m), Support("p.x", k, 0.1),
                                    Centripetal("p.x", m)])  # fmt: skip
    res = complex_campbell(model, np.linspace(0.0, 20.0, 21), orders={"1x": 1.0})
    bad = res.unstable_speeds()
    assert bad and min(bad) == pytest.approx(11 * 30 / math.pi, rel=1e-12)
    assert "UNSTABLE" in res.table()


def test_cli_campbell_complex(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app
    from reducerlab.examples import example_dir

    r = CliRunner().invoke(app, ["campbell", str(example_dir() / "gear_pair.toml"), "--complex",
                                 "--speeds", "lin:0:3000:11", "-o", str(tmp_path)])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "complex Campbell diagram" in r.output
    assert (tmp_path / "complex_campbell.nc").is_file()
    assert (tmp_path / "complex_campbell.png").is_file()


def test_resonance_check_gives_the_stability_verdict():
    # a mode with negative damping makes the check fail whatever the crossings, and
    # the report names it; a damped model reports its least damped mode
    from reducerlab.analysis.resonance import format_check, resonance_check

    bad = Model([Dof("a", "x")], [Inertia("a.x", 1.0), Support("a.x", 1e4, 0.0),
                                  NegativeDamper()], speed=100.0)  # fmt: skip
    rep = resonance_check(bad, speed_range=(50.0, 100.0), points=3)
    assert not rep["ok"] and len(rep["stability"]["unstable"]) == 3
    assert "UNSTABLE  mode 1" in format_check(rep)
    good = Model([Dof("a", "x")], [Inertia("a.x", 1.0), Support("a.x", 1e4, 20.0)], speed=100.0)
    rep = resonance_check(good, speed_range=(50.0, 100.0), points=3)
    assert rep["stability"]["unstable"] == []
    assert rep["stability"]["least_damped"]["damping_ratio"] == pytest.approx(0.1, rel=1e-12)


def test_lumped_design_declares_gyroscopic_elements():
    # examples/spinning_disc.toml: its tilting pair splits as the closed form says
    # (damping 0.5 N m s/rad on a 3e4 N m/rad support: damped frequencies, compared
    # through |lambda| with the undamped closed form to the damping's order, 1e-4)
    from reducerlab.drives import build_model, load_design
    from reducerlab.errors import DesignError
    from reducerlab.examples import example_dir

    path = example_dir() / "spinning_disc.toml"
    res = complex_modes(build_model(load_design(path)))
    tilt = res.data.where(res.data["whirl"].isin(["forward", "backward"]), drop=True)
    W, jd, jp, k = 3000 * math.pi / 30, 0.04, 0.07, 3e4
    half = jp / jd * W / 2
    wn = math.sqrt(k / jd)
    want = np.array([math.sqrt(wn**2 + half**2) - half, math.sqrt(wn**2 + half**2) + half])
    np.testing.assert_allclose(tilt["natural_frequency"].values, want / (2 * math.pi), rtol=1e-4)
    assert tilt["whirl"].values.tolist() == ["backward", "forward"]
    with pytest.raises(DesignError, match=r"elements\.8\.pair.*must be one body's rx, ry DOFs"):
        load_design(path, ["elements.8.pair=['disc.x', 'disc.y']"])
