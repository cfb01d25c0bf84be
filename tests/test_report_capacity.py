"""The report's load-capacity section (issue 29): the ISO safety factors of the design's
pairs, the same numbers as ``load_capacity``, and a note where the rating cannot apply."""

import math
from pathlib import Path

import pytest

from reducerlab import load_design
from reducerlab.analysis.rating import load_capacity
from reducerlab.reporting import report

EXAMPLES = Path(__file__).parents[1] / "examples"


def _section(design):
    rep = report(design, only=["capacity"])
    found = [s for s in rep.sections if s.id == "capacity"]
    return found[0] if found else None


def test_gear_pair_section_carries_the_rating():
    design = load_design(EXAMPLES / "gear_pair.toml")
    sec = _section(design)
    assert sec is not None and sec.error is None
    rating = load_capacity(design)
    assert sec.values["safety"] == rating.pairs()
    assert sec.values["minimum"]["S_H"] == pytest.approx(min(rating.pairs()["pair"]["S_H"]))
    # ISO 6336-2 Eq. 7 with sigma_H ~ sqrt(F_t): doubling the torque divides S_H by sqrt 2
    heavy = load_design(EXAMPLES / "gear_pair.toml", ["operating.torque=120 N*m"])
    assert _section(heavy).values["minimum"]["S_H"] == pytest.approx(
        sec.values["minimum"]["S_H"] / math.sqrt(2), rel=1e-9
    )


def test_double_arc_design_gets_a_note_not_a_rating():
    sec = _section(load_design(EXAMPLES / "nutation_double_sided.toml"))
    assert sec is not None and "safety" not in sec.values
    assert any("involute" in b.html for b in sec.blocks)


def test_drive_without_gear_pairs_has_no_section():
    assert _section(load_design(EXAMPLES / "cycloid_ball.toml")) is None


def test_a_given_rating_is_the_one_shown(tmp_path):
    # a rating made with other conditions (K_v = 1.5) and handed to the report (--with)
    # is the one the section shows, not a fresh one at the defaults
    from reducerlab.rating.material import RatingConditions

    design = load_design(EXAMPLES / "gear_pair.toml")
    given = load_capacity(design, conditions=RatingConditions(K_v=1.5))
    path = tmp_path / "rating.nc"
    given.save(path)
    rep = report(design, results=[path], only=["capacity"])
    (sec,) = [s for s in rep.sections if s.id == "capacity"]
    assert sec.values["safety"] == given.pairs()
    assert sec.values["safety"] != load_capacity(design).pairs()
