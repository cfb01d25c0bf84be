"""Regime maps (issue 16): motion and impact class over two parameters.

Oracle: the single-DOF gear pair with backlash of the gear-rattle literature (Kahraman
and Singh, J. Sound Vib. 142, 1990, 49-75), here ``m x'' + c x' + k f(x) = F_m + F_a
cos(W t)`` with ``f`` the dead zone of half width 1, mapped over the mesh stiffness
``k`` and the mass ``m``. While the teeth stay in contact the motion is linear about
``x = 1 + F_m / k`` with amplitude ``A = F_a / sqrt((k - m W^2)^2 + (c W)^2)``: a
no-impact motion exists exactly where ``A < F_m / k`` (closed form). Beyond it every
motion impacts; on the softening side of the resonance (``k > m W^2``) an impacting
motion coexists with the no-impact one (their jump and hysteresis), on the other side
it does not.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.regime_map import RegimeMapResult, motion_order, regime_map
from reducerlab.analysis.sweep import Axis
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import Backlash, Dof, Fourier, Inertia, Load, Mesh, Model
from reducerlab.results import Result

FM, FA, W, C = 0.1, 0.02, 0.8, 0.1
K = Axis.linspace("mesh:a.x.stiffness", 0.4, 1.6, 13)
M = Axis.linspace("inertia:a.x.value", 0.8, 1.6, 5)
KHV = example_dir() / "khv.toml"


def rattle() -> Model:
    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, 1.0, C, backlash=Backlash.half(1.0)),
            Load("a.x", Fourier(FM, (FA,), W)),
        ],
        name="rattle",
    )


def contact_ratio() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A / (F_m / k) over the (m, k) grid, and the grids."""
    k, m = np.meshgrid(K.values, M.values)
    A = FA / np.hypot(k - m * W**2, C * W)
    return A / (FM / k), k, m


@pytest.fixture(scope="module")
def both() -> RegimeMapResult:
    # 300 periods: the slowest transient (c / 2m = 0.03 1/s at m = 1.6) decays by
    # e^-47 over 300 periods of 7.85 s
    return regime_map(rattle(), K, M, periods=300, keep=16, continuation="both")


def test_impacts_follow_the_closed_form_no_impact_boundary(both):
    ratio, k, m = contact_ratio()
    imp = both.impacts()
    assert imp.shape == (2, 5, 13)
    # beyond the boundary no motion without impacts exists: every branch impacts (5 %
    # margin: a grazing separation of a few 1e-3 of the clearance lasts too short a
    # time to be resolved by the samples of the history)
    beyond = ratio > 1.05
    assert beyond.sum() >= 10
    assert np.all(imp[:, beyond] != "no impact")
    # and no point without impacts lies beyond it
    assert np.all(ratio[np.any(imp == "no impact", axis=0)] < 1.0)
    # hardening side of the resonance, inside the boundary: no impact on either sweep
    calm = (k < m * W**2) & (ratio < 0.95)
    assert calm.sum() >= 10
    assert np.all(imp[:, calm] == "no impact")
    assert set(both.labels().ravel()) == {"period-1"}


def test_the_two_sweeps_show_the_jump_on_the_softening_side_only(both):
    ratio, k, m = contact_ratio()
    co = both.coexisting()
    imp = both.impacts()
    # the ascending sweep stays on the rattle branch inside the boundary, the
    # descending one on the no-impact branch: coexisting attractors
    assert co.sum() >= 5
    assert np.all(k[co] > m[co] * W**2)
    assert np.all(ratio[co] < 1.05)
    # mostly rattle on one sweep and no impact on the other (a flagged point may also
    # hold two impacting orbits of different mean)
    assert np.mean((imp[0] != imp[1])[co]) >= 0.8


def test_a_row_is_the_bifurcation_of_its_value():
    # the map's rows are bifurcations by continuation at fixed y: same points, same
    # exponents (fixed steps: the accurate step count is the ensemble's largest)
    model = rattle()
    x = Axis.linspace("mesh:a.x.stiffness", 0.5, 1.2, 5)
    y = Axis("inertia:a.x.value", (1.0, 1.3))
    rm = regime_map(model, x, y, periods=120, keep=8, continuation="up", steps_per_period=200)
    bf = bifurcation(model.with_parameter("inertia:a.x.value", 1.3), x, periods=120, keep=8,
                     steps_per_period=200, continuation="up", exponents=True)  # fmt: skip
    np.testing.assert_array_equal(rm.data["poincare"].values[0, 1], bf.data["poincare"].values)
    np.testing.assert_array_equal(rm.data["exponent"].values[0, 1], bf.data["exponent"].values)
    assert rm.labels()[0, 1].tolist() == bf.labels()


