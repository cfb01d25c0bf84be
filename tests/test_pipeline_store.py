"""The stage cache of ``reducerlab run`` (issue 27): keys hash only what a stage
depends on; entries are complete or absent; a damaged entry is recomputed, never used."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.pipeline.stages import design_inputs
from reducerlab.pipeline.store import Store
from reducerlab.results import Result


@pytest.fixture(scope="module")
def double():
    return load_design(example_dir() / "nutation_double_sided.toml")


def test_keys_follow_the_inputs_only(tmp_path):
    s = Store(tmp_path)
    a = s.key("contact", {"torque": 10.0, "design": {"gear2.teeth": 26}})
    assert a == s.key("contact", {"design": {"gear2.teeth": 26}, "torque": 10.0})
    assert a != s.key("contact", {"torque": 10.5, "design": {"gear2.teeth": 26}})
    assert a != s.key("body", {"torque": 10.0, "design": {"gear2.teeth": 26}})


def test_damping_changes_the_dynamics_key_only(double):
    damped = double.with_values({"mesh1.damping": 900.0, "support2.c_x": 1000.0})
    for kind, attrs in (("contact", {"pair": 1}), ("contact", {"pair": 2}),
                        ("body-modal", {"gear": 2})):  # fmt: skip
        assert design_inputs(kind, damped, attrs) == design_inputs(kind, double, attrs)
    assert design_inputs("response", damped, {}) != design_inputs("response", double, {})


def test_tooth_geometry_changes_the_contact_and_body_keys(double):
    other = double.with_values({"surface.face_width": 0.011})
    assert design_inputs("contact", other, {"pair": 1}) != design_inputs(
        "contact", double, {"pair": 1}
    )
    blank = double.with_values({"gear2.blank.bore": 0.028})
    assert design_inputs("body-modal", blank, {"gear": 2}) != design_inputs(
        "body-modal", double, {"gear": 2}
    )
    # the blank of gear 2 is not in the contact (tooth models hold teeth and rim only)
    assert design_inputs("contact", blank, {"pair": 1}) == design_inputs(
        "contact", double, {"pair": 1}
    )


def _Toy(data: xr.Dataset) -> Result:
    """A small stored result (an existing kind: a test must not add kinds to the
    registry that other tests list)."""
    from reducerlab.analysis.response import ResponseResult

    return ResponseResult(data)


def test_put_get_round_trip_and_damaged_entries(tmp_path):
    s = Store(tmp_path / "cache")
    res = _Toy(xr.Dataset({"a": ("x", np.arange(3.0))}, attrs={"title": "t"}))
    key = s.key("toy", {"n": 3})
    assert s.get("toy", key) is None
    s.put("toy", key, {"n": 3}, res, extra={"matrix": np.eye(2)})
    back, more = s.get("toy", key, extra=True)
    assert np.array_equal(back.data["a"].values, np.arange(3.0))
    assert np.array_equal(more["matrix"], np.eye(2))
    assert not list((tmp_path / "cache").glob(".tmp-*"))  # nothing half-written left
    s.file("toy", key, ".nc").write_bytes(b"not a netCDF file")
    assert s.get("toy", key) is None  # damaged: dropped, to be recomputed
    assert not s.has("toy", key)


def test_an_entry_without_its_record_is_absent(tmp_path):
    s = Store(tmp_path)
    res = _Toy(xr.Dataset({"a": ("x", np.arange(2.0))}))
    key = s.key("toy", {})
    s.put("toy", key, {}, res)
    s.file("toy", key, ".json").unlink()  # the record is written last: an interrupted put
    assert s.get("toy", key) is None


def test_a_file_in_place_of_the_cache_folder_is_refused(tmp_path):
    f = tmp_path / "cache"
    f.write_text("x")
    with pytest.raises(Exception, match="not a folder"):
        Store(f)


def test_each_gear_and_pair_has_its_own_key(double):
    from reducerlab.pipeline.stages import body_inputs

    s = Store("unused")
    keys = {s.key("body", body_inputs(double, g)) for g in range(1, 5)}
    assert len(keys) == 4  # gears without a blank share their design fields
