"""Mode shapes as the drive moving (issue 32): the layout of each drive type's bodies,
their motion under a mode, the still and the animated 3-D figure, and the heat maps'
readable text."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.modal import frequency_sensitivity, modal
from reducerlab.drives import build_model, drive_layout, has_model, load_design
from reducerlab.drives.places import rotation
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir, example_files
from reducerlab.plot.drive_shape import (
    FRACTION,
    FRAMES_PER_CYCLE,
    body_points,
    deformed_points,
    plotly_drive_shapes,
    shape_values,
)


def _setup(name: str):
    design = load_design(example_dir() / f"{name}.toml")
    model = build_model(design)
    return design, model, modal(model), drive_layout(design, model)


@pytest.fixture(scope="module")
def gear_pair():
    return _setup("gear_pair")


@pytest.fixture(scope="module")
def khv():
    return _setup("khv")


def test_every_body_of_every_example_model_has_a_place():
    for path in example_files():
        design = load_design(path)
        if not has_model(design):
            continue
        model = build_model(design)
        layout = drive_layout(design, model)
        bodies = {d.body for d in model.dofs}
        assert bodies <= set(layout.bodies), path.name
        assert layout.size > 0
        for p in layout.places:
            assert np.linalg.norm(p.axis) == pytest.approx(1.0)


def test_gear_pair_gears_sit_a_centre_distance_apart(gear_pair):
    design, _, _, layout = gear_pair
    pinion, gear = layout["pinion"], layout["gear"]
    m = design.mesh.module
    a = m * (design.pinion.teeth + design.gear.teeth) / 2
    assert np.linalg.norm(np.subtract(gear.centre, pinion.centre)) == pytest.approx(a)
    assert pinion.radius == pytest.approx(m * design.pinion.teeth / 2)
    assert gear.axis == pinion.axis == (0.0, 0.0, 1.0)


def test_nutating_gear_is_tilted_and_its_pitch_circles_touch_the_other_gears():
    design, _, _, layout = _setup("nutation_double_sided")
    th = design.theta
    g13, g2, g4 = layout["g13"], layout["g2"], layout["g4"]
    assert math.acos(g13.axis[2]) == pytest.approx(th)  # tilted by the nutation angle
    assert g2.centre[2] < 0 < g4.centre[2]  # the external gears on either side
    (off1, r1), (off3, r3) = g13.rings
    e1, _, a = g13.frame()
    # a common apex: gear 1's pitch circle meets gear 2's at +x, gear 3's meets gear
    # 4's at -x (the mean cone distances agree to the design's tolerance, 1e-3)
    tol = 2e-3 * design.cone_distances(th)[0]
    np.testing.assert_allclose(off1 * a + r1 * e1, np.add(g2.centre, (g2.radius, 0, 0)), atol=tol)
    np.testing.assert_allclose(off3 * a - r3 * e1, np.add(g4.centre, (-g4.radius, 0, 0)), atol=tol)
    single = _setup("nutation_surface")[3]
    assert set(single.bodies) == {"g2", "g13"} and len(single["g13"].rings) == 1


def test_khv_planet_rides_the_carrier_and_the_ring_is_fixed(khv):
    design, model, _, layout = khv
    a = design.gears.pair().centre_distance
    planet = layout["planet"]
    assert np.hypot(*planet.centre[:2]) == pytest.approx(a) and planet.carrier == "carrier"
    assert "ring" in layout.bodies and "ring" not in {d.body for d in model.dofs}
    # the carrier's turn carries the planet's centre round the drive's axis
    turn = 0.2
    t, R = layout.motion({"carrier.u": turn * layout.u_radius["carrier"]})["planet"]
    moved = np.add(planet.centre, t)
    assert np.hypot(*moved[:2]) == pytest.approx(a)
    assert math.atan2(moved[1], moved[0]) == pytest.approx(turn)
    np.testing.assert_allclose(R, np.eye(3), atol=1e-15)  # its own turn is its own DOF


def test_cycloid_planetary_disc_sits_on_the_eccentric():
    design, _, _, layout = _setup("cycloid_ball")
    assert layout["planetary_disc"].centre == pytest.approx((design.eccentricity, 0.0, 0.0))
    assert layout["centre_disc"].radius == pytest.approx(design.pitch_radius(38))


def test_a_lumped_model_is_laid_out_on_one_axis():
    _, model, _, layout = _setup("torsional_chain")
    z = [layout[b].centre[2] for b in ("motor", "pinion", "wheel", "load")]
    assert z == sorted(z) and len(set(z)) == 4
    assert layout["wheel"].radius == pytest.approx(0.045)  # its u radius
    assert drive_layout(model).bodies == layout.bodies  # a bare model: the same


def test_motion_twists_translates_and_tilts(gear_pair):
    _, _, _, layout = gear_pair
    t, R = layout.motion({"gear.rz": 0.1})["gear"]
    np.testing.assert_allclose(t, 0.0)
    np.testing.assert_allclose(R, rotation((0, 0, 1), 0.1))
    t, R = layout.motion({"pinion.x": 1e-3, "pinion.y": -2e-3}, scale=2.0)["pinion"]
    np.testing.assert_allclose(t, (2e-3, -4e-3, 0.0))
    np.testing.assert_allclose(R, np.eye(3))
    disc = _setup("spinning_disc")[3]
    _, R = disc.motion({"disc.rx": 0.05})["disc"]
    np.testing.assert_allclose(R @ (0, 0, 1), (0, -math.sin(0.05), math.cos(0.05)))


def test_the_nutating_gear_tilts_about_its_own_axes_through_the_nutation_centre():
    design = load_design(
        example_dir() / "nutation_double_sided.toml",
        ["tilt13.k_rx=7.65e4 N*m/rad", "tilt13.k_ry=7.65e4 N*m/rad"],
    )
    model = build_model(design)
    layout = drive_layout(design, model)
    g13 = layout["g13"]
    e1, e2, a = g13.frame()
    assert e2 == pytest.approx((0.0, 1.0, 0.0)) and abs(e1 @ a) < 1e-15
    t, R = layout.motion({"g13.ry": 0.02})["g13"]
    np.testing.assert_allclose(t, 0.0)  # about the nutation centre, which stays
    tilt = math.acos(float((R @ a)[2]))
    assert tilt == pytest.approx(design.theta + 0.02)  # tips further about its own y
    res = modal(model)
    tilting = [j for j, c in enumerate(res.classifications) if c.startswith("tilting")]
    assert tilting  # and the figure draws those modes with the gear tipping
    fig = res.plot_drive(layout, [tilting[0] + 1])
    assert len([ax for ax in fig.axes if ax.name == "3d"]) == 1


def _peak(fig, j: int, body: str, bodies: list[str]) -> np.ndarray:
    """Decoded coordinates (m) of ``body`` in mode ``j`` of the plotly figure (peak)."""
    grid = fig.layout.meta["grid"]
    trace = fig.data[fig.layout.meta["first_mode_trace"] + j * len(bodies) + bodies.index(body)]
    q = np.column_stack([np.asarray(trace[k], float) for k in "xyz"])
    return np.asarray(grid["origin"]) + grid["unit"] * q


def test_a_twist_mode_turns_the_bodies_without_moving_their_centres(khv):
    _, _, res, layout = khv
    fig = plotly_drive_shapes(res, layout)
    moving = ["drive", "carrier", "planet", "load"]
    assert fig.data[1].name == layout["ring"].label  # the fixed ring, still
    assert fig.layout.meta["first_mode_trace"] == 2
    assert [t.name for t in fig.data[2:6]] == [layout[b].label for b in moving]
    assert all(f.traces[0] == 2 for f in fig.frames)  # rest and ring stay still
    unit = fig.layout.meta["grid"]["unit"]
    for j, _ in enumerate(fig.layout.meta["modes"]):
        for body in ("drive", "load"):  # on the axis, no carrier: they only turn
            pts = _peak(fig, j, body, moving)
            rest = body_points(layout[body])
            np.testing.assert_allclose(pts[:2], rest[:2], atol=2 * unit)  # axle, centre
            tip, r = pts[4] - pts[1], rest[4] - rest[1]
            assert np.linalg.norm(tip) == pytest.approx(np.linalg.norm(r), abs=3 * unit)
    # the mode's largest twist is visible: some pointer turned by a degree or more
    turned = max(
        np.linalg.norm(_peak(fig, 0, b, moving)[4] - body_points(layout[b])[4]) for b in moving
    )
    assert turned == pytest.approx(FRACTION * layout.size, rel=0.05)


def test_a_translation_mode_translates(gear_pair):
    _, _, res, layout = gear_pair
    mode = 3  # "translational — gear 100 %": the gear's x and y
    values = shape_values(res, mode)
    assert abs(values["gear.rz"]) < 1e-9 * abs(values["gear.x"])
    fig = plotly_drive_shapes(res, layout, [mode])
    pts = _peak(fig, 0, "gear", ["pinion", "gear"])
    shift = pts - body_points(layout["gear"])
    unit = fig.layout.meta["grid"]["unit"]
    np.testing.assert_allclose(shift, np.broadcast_to(shift[0], shift.shape), atol=2 * unit)
    direction = np.array([values["gear.x"], values["gear.y"], 0.0])
    assert abs(shift[0] @ direction) == pytest.approx(
        np.linalg.norm(shift[0]) * np.linalg.norm(direction), rel=1e-3
    )
    assert np.linalg.norm(shift[0]) == pytest.approx(FRACTION * layout.size, rel=0.01)


def test_frames_menu_and_play(gear_pair):
    _, _, res, layout = gear_pair
    fig = plotly_drive_shapes(res, layout, cycles=2)
    ds = res.data
    elastic = [int(m) for m, r in zip(ds["mode"].values, ds["rigid"].values, strict=True) if not r]
    assert fig.layout.meta["modes"] == elastic
    levels = fig.layout.meta["frame_levels"]
    assert levels == sorted(levels) and levels[0] == -1 and levels[-1] == 1 and 0 in levels
    assert [f.name for f in fig.frames] == [f"s{k}" for k in range(len(levels))]
    assert all(len(f.data) == len(fig.data) - 1 for f in fig.frames)
    menu, play = fig.layout.updatemenus
    assert len(menu.buttons) == len(elastic)
    visible = menu.buttons[1].args[0]["visible"]
    assert visible[0] and sum(visible) == 1 + 2 and visible[3] and visible[4]
    sequence = play.buttons[0].args[0]
    assert len(sequence) == 2 * FRAMES_PER_CYCLE + FRAMES_PER_CYCLE // 4 + 1
    top = f"s{levels.index(1.0)}"
    assert sequence[-1] == top and sequence[0] == f"s{levels.index(0.0)}"
    # the rest frame puts every body back where the layout says
    rest = fig.frames[levels.index(0.0)].data[0]
    grid = fig.layout.meta["grid"]
    q = np.column_stack([np.asarray(rest[k], float) for k in "xyz"])
    np.testing.assert_allclose(
        np.asarray(grid["origin"]) + grid["unit"] * q,
        body_points(layout["pinion"]),
        atol=grid["unit"],
    )
    assert "15 %" in fig.layout.title.text
    with pytest.raises(ReducerlabError, match="fraction"):
        plotly_drive_shapes(res, layout, fraction=2.0)
    with pytest.raises(ReducerlabError, match="mode 99 does not exist"):
        plotly_drive_shapes(res, layout, [99])


def test_the_still_has_one_panel_per_elastic_mode(gear_pair):
    _, _, res, layout = gear_pair
    fig = res.plot_drive(layout)
    panels = [a for a in fig.axes if a.name == "3d"]
    elastic = int((res.data["rigid"].values == 0).sum())
    assert len(panels) == elastic == 5
    assert "mode 2:" in panels[0].get_title() and "15 %" in fig.get_suptitle()
    # each panel draws the bodies at rest (grey) and at the mode's peak (coloured)
    peak = deformed_points(layout, shape_values(res, 2), 1.0)
    assert len(panels[0].lines) == 2 * len(peak)
    still = res.plot_drive(layout, [2])  # nothing fixed here; the KHV ring is: dashed
    assert [h.get_label() for h in still.legends[0].legend_handles][-1] == "at rest"
    assert len(res.plot_drive(layout, [2, 3]).axes) == 2


def test_cli_writes_the_still(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    r = CliRunner().invoke(app, ["modal", str(example_dir() / "khv.toml"), "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "drive_shapes.png").stat().st_size > 10_000


def test_report_shows_the_drive_moving():
    from reducerlab.reporting import report

    r = report(example_dir() / "nutation_double_sided.toml", only=["modal"])
    html = r.html
    assert 'id="fig-drive-shapes"' in html and "scatter3d" in html
    assert 'id="fig-mode-shapes"' in html
    assert len(html.encode()) - len(r.plotly_js.encode()) < 600_000


def test_heat_maps_text_reads_on_its_cells(gear_pair):
    from reducerlab.model.inspect import parameter_paths
    from reducerlab.plot.modal import REPORT_WIDTH, plotly_sensitivity, text_colour

    _, model, res, _ = gear_pair
    assert text_colour((0.0, 0.0, 0.3, 1.0)) == "white"
    assert text_colour((0.99, 0.9, 0.2, 1.0)) == "black"
    sens = frequency_sensitivity(model, [p for p, _ in parameter_paths(model)], res)
    ax = sens.plot().axes[0]
    im = ax.images[0]
    cells = sens.map_cells()  # elastic modes x parameters that show
    rel = sens.data["relative"].values[np.ix_(cells.modes, cells.parameters)]
    for t in ax.texts:  # each value's colour from its own cell
        r, c = (round(v) for v in t.get_position())
        want = text_colour(im.cmap(im.norm(rel[c, r])))
        assert t.get_color() == want
    colours = {t.get_color() for t in ax.texts}
    assert colours == {"white", "black"}  # strong cells dark, weak ones light here
    energy = res.plot_energy()
    assert energy.get_figwidth() <= REPORT_WIDTH  # shown at its size in the report
    assert min(t.get_fontsize() for a in energy.axes for t in a.texts) >= 9
    heat = plotly_sensitivity(sens).data[0]
    assert heat.texttemplate == "%{text}" and heat.textfont.color is None  # auto contrast


def test_a_place_refuses_what_it_cannot_draw(gear_pair):
    from reducerlab.drives.places import Place, complete

    with pytest.raises(ReducerlabError, match="axis must be a non-zero 3-vector"):
        Place("gear", (0, 0, 0), (0, 0, 0), 0.1)
    with pytest.raises(ReducerlabError, match="radius must be > 0 m"):
        Place("gear", (0, 0, 0), (0, 0, 1), -0.1)
    with pytest.raises(ReducerlabError, match="placed twice"):
        complete([Place("gear", (0, 0, 0), (0, 0, 1), 0.1)] * 2, gear_pair[1])
