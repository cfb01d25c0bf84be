"""Sweeps: tracking through crossings and veerings (closed forms), vectorised vs
per-point equality, relative and grid sweeps, Dask, resume after a kill, bad specs."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from reducerlab.analysis.parameters import Axis, parse_values
from reducerlab.analysis.runfolder import load_chunk
from reducerlab.analysis.sweep import SweepResult, sweep
from reducerlab.drives import build_model, load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import Coupling, Dof, Inertia, Model, Support

EXAMPLE = example_dir() / "gear_pair.toml"


def two_dof(k1: float, k2: float, kc: float) -> Model:
    """Unit masses on springs k1, k2 to ground, coupled by kc:
    lambda = (k1 + k2)/2 + kc -+ sqrt(((k1 - k2)/2)^2 + kc^2)."""
    return Model(
        [Dof("a", "x"), Dof("b", "x")],
        [
            Inertia("a.x", 1.0),
            Inertia("b.x", 1.0),
            Support("a.x", k1, name="k1"),
            Support("b.x", k2, name="k2"),
            Coupling({"a.x": 1.0, "b.x": -1.0}, kc, name="kc"),
        ],
    )


def test_crossing_of_uncoupled_modes():
    # kc = 0: the two modes are independent and cross at k1 = k2 = 1e6
    res = sweep(two_dof(1e6, 1e6, 0.0), Axis.linspace("k1.stiffness", 0.5e6, 1.5e6, 41), workers=1)
    ev = res.events()
    assert [e["kind"] for e in ev] == ["crossing"]
    # tracked frequencies are straight through the crossing: track of mode a is sqrt(k1)
    assert ev[0]["param"] == pytest.approx(1e6, rel=1e-9)
    tf = res.data["tracked_frequency"].values
    k1 = res.data["p0"].values
    a_track = np.argmin(np.abs(tf[0] - np.sqrt(k1[0]) / (2 * math.pi)))
    np.testing.assert_allclose(tf[:, a_track], np.sqrt(k1) / (2 * math.pi), rtol=1e-12)
    assert ev[0]["modes"] == [1, 2]


def test_veering_of_coupled_modes_closed_form():
    # kc > 0: the sorted curves veer at k1 = k2 with a minimum eigenvalue gap of 2 kc
    kc, k2 = 2e4, 1e6
    res = sweep(two_dof(0.5e6, k2, kc), Axis.linspace("k1.stiffness", 0.5e6, 1.5e6, 101), workers=1)
    ev = res.events()
    assert [e["kind"] for e in ev] == ["veering"]
    # parabolic interpolation on a grid of 1e4 N/m: within 1 % of the step
    assert ev[0]["param"] == pytest.approx(k2, abs=100.0)
    lam = (k2 + k2) / 2 + kc + np.array([-1, 1]) * kc
    gap = np.diff(np.sqrt(lam) / (2 * math.pi))[0]
    assert ev[0]["gap_hz"] == pytest.approx(gap, rel=1e-3)
    # tracks follow the sorted order through a veering (shapes rotate continuously)
    order = res.data["track_order"].values
    assert np.all(order == order[0])


def test_vectorised_equals_per_point(tmp_path):
    d = load_design(EXAMPLE)
    axis = Axis.logspace("mesh.stiffness", 1e8, 3e9, 50)
    fast = sweep(d, axis, workers=1)
    assert fast.data.attrs["vectorised"] == 1
    # the per-point way a user would write it
    per_point = []
    for k in axis.values:
        data = d.model_dump()
        data["mesh"]["stiffness"] = k
        from reducerlab.analysis.modal import modal
        from reducerlab.drives import design_from_dict

        per_point.append(modal(build_model(design_from_dict(data))).frequencies)
    np.testing.assert_allclose(fast.data["frequency"].values, np.array(per_point), rtol=1e-9,
                               atol=1e-6)  # fmt: skip


def test_nonlinear_parameter_is_evaluated_per_point():
    d = load_design(EXAMPLE)
    res = sweep(d, parse_values("pinion.teeth", "20,25,30"), workers=1)
    assert res.data.attrs["vectorised"] == 0
    assert res.data["frequency"].values[1] == pytest.approx(
        __import__("reducerlab").modal(build_model(d)).frequencies
    )


def test_relative_sweep_as_in_paper_000():
    d = load_design(EXAMPLE)
    res = sweep(d, parse_values("mesh.stiffness", "100%,150%,200%,250%"), workers=1)
    np.testing.assert_allclose(res.data["p0"].values, np.array([1, 1.5, 2, 2.5]) * 3.8e8)
    assert json.loads(res.data.attrs["relative"]) == [True]
    assert res.plot().axes[0].get_xlabel().endswith("(% of design)")


def test_model_parameter_and_units_in_values():
    d = load_design(EXAMPLE)
    r1 = sweep(d, parse_values("support:gear.x.stiffness", "1e8,2e8"), workers=1)
    r2 = sweep(d, parse_values("gear.bearing.stiffness_x", "1e8 N/m, 200 N/um"), workers=1)
    np.testing.assert_allclose(r1.data["frequency"].values, r2.data["frequency"].values, rtol=1e-12)


def test_grid_sweep_and_save(tmp_path):
    d = load_design(EXAMPLE)
    res = sweep(
        d,
        [parse_values("mesh.stiffness", "lin:1e8:1e9:4"), parse_values("gear.mass", "5,6,7")],
        output=tmp_path / "run",
        workers=1,
    )
    assert res.data["frequency"].shape == (4, 3, 6)
    back = SweepResult.load(tmp_path / "run" / "sweep.nc")
    np.testing.assert_array_equal(back.data["frequency"].values, res.data["frequency"].values)
    assert len(res.plot().axes) >= 6


def test_dask_local_cluster(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    d = load_design(EXAMPLE)
    axis = parse_values("pinion.teeth", "lin:20:44:25")
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        res = sweep(d, axis, scheduler=client, chunk_size=5, output=tmp_path / "dask")
    local = sweep(d, axis, workers=1)
    np.testing.assert_allclose(res.data["frequency"].values, local.data["frequency"].values)
    assert len(list((tmp_path / "dask" / "chunks").glob("*.npz"))) == 5


def test_worker_processes_give_the_same_result(tmp_path):
    d = load_design(EXAMPLE)
    axis = parse_values("pinion.teeth", "lin:20:35:16")
    a = sweep(d, axis, workers=2, chunk_size=4)
    b = sweep(d, axis, workers=1, chunk_size=16)
    np.testing.assert_allclose(a.data["frequency"].values, b.data["frequency"].values)


def test_resume_after_kill(tmp_path):
    # start a long sweep in a subprocess, kill it once some chunks are on disk,
    # re-run the same command: it computes only the missing chunks and the result
    # equals an uninterrupted run
    out = tmp_path / "run"
    cmd = [
        sys.executable, "-m", "reducerlab", "sweep", str(EXAMPLE),
        "-p", "pinion.teeth", "-v", "lin:10:2009:2000",
        "-o", str(out), "--chunk-size", "50", "--workers", "1", "--format", "json",
    ]  # fmt: skip
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    chunks = out / "chunks"
    deadline = time.time() + 120
    while time.time() < deadline:
        done = list(chunks.glob("chunk_*.npz")) if chunks.exists() else []
        if len(done) >= 3 or proc.poll() is not None:
            break
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    before = sorted(p.name for p in chunks.glob("chunk_*.npz"))
    assert 0 < len(before) < 40, "the sweep must be interrupted mid-run for this test"
    # chunks are written atomically: every chunk file left by the kill is complete and
    # stamped (a partial write stays under a hidden temporary name and is ignored)
    key = json.loads((out / "sweep.json").read_text())["key"]
    for p in chunks.glob("chunk_*.npz"):
        i = int(p.stem.split("_")[1])
        pts = np.arange(10.0, 2010.0)[50 * i : 50 * (i + 1), None]
        assert load_chunk(p, key, i, pts, ["lam", "phi", "y"])["lam"].shape == (50, 6)
    stamps = {p.name: p.stat().st_mtime_ns for p in chunks.glob("chunk_*.npz")}
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    resumed = json.loads(r.stdout)
    # chunks finished before the kill were not recomputed
    for name, ns in stamps.items():
        assert (chunks / name).stat().st_mtime_ns == ns
    full = sweep(load_design(EXAMPLE), parse_values("pinion.teeth", "lin:10:2009:2000"),
                 workers=1, track=False)  # fmt: skip
    np.testing.assert_allclose(np.array(resumed["frequencies_hz"]), full.data["frequency"].values)


def test_other_sweep_in_the_same_folder_is_refused(tmp_path):
    d = load_design(EXAMPLE)
    sweep(d, parse_values("mesh.stiffness", "1e8,2e8,3e8"), output=tmp_path, workers=1)
    with pytest.raises(ReducerlabError, match="holds a different sweep"):
        sweep(d, parse_values("mesh.stiffness", "1e8,2e8"), output=tmp_path, workers=1)


@pytest.mark.parametrize(
    ("path", "spec", "match"),
    [
        ("mesh.stiffness", "", "empty value specification"),
        ("mesh.stiffness", "lin:1:2", "write lin:START:STOP:N"),
        ("mesh.stiffness", "lin:a:2:3", "SI numbers"),
        ("mesh.stiffness", "lin:1:2:0", "number of points must be >= 1"),
        ("mesh.stiffness", "log:0:2:3", "log range needs start, stop > 0"),
        ("mesh.stiffness", "abc,def", "value 'abc' is not a number"),
        ("mesh.stiffness", "rel:1.5,x", "relative value 'x' is not a number"),
        ("mesh.stiffness", ",", "no values"),
    ],
)
def test_bad_value_specs(path, spec, match):
    with pytest.raises(ReducerlabError, match=match):
        parse_values(path, spec)


@pytest.mark.parametrize(
    ("axes", "match"),
    [
        ([parse_values("mesh.stifness", "1,2")], "unknown parameter path 'mesh.stifness'"),
        ([parse_values("support:gear.x.stiffness", "1e8 N/m,2e8 N/m")], "takes SI numbers"),
        ([parse_values("pinion.teeth", "20.5,21")], "whole numbers"),
        ([parse_values("mesh.stiffness", "5 kg")], "wrong dimension"),
        ([parse_values("pinion.mass", "-1,1")], "not a valid design"),
        ([parse_values("design:speed", "1,2")], "not a numeric field of the design"),
        (
            [parse_values("mesh.stiffness", "1,2"), parse_values("mesh.stiffness", "1,2")],
            "different parameters",
        ),
        ([], "give one Axis"),
    ],
)
def test_bad_sweeps(axes, match):
    with pytest.raises(ReducerlabError, match=match):
        sweep(load_design(EXAMPLE), axes, workers=1)


def test_bad_axis_and_options():
    with pytest.raises(ReducerlabError, match="no values"):
        Axis("mesh.stiffness", ())
    with pytest.raises(ReducerlabError, match="not finite"):
        Axis("mesh.stiffness", (math.nan,))
    d = load_design(EXAMPLE)
    with pytest.raises(ReducerlabError, match="chunk_size"):
        sweep(d, parse_values("mesh.stiffness", "1,2"), chunk_size=0)
    with pytest.raises(ReducerlabError, match="workers"):
        sweep(d, parse_values("mesh.stiffness", "1,2"), workers=0)


def test_tied_parameters_move_together():
    # "a+b" sets both to the value; relative factors scale each from its own value
    d = load_design(EXAMPLE)
    path = "pinion.bearing.stiffness_x+gear.bearing.stiffness_x"
    res = sweep(d, parse_values(path, "rel:1,2"), workers=1)
    data = d.model_dump()
    data["pinion"]["bearing"]["stiffness_x"] *= 2
    data["gear"]["bearing"]["stiffness_x"] *= 2
    from reducerlab.analysis.modal import modal
    from reducerlab.drives import design_from_dict

    f2 = modal(build_model(design_from_dict(data))).frequencies
    np.testing.assert_allclose(res.data["frequency"].values[1], f2, rtol=1e-9)
    with pytest.raises(ReducerlabError, match="lists a parameter twice"):
        sweep(d, parse_values("mesh.stiffness+mesh.stiffness", "1e8,2e8"), workers=1)


def test_a_range_count_that_is_not_a_whole_number_is_named():
    from reducerlab.analysis.parameters import parse_values

    with pytest.raises(ReducerlabError, match=r"N = '1e99' must be a whole number of points"):
        parse_values("mesh.stiffness", "lin:1e8:2e9:1e99")
    with pytest.raises(ReducerlabError, match=r"write lin:START:STOP:N with SI numbers"):
        parse_values("mesh.stiffness", "lin:a:2e9:10")


def test_a_range_with_units_is_converted_by_the_design_field():
    # issue 16: lin:1300 rpm:1700 rpm:N, as a list with units is: each value converted
    # by the field's unit (input_speed is stored in rad/s)
    import math

    from reducerlab.analysis.bifurcation import bifurcation
    from reducerlab.drives import load_design

    ax = parse_values("input_speed", "lin:1300 rpm:1700 rpm:3")
    design = load_design(example_dir() / "khv.toml")
    res = bifurcation(design, ax, periods=10, keep=2)
    np.testing.assert_allclose(res.data["p0"].values, np.array([1300, 1500, 1700]) * math.pi / 30)
    with pytest.raises(ReducerlabError, match="different dimensions"):
        parse_values("input_speed", "lin:1300 rpm:2 m:3")
    with pytest.raises(ReducerlabError, match="with SI numbers, or both ends as quantities"):
        parse_values("input_speed", "lin:fast:slow:3")
