"""The spur ``gear_pair`` design's tooth geometry fields (face width, shifts, rack)."""

import math
import tomllib
from pathlib import Path

import pytest

from reducerlab.drives import design_from_dict, load_design
from reducerlab.errors import DesignError, ReducerlabError

EXAMPLE = Path(__file__).parents[1] / "examples" / "gear_pair.toml"


def _design(**mesh):
    data = tomllib.loads(EXAMPLE.read_text())
    data["mesh"].update(mesh)
    return data


def _load(data):
    return design_from_dict(data)


def test_example_pair_contact_ratio():
    # ISO 21771 eq. for the transverse contact ratio of an unshifted 25/60 pair, m = 3 mm,
    # alpha = 20 deg: eps = (sqrt(ra1^2 - rb1^2) + sqrt(ra2^2 - rb2^2) - a sin a) / p_b
    pair = load_design(EXAMPLE).spur_pair()
    m, a = 3e-3, math.radians(20)
    r1, r2 = 25 * m / 2, 60 * m / 2
    rb1, rb2 = r1 * math.cos(a), r2 * math.cos(a)
    eps = (math.sqrt((r1 + m) ** 2 - rb1**2) + math.sqrt((r2 + m) ** 2 - rb2**2)
           - (r1 + r2) * math.sin(a)) / (math.pi * m * math.cos(a))  # fmt: skip
    assert pair.contact_ratio == pytest.approx(eps, rel=1e-9)
    assert pair.pinion.face_width == pytest.approx(0.02)


def test_missing_face_width_names_the_field():
    data = _design()
    del data["mesh"]["face_width"]
    with pytest.raises(DesignError, match=r"mesh\.face_width"):
        _load(data).spur_pair()


def test_undercut_pinion_names_its_shift():
    data = _design()
    data["pinion"]["teeth"] = 8
    with pytest.raises(ReducerlabError, match=r"pinion\.shift"):
        _load(data).spur_pair()
