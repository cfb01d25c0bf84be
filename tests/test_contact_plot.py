"""Figures of the loaded tooth contact analysis (``reducerlab.plot.contact``)."""

from __future__ import annotations

import json
import math

import matplotlib
import numpy as np
import pytest
import xarray as xr

matplotlib.use("Agg")

from reducerlab.analysis.contact import ContactResult, contact_analysis
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.plot.contact import cycle_label, plot_contact, plot_pressure_map
from reducerlab.plot.contact_flank import developed_flank as _flank
from reducerlab.plot.contact_pattern import PRESSURE_LABEL as PATTERN_LABEL

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def result() -> ContactResult:
    """A small real result: rigid teeth (no finite-element models), 5 positions."""
    design = load_design("examples/nutation_surface.toml")
    return contact_analysis(design, 1, torque=19.1, positions=5, order=2, rigid=True)


def _labels(fig):
    return [(ax.get_xlabel(), ax.get_ylabel()) for ax in fig.axes]


def _colorbars(fig):
    return [ax for ax in fig.axes if "contact pressure (MPa)" in ax.get_ylabel()]


def _legend_texts(ax) -> list[str]:
    leg = ax.get_legend()
    return [t.get_text() for t in leg.get_texts()] if leg is not None else []


def _saves(fig, path) -> None:
    fig.savefig(path, dpi=50)
    assert path.read_bytes()[:8] == PNG


def test_overview_panels(result, tmp_path):
    fig = result.figure()
    assert type(fig).__name__ == "Figure"
    # 4 panels + the twin axis of (d); the pattern's colour bar is an inset of (a)
    assert len(fig.axes) == 5
    a, b, c, d = fig.axes[:4]
    assert a.get_title().startswith("(a)") and d.get_title().startswith("(d)")
    assert a.get_xlabel() == "face width from the toe (mm)"
    assert a.get_ylabel() == "profile from the root end (mm)"
    bars = [ax for ax in a.child_axes if "contact pressure" in ax.get_ylabel()]
    assert [ax.get_ylabel() for ax in bars] == [PATTERN_LABEL]
    # (a): the highest cell is starred and named in the legend with its position
    j = int(np.argmax(result.data["peak_pressure"].values))
    p = 1e-6 * float(result.data["peak_pressure"].values[j])
    assert any(f"position {j} (" in t and f"{p:.0f} MPa" in t for t in _legend_texts(a))
    # (b): k(t) points, the dashed red Eq. 8 law with order and residual, k_m
    assert b.get_ylabel() == "mesh stiffness k (10^8 N/m)"
    texts = _legend_texts(b)
    assert any(t.startswith("Eq. 8 in the dynamic model, order 2 (residual") for t in texts)
    assert any(t.startswith("k_m = ") for t in texts)
    fits = [ln for ln in b.get_lines() if ln.get_linestyle() == "--"]
    assert len(fits) == 1 and fits[0].get_color() == "tab:red"
    pts = next(ln for ln in b.get_lines() if ln.get_label().startswith("LTCA ("))
    np.testing.assert_allclose(pts.get_ydata(), 1e-8 * result.stiffness)
    np.testing.assert_allclose(pts.get_xdata(), np.degrees(result.data["angle"].values))
    # (b)-(d) share one abscissa: gear A's rotation in deg over one mesh period
    period = 360.0 / result.data.attrs["teeth_external"]
    start = float(np.degrees(result.data["angle"].values[0]))
    for ax in (b, c, d):
        assert ax.get_xlabel() == cycle_label(result.data)
        assert ax.get_xlim() == pytest.approx((start - 0.02 * period, start + 1.02 * period))
    assert "(deg)" in b.get_xlabel() and "ms" not in b.get_xlabel()
    # (c) TE in um, (d) stresses in MPa and tooth pairs on the twin axis
    assert c.get_ylabel() == "loaded transmission error (um)"
    np.testing.assert_allclose(c.get_lines()[0].get_ydata(), 1e6 * result.data["te"].values)
    assert d.get_ylabel() == "stress (MPa)"
    assert fig.axes[4].get_ylabel() == "tooth pairs in contact"
    assert "max subsurface von Mises" in _legend_texts(d)
    _saves(fig, tmp_path / "overview.png")