def test_an_interrupted_map_resumes_from_its_chunks(tmp_path, dask_client):
    x = Axis.linspace("mesh:a.x.stiffness", 0.5, 1.2, 4)
    y = Axis("inertia:a.x.value", (1.0, 1.2, 1.4, 1.6))
    # two sweeps (branches) and three rows per chunk: a chunk read back must keep its
    # row and branch axes apart
    kw = dict(periods=60, keep=8, continuation="both", rows_per_chunk=3, output=tmp_path)
    first = regime_map(rattle(), x, y, **kw)
    chunks = sorted((tmp_path / "chunks").glob("chunk_*.npz"))
    assert len(chunks) == 2  # rows 0-2 and row 3
    chunks[1].unlink()
    seen: list[tuple[int, int]] = []
    again = regime_map(rattle(), x, y, progress=lambda d, t: seen.append((d, t)), **kw)
    assert seen[0] == (12, 16)  # three rows of four points read back, one computed
    np.testing.assert_array_equal(first.data["poincare"].values, again.data["poincare"].values)
    # other arguments: the folder refuses to mix runs
    with pytest.raises(ReducerlabError, match="regime map run"):
        regime_map(rattle(), x, y, **{**kw, "periods": 61})
    # the chunks on a Dask cluster give the same map
    kw.pop("output")
    dask = regime_map(rattle(), x, y, scheduler=dask_client, **kw)
    np.testing.assert_array_equal(dask.data["poincare"].values, first.data["poincare"].values)


def test_result_round_trip_summary_and_figure(tmp_path, both):
    path = both.save(tmp_path / "map.nc")
    back = Result.load(path)
    assert isinstance(back, RegimeMapResult)
    assert back.labels().tolist() == both.labels().tolist()
    summary = both.to_dict()
    assert summary["branches"] == ["up", "down"] and len(summary["motion"][0]) == 5
    assert any(r["class"] == "single-sided impact" for r in summary["regions"])
    assert "coexisting attractors" in both.table()
    fig = both.plot()
    assert len(fig.axes) >= 4


def test_motion_order_reads_period_n_first():
    got = motion_order(["chaotic", "period-12", "diverged", "period-2", "quasi-periodic"])
    assert got == ["period-2", "period-12", "quasi-periodic", "chaotic", "diverged"]


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"continuation": "sideways"}, "continuation must be"),
        ({"keep": 10, "periods": 5}, "keep = 10 must be <= periods"),
        ({"rows_per_chunk": 0}, "rows_per_chunk must be an integer >= 1"),
        ({"line": 3}, "line must be in 0..0"),
    ],
)
def test_bad_arguments_are_named(kw, message):
    with pytest.raises(ReducerlabError, match=message):
        regime_map(rattle(), K, M, **kw)


def test_axes_must_differ_and_targets_must_be_models():
    with pytest.raises(ReducerlabError, match="share a parameter"):
        regime_map(rattle(), K, K)
    with pytest.raises(ReducerlabError, match="target must be a Design or a Model"):
        regime_map("design.toml", K, M)  # type: ignore[arg-type]


def test_speed_axis_is_shown_in_rpm():
    d = load_design(KHV)
    x = Axis("input_speed", ("600 rpm", "700 rpm"))
    y = Axis("gears.x1", (0.6,))
    res = regime_map(d, x, y, periods=40, keep=4)
    c = res.data["p0"]
    assert c.attrs["display_unit"] == "rpm"
    assert c.values * c.attrs["display_factor"] == pytest.approx([600, 700], rel=1e-12)
    assert res.data["p1"].attrs["display_unit"] == ""
    assert res.data["p0"].values[0] == pytest.approx(600 * 2 * math.pi / 60, rel=1e-12)
    assert res.plot().axes[-1].get_xlabel() == "input speed (rpm)"
    # the bifurcation diagram and the frequency response draw the speed in rpm too
    from reducerlab.analysis.frequency_response import frequency_response

    b = bifurcation(d, x, periods=40, keep=4)
    assert b.data["p0"].attrs["display_unit"] == "rpm"
    assert b.plot().axes[-1].get_xlabel() == "input speed (rpm)"
    fr = frequency_response(d, x, periods=20, history=2)
    assert fr.plot().axes[-1].get_xlabel() == "input speed (rpm)"
    backlash = bifurcation(d, Axis("mesh.half_backlash", ("1 um", "2 um")), periods=20, keep=2)
    assert backlash.plot().axes[-1].get_xlabel() == "mesh half backlash (um)"


runner = CliRunner()


def test_cli_writes_the_map_and_names_bad_axes(tmp_path):
    args = ["regime-map", str(KHV), "-x", "input_speed=600 rpm,700 rpm", "-y",
            "gears.x1=0.55,0.65", "--periods", "40", "--keep", "4", "-o", str(tmp_path),
            "--set", "mesh.half_backlash=3 um"]  # fmt: skip
    r = runner.invoke(app, args)
    assert r.exit_code == 0, r.output
    for name in ("regime_map.nc", "regime_map.png", "regime_map.json", "regime_map.txt"):
        assert (tmp_path / name).is_file()
    assert "regime map: KHV drive" in r.output
    r = runner.invoke(app, [*args[:3], "input_speed", *args[4:]])
    assert r.exit_code == 2 and "-x must be 'PATH=VALUES'" in r.output
    r = runner.invoke(app, [*args[:5], "gears.x1=lin:0.5:0.6:x", *args[6:]])
    assert r.exit_code == 2 and "N = 'x' must be a whole number" in r.output
