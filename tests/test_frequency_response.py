"""Frequency-response curves swept up and down (analysis/frequency_response.py).

Oracles: the linear oscillator's amplitude ``F_a / sqrt((1 - m W^2)^2 + (c W)^2)`` while
the teeth stay in contact (any vibration text; Kahraman and Singh, J. Sound Vib. 142,
1990, use it as the no-impact solution), and the hysteresis at their no-impact boundary:
the no-impact orbit (amplitude A) exists for a mean force F_m > A, a rattle below it and,
for these values, also somewhat above it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.frequency_response import frequency_response
from reducerlab.analysis.sweep import Axis
from reducerlab.cli import app
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import Backlash, Dof, Fourier, Inertia, Load, Mesh, Model
from reducerlab.results import Result

C, W = 0.1, 0.8


def pair(mean: float, fa: float, omega: float) -> Model:
    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, 1.0, C, name="mesh", backlash=Backlash.half(1.0)),
            Load("a.x", mean, name="mean"),
            Load("a.x", Fourier(0.0, (fa,), omega), name="alt"),
        ],
        name="pair",
    )


def test_no_impact_curve_is_the_linear_closed_form():
    # mass swept through resonance (m W^2 = 1 at m = 1): a mean force of 5 keeps the
    # teeth in contact; RMS = amplitude / sqrt 2 and DLF = 1 + amplitude sqrt(1 + (c W)^2)
    # / F_m (elastic plus viscous force) at every value, to the integrator's 1e-6
    masses = np.linspace(0.5, 2.0, 7)
    res = frequency_response(pair(5.0, 0.1, 1.0), Axis("inertia:a.x.value", masses),
                             periods=300, continuation="up")  # fmt: skip
    amp = 0.1 / np.hypot(1 - masses, C)
    up = res.data.sel(branch="up")
    np.testing.assert_allclose(up["rms_dte"].values, amp / math.sqrt(2), rtol=1e-5)
    np.testing.assert_allclose(up["ptp_dte"].values, 2 * amp, rtol=1e-3)  # sampled peaks
    np.testing.assert_allclose(
        up["dynamic_load_factor"].values, 1 + amp * math.hypot(1, C) / 5.0, rtol=1e-3
    )
    assert np.all(up["separation_fraction"].values == 0)
    # omega-bar: forcing 1 rad/s over the mode sqrt(1/m)
    np.testing.assert_allclose(up["frequency_ratio"].values, np.sqrt(masses), rtol=1e-12)


def test_up_and_down_sweeps_jump_at_the_no_impact_boundary():
    A = 0.09
    fa = A * math.hypot(1 - W**2, C * W)
    vals = [0.06, 0.08, 0.1, 0.12, 0.2, 0.3]
    res = frequency_response(pair(0.1, fa, W), Axis("mean.value", vals), periods=300)
    up, down = res.data.sel(branch="up"), res.data.sel(branch="down")
    # descending: the no-impact orbit, RMS A / sqrt 2, down to F_m = 0.1
    np.testing.assert_allclose(down["rms_dte"].values[2:], A / math.sqrt(2), rtol=1e-5)
    assert np.all(down["separation_fraction"].values[2:] == 0)
    # ascending: still rattling at 0.1 and 0.12 (coexistence), larger motion
    assert np.all(up["separation_fraction"].values[:4] > 0.4)
    assert np.all(up["rms_dte"].values[2:4] > 2 * down["rms_dte"].values[2:4])
    # one attractor only at the ends: the sweeps agree
    np.testing.assert_allclose(up["rms_dte"].values[[0, 4, 5]], down["rms_dte"].values[[0, 4, 5]],
                               rtol=1e-6)  # fmt: skip
    assert len(res.plot().axes) == 3


@pytest.mark.parametrize(
    ("kw", "rule"),
    [
        ({"continuation": "left"}, "continuation must be"),
        ({"periods": 5, "history": 6}, "history must be <= periods"),
        ({"periods": 1}, "periods must be an integer >= 2"),
        ({"line": 3}, "line must be in 0..0"),
    ],
)
def test_bad_input_is_named(kw, rule):
    with pytest.raises(ReducerlabError, match=rule):
        frequency_response(pair(0.1, 0.03, W), Axis("mean.value", [0.1, 0.2]), **kw)


def test_cli_writes_and_reloads(tmp_path):
    out = tmp_path / "fr"
    r = CliRunner().invoke(app, [
        "frequency-response", str(example_dir() / "khv.toml"), "-p", "input_speed",
        "-v", "1400 rpm,1600 rpm", "--periods", "40", "--history", "4", "-o", str(out),
    ])  # fmt: skip
    assert r.exit_code == 0, r.output
    res = Result.load(out / "frequency-response.nc")
    assert res.kind == "frequency-response"
    np.testing.assert_allclose(res.data["p0"].values, [1400 * math.pi / 30, 1600 * math.pi / 30])
    assert (out / "frequency-response.png").stat().st_size > 0