def test_overview_direct_call_matches(result):
    fig = plot_contact(result.data)  # the dataset itself also works
    assert len(fig.axes) == 5


def test_developed_flank_of_a_real_result(result):
    fl = _flank(result.data)
    assert fl.mm
    face = 1e3 * json.loads(result.data.attrs["design"])["surface"]["face_width"]  # mm
    span_v = fl.ev[-1] - fl.ev[0]
    assert 0.8 * face < span_v < 1.3 * face
    # cells are about cell_m apart along both directions
    h = 1e3 * result.data.attrs["cell_m"]
    assert np.median(np.diff(fl.cv)) == pytest.approx(h, rel=0.15)
    assert np.median(np.diff(fl.cu)) == pytest.approx(h, rel=0.15)


def test_pressure_map_default_is_peak_position(result, tmp_path):
    ds = result.data
    j = int(np.argmax(ds["peak_pressure"].values))
    fig = plot_pressure_map(result)
    assert f"position {j}:" in fig._suptitle.get_text()
    here = (ds["cell_position"].values == j) & (ds["cell_force"].values > 0)
    teeth = np.unique(ds["cell_tooth"].values[here])
    panels = [ax for ax in fig.axes if ax.get_title().startswith("tooth pair")]
    assert len(panels) == len(teeth) == int(ds["pairs"].values[j])
    assert [ax.get_title().split(":")[0] for ax in panels] == [f"tooth pair {k}" for k in teeth]
    assert len(_colorbars(fig)) == 1
    assert panels[0].get_xlabel() == "face: toe -> heel (mm)"
    _saves(fig, tmp_path / "map.png")


def test_pressure_map_position_and_errors(result):
    fig = plot_pressure_map(result, position=2)
    assert "position 2:" in fig._suptitle.get_text()
    n = result.data.sizes["position"]
    for bad in (-1, n, 1.5, True, "1"):
        with pytest.raises(ReducerlabError, match="position"):
            plot_pressure_map(result, position=bad)


# ------------------------------------------------------------------ synthetic datasets


