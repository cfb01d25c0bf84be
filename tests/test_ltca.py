"""Tooth contact analysis of nutation bevel pairs (contact/flanks.py, contact/ltca.py,
contact/meshstiffness.py, analysis/contact.py): conjugacy, equilibrium checked with an
independent lever arm, periodicity, misalignment, the Eq. 8 fit, results and errors."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from reducerlab.analysis.contact import (
    ContactResult,
    contact_analysis,
    contact_pair,
    design_with_mesh,
)
from reducerlab.contact.complementarity import ContactError
from reducerlab.contact.flanks import Misalignment, separations
from reducerlab.contact.halfspace import combined_modulus
from reducerlab.contact.ltca import ContactGrid, loaded_contact
from reducerlab.contact.meshstiffness import fit_fourier
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.results import Result

E_STAR = combined_modulus(2.06e11, 0.3, 2.06e11, 0.3)


@pytest.fixture(scope="module")
def design():
    return load_design("examples/nutation_surface.toml")


@pytest.mark.parametrize("profile", ["involute", "double-arc"])
def test_generated_pair_is_conjugate(design, profile):
    """Both gears are envelopes of one crown surface (paper 001), so the unloaded pair
    touches with zero separation and no interference: min t over the flank is 0 to the
    Newton tolerance, at any mesh position (here three)."""
    pair = contact_pair(design, 1, profile=profile)
    lo, hi = pair.flank_a.u_range
    u, v = np.meshgrid(np.linspace(lo + 0.01, hi - 0.01, 25), np.linspace(0.02, 0.98, 25))
    pitch = 2 * math.pi / pair.external.teeth
    for phi in (0.0, 0.3 * pitch, 0.7 * pitch):
        t = np.concatenate(
            [separations(pair, phi, k, u.ravel(), v.ravel()).distance for k in (-1, 0, 1)]
        )
        t = t[np.isfinite(t)]
        assert t.size > 100
        # smooth flanks: no overlap beyond the Newton tolerance; double arc: its non-working
        # transition arc meets the concave arc at a corner (docs/tooth_surfaces.md), where
        # the two gears' corners overlap by micrometres without ever carrying load
        if profile == "involute":
            assert t.min() > -1e-9
        assert np.sort(np.abs(t))[:5].max() < 2e-7  # touching points exist (coarse grid)


def test_load_equilibrium_with_an_independent_lever(design):
    """The solver enforces sum(F lam) = T_B with the levers of contact/flanks.py; the
    torque of the resultant cell forces about gear B's own axis, summed from the cell
    points and normals (r x F), must give the same T_B."""
    pair = contact_pair(design, 1)
    run = loaded_contact(pair, 19.1, [0.01], ContactGrid(2e-4), E_star=E_STAR)[0]
    _, pb = pair.poses(0.01)
    F = run.force[:, None] * run.normals  # force on gear B (pushed by A's normal)
    torque_b = np.sum(np.cross(run.points - pb.origin, F) @ pb.axis)
    # the solver's levers use B's mating points and B's normals, this check A's cell
    # centres and A's normals: loaded cells lie within micrometres of B and the normals
    # agree to ~1e-4 rad, so the two torques agree to ~1e-4 (measured 7e-5)
    assert abs(abs(torque_b) - run.torque) < 5e-4 * run.torque
    assert run.torque == pytest.approx(19.1 * pair.torque_ratio)
    assert run.unloaded_te == pytest.approx(0.0, abs=1e-8)


def test_results_repeat_after_one_pitch(design):
    """Mesh position phi and phi + one pitch of gear A are the same state (tooth pairs
    renumbered), so the rigid-tooth contact must repeat."""
    pair = contact_pair(design, 1)
    pitch = 2 * math.pi / pair.external.teeth
    a, b = loaded_contact(pair, 19.1, [-0.5 * pitch, 0.5 * pitch], ContactGrid(2e-4),
                          E_star=E_STAR)  # fmt: skip
    assert b.loaded_te == pytest.approx(a.loaded_te, rel=1e-6)
    assert b.contact_area == pytest.approx(a.contact_area, rel=1e-6)
    assert np.allclose(b.force_vector, a.force_vector, rtol=1e-6)


def test_shaft_angle_error_gives_transmission_error_and_shifts_contact(design):
    """A shaft-angle error breaks conjugacy: the unloaded TE varies over the cycle
    (first-order for a misaligned spiral bevel pair) and the loaded zone shrinks."""
    base = contact_pair(design, 1)
    mis = contact_pair(design, 1, misalignment=Misalignment(shaft_angle=math.radians(0.05)))
    pitch = 2 * math.pi / base.external.teeth
    phis = np.linspace(0, pitch, 4, endpoint=False)
    ok = loaded_contact(base, 5.0, phis, ContactGrid(2e-4), E_star=E_STAR)
    bad = loaded_contact(mis, 5.0, phis, ContactGrid(2e-4), E_star=E_STAR)
    te = np.array([r.unloaded_te for r in bad])
    assert np.ptp([r.unloaded_te for r in ok]) < 1e-8
    assert np.ptp(te) > 1e-6  # rad: micrometres at the mean radius
    assert np.mean([r.contact_area for r in bad]) < 0.8 * np.mean([r.contact_area for r in ok])


def test_no_contact_is_a_clear_error(design):
    """Gear B moved 20 mm off its place: no point of A's flank finds B's flank (the pair
    built directly: ``contact_pair`` refuses such a shift, see the next test)."""
    far = dataclasses.replace(contact_pair(design, 1), misalignment=Misalignment(offset=0.02))
    with pytest.raises(ContactError, match="no contact"):
        loaded_contact(far, 1.0, [0.0], ContactGrid(2e-4), E_star=E_STAR)


@pytest.mark.parametrize("field", ["axial_a", "axial_b", "offset"])
def test_a_shift_beyond_one_module_is_not_an_assembly_error(design, field):
    # issue 26: `contact --offset "1 km"` searched whole flanks for minutes
    with pytest.raises(ReducerlabError, match=rf"misalignment\.{field} \(--.*\): must be within"):
        contact_pair(design, 1, misalignment=Misalignment(**{field: -2.5e-3}))
    contact_pair(design, 1, misalignment=Misalignment(**{field: 1.9e-3}))  # within 2 mm


def test_misalignment_and_grid_errors_name_the_field():
    with pytest.raises(ReducerlabError, match=r"misalignment\.shaft_angle"):
        Misalignment(shaft_angle=0.1)
    with pytest.raises(ReducerlabError, match=r"misalignment\.offset"):
        Misalignment(offset=float("nan"))
    with pytest.raises(ReducerlabError, match=r"grid\.cell"):
        ContactGrid(cell=-1.0)


# --------------------------------------------------------------------- Eq. 8 fit


def test_fourier_fit_recovers_a_series_exactly():
    """Samples of k_m + sum k_r cos(r x + phi_r) are fitted exactly (the DFT is the
    least-squares fit on even samples)."""
    amps, phases = np.array([3e7, 1e7, 4e6]), np.array([0.3, -1.2, 2.5])
    x = 2 * np.pi * np.arange(24) / 24
    k = 2.1e8 + sum(
        a * np.cos((r + 1) * x + p) for r, (a, p) in enumerate(zip(amps, phases, strict=True))
    )
    fit = fit_fourier(k, 7)
    assert fit.mean == pytest.approx(2.1e8)
    assert np.allclose(fit.amplitudes[:3], amps, rtol=1e-12)
    assert np.allclose(fit.phases[:3], phases, atol=1e-12)
    assert np.allclose(fit.amplitudes[3:], 0.0, atol=1e-6)
    assert fit.residual < 1e-14
    assert np.allclose(fit(x), k)
    # a lower order leaves the omitted harmonic in the residual: rms 4e6/sqrt(2)/2.1e8
    assert fit_fourier(k, 2).residual == pytest.approx(4e6 / math.sqrt(2) / 2.1e8, rel=1e-9)


def test_fourier_fit_errors():
    with pytest.raises(ReducerlabError, match="need at least 15 positions"):
        fit_fourier(np.ones(10), 7)
    with pytest.raises(ReducerlabError, match="finite"):
        fit_fourier([1.0, np.nan, 1.0], 1)


# --------------------------------------------------------------------- analysis


@pytest.fixture(scope="module")
def quick(design):
    """A rigid-tooth run (no finite-element models): seconds."""
    return contact_analysis(design, 1, torque=19.1, positions=6, order=2, rigid=True)


def test_quick_result_round_trip_and_summary(quick, tmp_path):
    import json

    path = quick.save(tmp_path / "c.nc")
    back = Result.load(path)
    assert back.kind == "contact"
    assert np.allclose(back.stiffness, quick.stiffness)
    d = back.to_dict()
    json.dumps(d)
    assert len(d["positions"]) == 6
    assert d["fourier"]["k_mean_N_per_m"] == pytest.approx(quick.mean_stiffness)
    assert "k_m =" in quick.table()
    # the force balances the torque: |F_x| (tangential at the mesh) ~ T / r_m
    s = quick.summary()
    assert 0.5 < s["force_x_mean_abs"] * 0.0309 / 19.1 < 2.0


def test_design_with_mesh_is_a_valid_design(design, quick, tmp_path):
    text = design_with_mesh("examples/nutation_surface.toml", quick)
    out = tmp_path / "d.toml"
    out.write_text(text)
    new = load_design(out)
    assert new.mesh1.stiffness == pytest.approx(quick.mean_stiffness, rel=1e-5)
    assert len(new.mesh1.harmonics) == 2
    assert new.mesh1.phases[0] == pytest.approx(quick.harmonics()[1][0], abs=1e-5)


def test_analysis_bad_input(design):
    with pytest.raises(ReducerlabError, match="exactly one of power"):
        contact_analysis(design, 1, rigid=True)
    with pytest.raises(ReducerlabError, match=r"pair: must be 1\.\.1"):
        contact_analysis(design, 2, torque=1.0, rigid=True)
    with pytest.raises(ReducerlabError, match="order: 7 harmonics need positions >= 15"):
        contact_analysis(design, 1, torque=1.0, positions=10, rigid=True)
    with pytest.raises(ReducerlabError, match="cell: must be a length"):
        contact_analysis(design, 1, torque=1.0, cell=1.0, order=1, rigid=True)
    with pytest.raises(ReducerlabError, match="power: must be a number > 0"):
        contact_analysis(design, 1, power=-3.0, rigid=True)


def test_design_without_surface_is_refused(no_surface_design):
    with pytest.raises(ReducerlabError, match="surface"):
        contact_analysis(no_surface_design, 1, torque=1.0, rigid=True)


# --------------------------------------------------------------------- command line


def test_cli_contact_options_are_checked(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    runner = CliRunner()
    base = ["contact", "examples/nutation_surface.toml", "-o", str(tmp_path / "o")]
    for extra, message in (
        (["--set", "output_torque=0"], "--power/--torque: give exactly one of them, or a load"),
        (["--power", "3 kg"], "--power"),
        (["--torque", "1 N*m", "--power", "1 kW"], "exactly one"),
        (["--torque", "1 N*m", "--cell", "-1 mm"], "--cell"),
        (["--torque", "1 N*m", "--shaft-angle", "5 deg", "--rigid"], "misalignment.shaft_angle"),
        (["--torque", "1 N*m", "--pair", "2", "--rigid"], "pair: must be 1..1"),
    ):
        r = runner.invoke(app, base + extra)
        assert r.exit_code == 2, (extra, r.output)
        assert message in r.output and "Traceback" not in r.output


def test_cli_contact_takes_the_torque_flow_at_the_designs_load(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    args = ["contact", "examples/nutation_surface.toml", "--rigid", "--positions", "5",
            "--order", "2", "-o", str(tmp_path / "o")]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    # 60 N m on the nutating gear's coupling: z2 / z1 of it on the fixed external gear 2
    assert "torque on central gear (pair 1) from the torque flow at 60 N m output " in r.output
    # 60 * 26 / 28 = 55.714... N m, printed with a torque's 4 digits (issue 32)
    assert "output torque: 55.71 N m" in r.output
    back = ContactResult.load(tmp_path / "o" / "contact.nc")
    assert back.data.attrs["torque_external"] == pytest.approx(60 * 26 / 28)


def test_cli_contact_writes_results_and_a_fitted_design(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    out, fitted = tmp_path / "o", tmp_path / "fitted.toml"
    args = ["contact", "examples/nutation_surface.toml", "--torque", "19.1 N*m", "--rigid"]
    args += ["--positions", "5", "--order", "2", "-o", str(out), "--write-design", str(fitted)]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    names = {p.name for p in out.iterdir()}
    assert names == {"contact.nc", "contact.json", "contact.txt", "contact.png", "pressure.png",
                     "pattern.png"}  # fmt: skip
    assert load_design(fitted).mesh1.harmonics


def test_result_does_not_depend_on_the_grid_margin(design, monkeypatch):
    """The candidate cells of a position come from the coarse separation and the last
    position's approach times a margin; the completeness check must make the answer
    independent of that margin. Rigid teeth give the thinnest contact bands (thinner
    than a coarse cell, between coarse centres): before the gap was bounded inside the
    coarse cells, a margin of 1.1 instead of 1.3 changed the loaded TE by 0.4 %."""
    import reducerlab.contact.ltca as ltca

    pair = contact_pair(design, 1)
    pitch = 2 * math.pi / pair.external.teeth
    phis = [-0.5 * pitch, -0.2 * pitch, 0.5 * pitch]
    runs = {}
    for margin in (1.0, 2.0):
        monkeypatch.setattr(ltca, "MARGIN", margin)
        runs[margin] = loaded_contact(pair, 19.1, phis, ContactGrid(2e-4), E_star=E_STAR)
    for a, b in zip(runs[1.0], runs[2.0], strict=True):
        assert a.loaded_te == pytest.approx(b.loaded_te, rel=1e-9)
        assert a.contact_area == pytest.approx(b.contact_area, rel=1e-9)
