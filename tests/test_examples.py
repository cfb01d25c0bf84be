"""Examples are tests: every shipped example runs, and pins a number."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest
import scipy.linalg

from reducerlab.analysis.modal import modal
from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir, example_files


def test_every_toml_example_loads_builds_and_solves():
    files = example_files()
    assert files, "no bundled examples"
    from reducerlab.drives import has_model

    for path in files:
        design = load_design(path)
        if has_model(design):
            assert np.all(np.isfinite(modal(build_model(design)).frequencies))
        else:
            assert design.kinematics().ratio != 0


def test_gear_pair_example_against_hand_assembled_matrices():
    # independent assembly of the 6x6 bending-torsional gear pair from its equations
    d = load_design(example_dir() / "gear_pair.toml")
    a = d.mesh.pressure_angle
    rbp = d.mesh.module * d.pinion.teeth * math.cos(a) / 2
    rbg = d.mesh.module * d.gear.teeth * math.cos(a) / 2
    g = np.array([math.sin(a), math.cos(a), rbp, -math.sin(a), -math.cos(a), rbg])
    M = np.diag([d.pinion.mass, d.pinion.mass, d.pinion.moment_of_inertia,
                 d.gear.mass, d.gear.mass, d.gear.moment_of_inertia])  # fmt: skip
    K = np.diag([d.pinion.bearing.stiffness_x, d.pinion.bearing.stiffness_y, 0,
                 d.gear.bearing.stiffness_x, d.gear.bearing.stiffness_y, 0])  # fmt: skip
    K = K + d.mesh.stiffness * np.outer(g, g)
    lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    f = np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)
    res = modal(build_model(d))
    np.testing.assert_allclose(res.frequencies[1:], f[1:], rtol=1e-10)
    assert res.frequencies[0] == 0.0
    # pin one number so an accidental change of the example shows up
    assert res.frequencies[-1] == pytest.approx(5047.42, rel=1e-5)


def test_custom_drive_python_example(capsys):
    path = example_dir() / "custom_drive.py"
    spec = importlib.util.spec_from_file_location("custom_drive", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.main()
    out = capsys.readouterr().out
    assert "rigid body" in out and "mesh.stiffness" in out
    model = mod.build()
    # the composed model equals a hand-written M and K
    M, K = model.matrices().M, model.matrices().K
    r_g = 0.045
    assert M[2, 2] == pytest.approx(2.2e-3 / r_g**2)  # J / r^2 on u
    omega = 3000 * 2 * math.pi / 60
    assert K[3, 3] == pytest.approx(
        3.0e8 - 0.9 * omega**2 + 2.4e8 * math.sin(math.radians(20)) ** 2
    )
    res = modal(model)
    assert res.frequencies[0] == 0.0 and np.all(res.frequencies[1:] > 0)


def test_paper_001_figures_example(tmp_path):
    path = example_dir() / "paper_001_figures.py"
    spec = importlib.util.spec_from_file_location("paper_001_figures", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.main(tmp_path)
    for name in ("tooth_involute.png", "tooth_double_arc.png", "pair_in_mesh.png"):
        assert (tmp_path / name).stat().st_size > 10_000