def synthetic(n: int = 3, *, empty_tooth: bool = True, nan_vm: bool = True,
              unloaded_position: int | None = None, points: bool = True) -> xr.Dataset:  # fmt: skip
    """A contact dataset with the variables of ``ContactResult``: a flat flank 10 mm
    (face, ``v`` 0..1) by 4 mm (profile, ``u`` 0.2..0.9), a diagonal contact line on
    tooth pair 0 moving with the position, tooth pair 1 in the grid but unloaded."""
    U = np.linspace(0.2, 0.9, 8)
    V = np.linspace(0.0, 1.0, 12)
    uu, vv = (a.ravel() for a in np.meshgrid(U, V, indexing="ij"))
    cols: dict[str, list] = {k: [] for k in ("pos", "tooth", "u", "v", "force")}
    for j in range(n):
        for k in (0, 1):
            line = 0.2 + 0.7 * ((vv + j / max(n, 1)) % 1.0)
            f = np.where(np.abs(uu - line) < 0.06, 10.0 + 30.0 * vv, 0.0)
            if (k == 1 and empty_tooth) or j == unloaded_position:
                f = np.zeros_like(f)
            elif k == 1:
                f = f[::-1]
            cols["pos"].append(np.full(uu.size, j))
            cols["tooth"].append(np.full(uu.size, k))
            cols["u"].append(uu)
            cols["v"].append(vv)
            cols["force"].append(f)
    c = {k: np.concatenate(v) for k, v in cols.items()}
    area = np.full(c["u"].size, (10e-3 / 11) * (4e-3 / 7))
    pk = np.array([(c["force"][c["pos"] == j] / area[0]).max() for j in range(n)])
    vm = 0.3 * pk
    depth = np.full(n, 1e-4)
    if nan_vm:
        vm[0], depth[0] = np.nan, np.nan
        if n > 2:
            vm[1], depth[1] = 0.0, np.nan  # no interior cell: not computed
    k = 6e8 + 5e7 * np.cos(2 * math.pi * np.arange(n) / n)
    order = (n - 1) // 2
    data = {
        "angle": ("position", 2 * math.pi / 26 * np.arange(n) / n),
        "time": ("position", np.arange(n) / (n * 650.0)),
        "te": ("position", 1.4e-6 + 1e-7 * np.sin(np.arange(n))),
        "stiffness": ("position", k),
        "stiffness_fit": ("position", k),
        "contact_area": ("position", np.ones(n) * 1e-6),
        "peak_pressure": ("position", pk),
        "normal_force": ("position", np.ones(n) * 500.0),
        "force": (("position", "axis"), np.ones((n, 3))),
        "von_mises": ("position", vm),
        "von_mises_depth": ("position", depth),
        "pairs": (
            "position",
            [len(np.unique(c["tooth"][(c["pos"] == j) & (c["force"] > 0)])) for j in range(n)],
        ),
        "amplitude": ("harmonic", [5e7, 0.0][:order]),
        "phase": ("harmonic", [0.0, 0.0][:order]),
        "cell_position": ("cell", c["pos"]),
        "cell_tooth": ("cell", c["tooth"]),
        "u": ("cell", c["u"]),
        "v": ("cell", c["v"]),
        "area": ("cell", area),
        "separation": ("cell", np.zeros_like(area)),
        "cell_force": ("cell", c["force"]),
        "pressure": ("cell", c["force"] / area),
    }
    if points:
        data |= {"x": ("cell", 10e-3 * c["v"]), "y": ("cell", 4e-3 * (c["u"] - 0.2) / 0.7),
                 "z": ("cell", 0.01 * c["tooth"])}  # fmt: skip
    return xr.Dataset(
        data,
        coords={
            "position": np.arange(n),
            "axis": ["x", "y", "z"],
            "harmonic": np.arange(1, order + 1),
        },
        attrs={
            "title": "synthetic contact",
            "pair": 1,
            "profile": "involute",
            "torque_external": 19.1,
            "mesh_frequency": 650.0,
            "k_mean": 6e8,
            "fit_residual": 0.0,
            "order": order,
            "cell_m": 4e-3 / 7,
        },
    )


def test_synthetic_developed_coordinates():
    fl = _flank(synthetic())
    assert fl.mm
    np.testing.assert_allclose(fl.cv, np.linspace(0.0, 10.0, 12), atol=1e-9)
    np.testing.assert_allclose(fl.cu, np.linspace(0.0, 4.0, 8), atol=1e-9)
    bare = _flank(synthetic(points=False))
    assert not bare.mm
    assert bare.xlabel == "face: toe -> heel (flank parameter v)"


def test_edge_cases_render(tmp_path):
    """Empty tooth pair, NaN von Mises (and 0 with no depth), several positions."""
    ds = synthetic(4)
    fig = plot_contact(ContactResult(ds))
    d = fig.axes[3]
    vm = next(ln for ln in d.get_lines() if ln.get_label() == "max subsurface von Mises")
    y = np.asarray(vm.get_ydata(), float)
    assert np.isnan(y[:2]).all() and np.isfinite(y[2:]).all()
    _saves(fig, tmp_path / "synthetic.png")
    # only tooth pair 0 carries load: one panel, the empty pair left out
    m = plot_pressure_map(ds)
    panels = [ax for ax in m.axes if ax.get_title().startswith("tooth pair")]
    assert [ax.get_title().split(":")[0] for ax in panels] == ["tooth pair 0"]
    _saves(m, tmp_path / "synthetic_map.png")
    # both tooth pairs loaded: two panels side by side
    two = plot_pressure_map(synthetic(3, empty_tooth=False), position=1)
    assert len([ax for ax in two.axes if ax.get_title().startswith("tooth pair")]) == 2


