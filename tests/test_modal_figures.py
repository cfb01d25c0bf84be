"""The sensitivity and energy maps and the kinematics figure as the report shows them
(issue 32): the parameters the sensitivities cover, the rows and columns the maps keep,
readable text and no touching tick labels."""

from __future__ import annotations

import numpy as np
import pytest

from reducerlab.analysis.modal import frequency_sensitivity, modal
from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir
from reducerlab.model.inspect import parameter_paths


def _model(name: str):
    return build_model(load_design(example_dir() / f"{name}.toml"))


@pytest.fixture(scope="module")
def khv():
    model = _model("khv")
    return model, modal(model)


@pytest.fixture(scope="module")
def cycloid():
    model = _model("cycloid_ball")
    res = modal(model)
    return model, res, frequency_sensitivity(model, [p for p, _ in parameter_paths(model)], res)


def test_a_piecewise_mesh_law_is_a_parameter_by_its_mean(khv):
    # the KHV mesh stiffness is a piecewise polynomial (single/double tooth): its mean
    # is derived, and was left out of the parameters; it is the mean mesh stiffness
    model, res = khv
    paths = dict(parameter_paths(model))
    assert "mesh.stiffness" in paths
    k = model.parameter("mesh.stiffness")
    assert paths["mesh.stiffness"] == pytest.approx(k)
    s = frequency_sensitivity(model, ["mesh.stiffness"], res).data["dfdp"].values[:, 0]
    h = 1e-4 * k
    up = modal(model.with_parameter("mesh.stiffness", k + h)).frequencies
    down = modal(model.with_parameter("mesh.stiffness", k - h)).frequencies
    fd = (up - down) / (2 * h)
    elastic = ~res.data["rigid"].values.astype(bool)
    np.testing.assert_allclose(s[elastic], fd[elastic], rtol=1e-3)
    # the law is scaled to the mean, its shape held
    law = model.with_parameter("mesh.stiffness", 2 * k).elements
    law = next(e for e in law if e.name == "mesh").stiffness
    old = next(e for e in model.elements if e.name == "mesh").stiffness
    t = np.linspace(0.0, 2 * old.period, 50)
    np.testing.assert_allclose(law(t), 2 * old(t))


def test_sensitivity_maps_leave_out_rigid_modes_and_silent_parameters(cycloid):
    from reducerlab.plot.modal import plotly_sensitivity

    _, _, sens = cycloid
    cells = sens.map_cells()
    assert cells.rigid == [1]  # the rigid-body mode: no frequency to move
    # the centripetal terms and the speed do move the modes, by m Omega^2 / k ~ 1e-5:
    # truly small, not a bug, and left out of the map, named
    rel = sens.data["relative"].sel(parameter="speed").values[1:]
    assert 0 < np.max(np.abs(rel)) < 1e-4
    assert "speed" in cells.negligible
    assert {p for p in cells.negligible if p.startswith("centripetal")} == {
        f"centripetal_{b}.{f}"
        for b in ("input_shaft", "centre_disc", "planetary_disc")
        for f in ("mass", "ratio")
    }
    assert cells.at_zero == ["k1u.stiffness", "k2u.stiffness"]  # 0 N m/rad supports
    assert "no effect on any mode" in cells.note().lower() and "speed" in cells.note()
    fig = plotly_sensitivity(sens)
    heat = fig.data[0]
    assert len(heat.y) == 6 and not any(y.split(": ")[1] == "0 Hz" for y in heat.y)
    assert "speed" not in heat.x and "cycloid_pairs.stiffness" in heat.x
    assert np.asarray(heat.z).shape == (6, len(heat.x))
    # the mode bar sits in the top margin, over no cell; the height follows the rows
    assert fig.layout.margin.t >= 35
    bottom = fig.layout.margin.b
    assert fig.layout.height == fig.layout.margin.t + bottom + max(180, 30 * 6)
    assert fig.layout.meta["left_out"] == cells.note()
    still = sens.plot()
    ax = still.axes[0]
    assert [t.get_text().split(": ")[0] for t in ax.get_yticklabels()] == [
        "2", "3", "4", "5", "6", "7"
    ]  # fmt: skip
    assert "speed" in still._supxlabel.get_text()
    assert min(t.get_fontsize() for t in ax.texts) >= 9


def test_the_report_names_what_the_sensitivity_map_leaves_out():
    from reducerlab.reporting import report

    r = report(example_dir() / "cycloid_ball.toml", only=["sensitivity"])
    s = next(s for s in r.sections if s.id == "sensitivity")
    assert s.values["map_left_out"]["rigid_modes"] == [1]
    assert "speed" in s.values["map_left_out"]["negligible"]
    assert "No effect on any mode" in r.html and "rigid-body modes left out" in r.html


def _chain(n: int):
    from reducerlab.model import Coupling, Dof, Inertia, Model, Support

    dofs = [Dof(f"m{i}", "x") for i in range(n)]
    els = [Inertia(f"m{i}.x", 1.0 + 0.01 * i) for i in range(n)]
    els += [
        Coupling({f"m{i}.x": 1.0, f"m{i + 1}.x": -1.0}, 1e6 * (1 + 0.02 * i), name=f"k{i}")
        for i in range(n - 1)
    ]
    els.append(Support("m0.x", 1e6, name="ground"))
    return Model(dofs, els, name="chain")


def test_energy_maps_of_many_dofs_stay_readable(cycloid):
    from reducerlab.plot.modal import MAX_COLUMNS, REPORT_WIDTH, energy_columns

    res = modal(_chain(60))
    kinetic, klabels, strain, elements, dropped = energy_columns(res)
    assert kinetic.shape[1] == len(klabels) == MAX_COLUMNS
    assert strain.shape[1] == len(elements) == MAX_COLUMNS
    assert klabels[-1].startswith("other DOFs (") and elements[-1].startswith("other elements (")
    np.testing.assert_allclose(kinetic.sum(axis=1), 1.0, atol=1e-9)  # nothing lost
    fig = res.plot_energy()
    assert fig.get_figwidth() <= REPORT_WIDTH
    sizes = [t.get_fontsize() for a in fig.axes for t in a.texts]
    sizes += [t.get_fontsize() for a in fig.axes for t in a.get_xticklabels()]
    assert min(sizes) >= 9
    # elements that take no strain energy in any mode are named, not drawn
    _, res, _ = cycloid
    *_, elements, dropped = energy_columns(res)
    assert dropped == [f"centripetal_{b}" for b in ("input_shaft", "centre_disc", "planetary_disc")]
    assert not set(dropped) & set(elements)
    assert "centripetal_input_shaft" in res.plot_energy()._supxlabel.get_text()


def test_kinematics_panels_keep_their_tick_labels_apart():
    from reducerlab.analysis.kinematics import kinematics
    from reducerlab.drives import kinematics_of

    drive, speed = kinematics_of(load_design(example_dir() / "nutation_double_sided.toml"))
    fig = kinematics(drive, speed).plot()
    left, right = fig.axes[:2]
    assert list(left.get_xticks()) == [0, 90, 180, 270, 360]
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig.set_dpi(110)  # as the report shows it
    r = FigureCanvasAgg(fig).get_renderer()
    fig.draw(r)

    def labels(ax):
        return sorted(
            (t for t in ax.get_xticklabels() if t.get_text()), key=lambda t: t.get_position()[0]
        )

    last, first = labels(left)[-1], labels(right)[0]
    gap = first.get_window_extent(r).x0 - last.get_window_extent(r).x1
    assert gap >= 8  # px
