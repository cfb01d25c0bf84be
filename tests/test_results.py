"""ModalResult: netCDF round trip, provenance, table, JSON, figures."""

from __future__ import annotations

import json

import numpy as np
import pytest

from reducerlab import __version__
from reducerlab.analysis.modal import ModalResult, SensitivityResult, frequency_sensitivity, modal
from reducerlab.drives import build_model, load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.plot.axes import scaled_unit


@pytest.fixture(scope="module")
def example():
    design = load_design(example_dir() / "gear_pair.toml")
    model = build_model(design)
    return design, model, modal(model)


def test_provenance_in_metadata(example):
    design, _, res = example
    assert res.attrs["reducerlab_version"] == __version__
    assert res.attrs["design_hash"] == design.hash
    assert res.design["pinion"]["mass"] == pytest.approx(1.25)
    assert res.data["frequency"].attrs["units"] == "Hz"


def test_netcdf_round_trip(example, tmp_path):
    _, _, res = example
    path = res.save(tmp_path / "out" / "modal.nc")
    back = ModalResult.load(path)
    np.testing.assert_array_equal(back.frequencies, res.frequencies)
    np.testing.assert_array_equal(back.shapes, res.shapes)
    assert back.classifications == res.classifications
    assert back.dof_names == res.dof_names
    assert back.attrs["design_hash"] == res.attrs["design_hash"]
    assert back.to_dict()["frequencies_hz"] == res.to_dict()["frequencies_hz"]


def test_loading_the_wrong_kind_is_refused(example, tmp_path):
    _, model, res = example
    sens = frequency_sensitivity(model, ["mesh.stiffness"], res)
    p = sens.save(tmp_path / "s.nc")
    with pytest.raises(ReducerlabError, match="'sensitivity' result, not a 'modal'"):
        ModalResult.load(p)
    assert SensitivityResult.load(p).data["dfdp"].shape == (6, 1)
    with pytest.raises(ReducerlabError, match="no such result file"):
        ModalResult.load(tmp_path / "missing.nc")


def test_table_and_json(example):
    _, _, res = example
    lines = res.table().splitlines()
    assert len(lines) == 7 and "classification" in lines[0]
    d = json.loads(res.to_json())
    assert d["frequencies_hz"] == sorted(d["frequencies_hz"])
    assert [m["frequency_hz"] for m in d["modes"]] == d["frequencies_hz"]
    assert all(isinstance(m["classification"], str) and m["classification"] for m in d["modes"])


def test_figures(example):
    _, model, res = example
    fig = res.plot_shapes()
    panels = [f for f in fig.subfigs if f.get_visible()]
    assert len(panels) == 6
    # default: the mass-normalised shape, translations (m) over rotations (rad)
    top, bottom = panels[1].axes
    assert "m)" in top.get_ylabel() and "rad)" in bottom.get_ylabel()
    kinds = list(res.data["kind"].values)
    trans = [i for i, k in enumerate(kinds) if k in ("x", "y")]
    rot = [i for i, k in enumerate(kinds) if k == "rz"]
    for ax, rows, unit in ((top, trans, "m"), (bottom, rot, "rad")):
        factor, shown = scaled_unit(res.shapes[rows, 1], unit)  # with a prefix: mm, mrad
        assert ax.get_ylabel().endswith(f"({shown})")
        heights = [p.get_height() for p in ax.patches]
        np.testing.assert_allclose(heights, factor * res.shapes[rows, 1])
    # energy scale: bars are signed sqrt of the kinetic shares, max 1 over the mode
    energy = res.plot_shapes(scale="energy")
    heights = [p.get_height() for a in energy.subfigs[1].axes for p in a.patches]
    ke = res.data["kinetic_energy"].values[1]
    expected = np.sign(res.shapes[:, 1]) * np.sqrt(np.clip(ke, 0, None))
    expected = (expected / np.abs(expected).max())[trans + rot]
    np.testing.assert_allclose(heights, expected, atol=1e-12)
    raw = res.plot_shapes([2, 3], scale="max")
    got = [p.get_height() for a in raw.subfigs[0].axes for p in a.patches]
    assert got == pytest.approx(res.data["shape_max"].values[trans + rot, 1].tolist())
    assert len(res.plot_energy().axes) == 3  # two maps and a colour bar
    sens = frequency_sensitivity(model, ["mesh.stiffness", "support:gear.x.stiffness"], res)
    assert sens.plot().axes
    with pytest.raises(ReducerlabError, match="modes \\[9\\] do not exist"):
        res.plot_shapes([9])
    with pytest.raises(ReducerlabError, match="scale must be"):
        res.plot_shapes(scale="log")