def test_single_position_and_all_nan(tmp_path):
    ds = synthetic(1)
    assert ds.sizes["position"] == 1 and ds.sizes["harmonic"] == 0
    fig = plot_contact(ds)
    d = fig.axes[3]
    assert "max subsurface von Mises (not computed)" in _legend_texts(d)
    assert any(
        t.startswith("Eq. 8 in the dynamic model, order 0") for t in _legend_texts(fig.axes[1])
    )
    _saves(fig, tmp_path / "single.png")
    _saves(plot_pressure_map(ds), tmp_path / "single_map.png")


def test_position_without_loaded_cells(tmp_path):
    ds = synthetic(3, unloaded_position=2)
    m = plot_pressure_map(ds, position=2)
    assert any("no loaded cells at position 2" in t.get_text() for ax in m.axes
               for t in ax.texts)  # fmt: skip
    assert not _colorbars(m)
    _saves(m, tmp_path / "none.png")
    _saves(plot_contact(ds), tmp_path / "overview.png")
    # nothing loaded anywhere
    empty = synthetic(2, unloaded_position=0)
    empty["cell_force"][:] = 0.0
    empty["pressure"][:] = 0.0
    fig = plot_contact(empty)
    assert any(t.get_text() == "no loaded cells" for t in fig.axes[0].texts)
    _saves(fig, tmp_path / "empty.png")


# ------------------------------------------------------------------ issue 32


def test_stiffness_drawn_between_samples_stays_within_them_and_law_is_the_models(result):
    """The solid k(t) curve never leaves the samples' range (shape-preserving); the
    dashed one is the model's own Fourier law (paper 000 Eq. 8) at the same times."""
    from reducerlab.model.laws import Fourier
    from reducerlab.plot.contact import stiffness_curves

    for ds in (result.data, synthetic(5), synthetic(6)):
        k = np.asarray(ds["stiffness"].values, float)
        c = stiffness_curves(ds)
        tol = 1e-9 * np.ptp(k) + 1e-6
        assert c["between"].min() >= k.min() - tol and c["between"].max() <= k.max() + tol
        # through every sample
        ang = np.degrees(ds["angle"].values)
        np.testing.assert_allclose(np.interp(ang, c["angle"], c["between"]), k, rtol=2e-3)
        f_mesh = float(ds.attrs["mesh_frequency"])
        law = Fourier(mean=float(ds.attrs["k_mean"]), amplitudes=tuple(ds["amplitude"].values),
                      phases=tuple(ds["phase"].values), omega=2 * math.pi * f_mesh)  # fmt: skip
        t = (c["angle"] - c["angle"][0]) / (c["angle"][-1] - c["angle"][0]) / f_mesh
        np.testing.assert_allclose(c["law"], law(t), rtol=1e-12)
    # the real result's Eq. 8 at the positions is the fit the analysis stored
    c = stiffness_curves(result.data, points=result.data.sizes["position"] * 40 + 1)
    np.testing.assert_allclose(c["law"][:-1:40], result.data["stiffness_fit"].values, rtol=1e-9)


def test_bearing_pattern_fills_the_flank_between_positions_inside_its_outline():
    from reducerlab.plot.contact_pattern import bearing_pattern, plot_bearing_pattern

    ds = synthetic(6)
    ds.attrs.update(flank_u_range=[0.0, 1.0], flank_tip_end=1)
    bp = bearing_pattern(ds)
    o = bp["outline"]
    # u 0.2..0.9 is 0..4 mm: u = 0 and 1 lie 8/7 mm below and 4/7 mm above; v 0..1 is 10 mm
    assert bp["mm"] and bp["tip_known"]
    assert o["tip"] == pytest.approx(4.0 / 0.7, rel=1e-9)
    assert o["heel"] == pytest.approx(10.0, rel=1e-9)
    assert bp["profile"][[0, -1]] == pytest.approx([0.0, o["tip"]], abs=1e-9)
    p = bp["pressure"]
    computed = bp["profile"][np.isfinite(p).any(axis=1)]  # the cells' rows: u 0.2..0.9
    step = bp["profile"][1] - bp["profile"][0]
    assert computed[0] == pytest.approx(8.0 / 7.0, abs=step)
    assert computed[-1] == pytest.approx(8.0 / 7.0 + 4.0, abs=step)
    cells = np.asarray(ds["pressure"].values)
    assert np.nanmax(p) <= cells.max() * (1 + 1e-12)
    assert bp["peak"][2] == pytest.approx(cells.max())
    assert _stripes(p) == 0
    fig = plot_bearing_pattern(ds)
    ax = fig.axes[0]
    outline = [ln for ln in ax.get_lines() if ln.get_color() == "k" and len(ln.get_xdata()) == 5]
    assert len(outline) == 1
    np.testing.assert_allclose(sorted(set(outline[0].get_ydata())), [0.0, o["tip"]])
    names = {t.get_text().strip() for t in ax.texts}
    assert {"tip", "root end of the flank", "toe", "heel"} <= names
    # without the flank's range: the computed rows' ends, said so
    plain = bearing_pattern(synthetic(3))
    assert not plain["tip_known"] and plain["outline"]["tip"] == pytest.approx(4.0)


