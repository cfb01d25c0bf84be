"""``stiffness = "contact"`` in a nutation design's ``[meshN]`` (issue 27): the loaded
contact's k(t) at the operating point, which ``reducerlab run`` puts in; every other
command refuses the model, naming the field."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from reducerlab.analysis.contact import ContactResult, design_with_contact
from reducerlab.drives import build_model, load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir

DOUBLE = example_dir() / "nutation_double_sided.toml"


def _contact(pair: int, k_m: float, amp: list[float], phase: list[float]) -> ContactResult:
    ds = xr.Dataset(
        {"amplitude": ("harmonic", amp), "phase": ("harmonic", phase)},
        coords={"harmonic": np.arange(1, len(amp) + 1)},
        attrs={"pair": pair, "k_mean": k_m},
    )
    return ContactResult(ds)


def test_contact_stiffness_is_refused_by_the_model_naming_the_field():
    d = load_design(DOUBLE, ["mesh2.stiffness=contact", "mesh2.harmonics=[]"])
    assert d.mesh2.stiffness == "contact"
    with pytest.raises(ReducerlabError, match=r'mesh2\.stiffness = "contact".*reducerlab run'):
        build_model(d)


@pytest.mark.parametrize(
    "sets, match",
    [
        (["mesh1.stiffness=contact", 'mesh1.harmonics=["1e6 N/m"]'], "mesh1.harmonics"),
        (["mesh1.stiffness=5 kg"], r"mesh1\.stiffness.*wrong dimension.*or \"contact\""),
        (["mesh1.stiffness=-3 N/m"], r"mesh1\.stiffness.*must be greater than 0"),
        (["mesh1.stiffness=contakt"], r"mesh1\.stiffness.*or \"contact\""),
    ],
)
def test_bad_mesh_stiffness_named(sets, match):
    with pytest.raises(ReducerlabError, match=match):
        load_design(DOUBLE, sets)


def test_contact_stiffness_needs_tooth_surfaces(tmp_path):
    text = DOUBLE.read_text()
    start = text.index("[surface]")
    end = text.index("[material]")
    f = tmp_path / "plain.toml"
    f.write_text(text[:start] + text[end:])
    with pytest.raises(ReducerlabError, match=r"mesh1\.stiffness.*\[surface\]"):
        load_design(f, ["mesh1.stiffness=contact", "mesh1.harmonics=[]"])


def test_the_contact_fills_the_mesh():
    d = load_design(DOUBLE, ["mesh1.stiffness=contact", "mesh1.harmonics=[]"])
    filled = design_with_contact(d, [_contact(1, 3.1e8, [1.2e7, 3e6], [0.5, -1.0])])
    assert filled.mesh1.stiffness == 3.1e8
    assert filled.mesh1.harmonics == [1.2e7, 3e6]
    assert filled.mesh1.phases == pytest.approx([0.5, -1.0])
    assert filled.mesh2 == d.mesh2  # the other pair as written
    model = build_model(filled)
    law = next(e for e in model.elements if e.name == "mesh1").stiffness
    assert law.mean == pytest.approx(3.1e8)
    with pytest.raises(ReducerlabError, match="two loaded-contact results of pair 1"):
        design_with_contact(d, [_contact(1, 3e8, [1e6], [0.0]), _contact(1, 3e8, [1e6], [0.0])])
