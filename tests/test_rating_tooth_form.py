"""ISO 6336-3:2019 method B tooth form (Y_F, Y_S) against the generated tooth itself.

The closed forms of clause 6.2 (Eq. 11 to 18) describe the tooth cut by the ISO 53 rack;
:class:`~reducerlab.geometry.spur.SpurGear` generates that tooth independently (the
rack tip circle's envelope, the involute). Measuring the 30 deg tangent, the fillet
radius and the load arm on those points must give the standard's numbers.
"""

from __future__ import annotations

import math

import pytest

from reducerlab.errors import ReducerlabError
from reducerlab.geometry.spur import SpurGear, SpurPair
from reducerlab.rating.iso6336_3 import (
    fillet_tangent_point,
    helix_factor,
    spur_tooth_form,
    tooth_form,
)

PAIRS = [(20, 40, 0.0, 0.0), (17, 103, 0.145, 0.0), (30, 60, 0.3, -0.2), (13, 50, 0.4, 0.1)]


@pytest.mark.parametrize("z1, z2, x1, x2", PAIRS)
def test_closed_form_matches_the_generated_tooth(z1, z2, x1, x2):
    pair = SpurPair(SpurGear(z1, 0.004, 0.02, shift=x1), SpurGear(z2, 0.004, 0.02, shift=x2))
    for name in ("pinion", "wheel"):
        tf = spur_tooth_form(pair, name)
        s_Fn, rho_F, h_Fe = fillet_tangent_point(getattr(pair, name), tf.d_en)
        # chord and arm: the same point found by bisection on 4001 fillet points, linear
        # interpolation error ~(h/rho)^2 ~ 1e-9 relative
        assert s_Fn == pytest.approx(tf.s_Fn, rel=1e-6)
        assert h_Fe == pytest.approx(tf.h_Fe, rel=1e-6)
        # curvature from three points 11 samples apart: round-off in the fillet points
        # (~1e-16 m over ~1e-5 m chords) leaves ~1e-4 relative
        assert rho_F == pytest.approx(tf.rho_F, rel=5e-4)
        assert 1.0 < tf.Y_F < 3.0 and 1.5 < tf.Y_S < 2.5


def test_load_at_the_tip_gives_the_tip_factors_of_the_standard_rack():
    # contact ratio 1: the outer point of single contact is the tip, Y_F -> Y_Fa. For
    # z = 20, x = 0 and the 20 deg basic rack (h_fP = 1.25 m) the tip-load charts of
    # DIN 3990-3:1987 (method C, Y_Fa and Y_Sa over z and x) read about 2.80 and 1.55;
    # the tolerance is the charts' reading resolution (~0.02)
    tf = tooth_form(
        teeth=20,
        module=1.0,
        pressure_angle=math.radians(20),
        shift=0.0,
        tip_diameter=22.0,
        contact_ratio=1.0,
    )
    assert abs(tf.Y_F - 2.80) <= 0.02
    assert abs(tf.Y_S - 1.55) <= 0.02


def test_helix_factor_caps_and_spur_value():
    assert helix_factor(1.3, 0.0) == 1.0
    assert helix_factor(2.0, math.radians(15)) == pytest.approx(1 - 15 / 120)
    assert helix_factor(0.5, math.radians(40)) == pytest.approx(1 - 0.5 * 30 / 120)


def test_bad_input_named():
    with pytest.raises(ReducerlabError, match="teeth"):
        tooth_form(
            teeth=3, module=1.0, pressure_angle=0.35, shift=0, tip_diameter=5, contact_ratio=1.5
        )
    with pytest.raises(ReducerlabError, match="contact_ratio"):
        tooth_form(
            teeth=20, module=1.0, pressure_angle=0.35, shift=0, tip_diameter=22, contact_ratio=-1
        )
    pair = SpurPair(SpurGear(20, 0.004, 0.02), SpurGear(40, 0.004, 0.02))
    with pytest.raises(ReducerlabError, match="gear"):
        spur_tooth_form(pair, "planet")