def _stripes(p: np.ndarray) -> int:
    """Unloaded grid points between the first and last loaded row of each column."""
    out = 0
    for col in range(p.shape[1]):
        hit = np.flatnonzero(np.nan_to_num(p[:, col]) > 0)
        if len(hit):
            out += int(np.sum(~(np.nan_to_num(p[hit[0] : hit[-1] + 1, col]) > 0)))
    return out


def test_bearing_pattern_has_no_stripes_between_narrow_moving_lines():
    """Each position computes its own band of rows around a narrow contact line that
    moves 0.12 in u per position (as the loaded contact does): the pattern is the swept
    area, the peak pressure of the line interpolated between positions."""
    from reducerlab.plot.contact_pattern import bearing_pattern

    n, V = 6, np.linspace(0.0, 1.0, 5)
    cols: dict[str, list] = {k: [] for k in ("pos", "u", "v", "p")}
    for j in range(n):
        c = 0.2 + 0.6 * j / (n - 1)
        U = c + 0.025 * np.arange(-5, 8)  # its own rows, 0.025 apart, one on the line
        uu, vv = (a.ravel() for a in np.meshgrid(U, V, indexing="ij"))
        cols["pos"].append(np.full(uu.size, j))
        cols["u"].append(uu)
        cols["v"].append(vv)
        cols["p"].append(1e9 * (1 + j) * np.clip(1 - ((uu - c) / 0.02) ** 2, 0, None))
    c = {k: np.concatenate(v) for k, v in cols.items()}
    ds = xr.Dataset(
        {"angle": ("position", np.arange(n) * 0.01),
         "cell_position": ("cell", c["pos"]), "cell_tooth": ("cell", np.zeros_like(c["pos"])),
         "u": ("cell", c["u"]), "v": ("cell", c["v"]), "pressure": ("cell", c["p"]),
         "cell_force": ("cell", c["p"] * 1e-8)},
        coords={"position": np.arange(n)},
        attrs={"flank_u_range": [0.0, 1.0], "flank_tip_end": 1},
    )  # fmt: skip
    bp = bearing_pattern(ds)
    assert not bp["mm"]  # no cell points: bare parameters
    p = bp["pressure"]
    assert _stripes(p) == 0
    # along a column: the line's peak grows linearly from 1 GPa at u = 0.2 to 6 at 0.8
    u = bp["profile"]
    on = (u > 0.21) & (u < 0.79)
    np.testing.assert_allclose(p[on, 2], 1e9 * (1 + 5 * (u[on] - 0.2) / 0.6), rtol=0.02)


def test_report_shows_the_bearing_pattern(result):
    from reducerlab.reporting import report

    r = report("examples/nutation_surface.toml", results=[result], only=["contact"])
    sec = r.section("contact")
    assert sec.error is None
    html = "".join(b.html for b in sec.blocks if b.kind == "interactive")
    assert 'id="fig-bearing-pattern-1"' in html and '"type":"heatmap"' in html
    assert "flank outline" in html
    # its still: the overview's panel (a), a static figure beside it
    assert any(b.kind == "figure" and "bearing pattern" in b.html for b in sec.blocks)
