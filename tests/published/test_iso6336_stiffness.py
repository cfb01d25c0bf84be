"""ISO 6336-1:2019 clause 9, method B: single stiffness c' and mesh stiffness c_gamma_alpha
of spur gear pairs (reducerlab.contact.iso6336). Values recomputed by hand from the
standard's formulas (the standard gives no worked spur example in its text; ISO/TR 6336-30
examples are helical)."""

from __future__ import annotations

import math

import pytest

from reducerlab.contact.iso6336 import (
    ISO_STIFFNESS_TO_SI,
    basic_rack_factor,
    iso6336_q,
    mesh_stiffness_c_gamma,
    pitch_point_stiffness,
    single_pair_stiffness,
)
from reducerlab.errors import ReducerlabError
from reducerlab.geometry.spur import SpurGear, SpurPair

A20 = math.radians(20.0)


def gear(z, x=0.0, **kw):
    return SpurGear(z, 2e-3, 20e-3, shift=x, **kw)


def test_basic_rack_factor():
    # C_B = (1 + 0.5 (1.2 - h_fP/m)) (1 - 0.02 (20 - alpha_deg)): ISO 53 -> 0.975
    assert basic_rack_factor(1.25, A20) == pytest.approx(0.975, rel=1e-15)
    assert basic_rack_factor(1.2, A20) == pytest.approx(1.0, rel=1e-15)
    assert basic_rack_factor(1.4, math.radians(25.0)) == pytest.approx(0.9 * 1.1, rel=1e-14)


def test_large_gears_approach_the_rack_limit():
    # z1 = z2 -> infinity, x = 0: c'_th -> 1 / C1 = 1 / 0.04723 = 21.17 N/(mm um);
    # c' = c'_th C_M C_R C_B = 21.17 * 0.8 * 1 * 0.975 = 16.51 N/(mm um)
    limit = 0.8 * 0.975 / 0.04723
    assert pytest.approx(21.17, abs=5e-3) == 1 / 0.04723
    values = [single_pair_stiffness(gear(z), gear(z)) for z in (30, 300, 10**6)]
    assert values[0] < values[1] < values[2] < limit
    assert values[2] == pytest.approx(limit, rel=1e-5)
    assert limit == pytest.approx(16.51, abs=5e-3)
    # C_M = C_R = C_B = 1 leaves the theoretical single stiffness
    big = gear(10**6, dedendum=1.2)
    assert single_pair_stiffness(big, big, correction=1.0) == pytest.approx(1 / 0.04723, rel=1e-5)


def test_worked_example_z20_z40():
    # z 20/40, x = 0, ISO 53 rack: q' = 0.04723 + 0.15551/20 + 0.25791/40 mm um/N
    q = 0.04723 + 0.15551 / 20 + 0.25791 / 40
    assert q == pytest.approx(0.06145325, rel=1e-12)
    c = 0.8 * 1.0 * 0.975 / q  # = 12.6926 N/(mm um)
    p, w = gear(20), gear(40)
    assert single_pair_stiffness(p, w) == pytest.approx(c, rel=1e-14)
    assert c == pytest.approx(12.6926, abs=5e-5)
    # contact ratio of the standard pair (ISO 21771 closed form), c_gamma_alpha
    rb1, rb2 = 20e-3 * math.cos(A20), 40e-3 * math.cos(A20)
    g = math.sqrt(22e-3**2 - rb1**2) + math.sqrt(42e-3**2 - rb2**2) - 60e-3 * math.sin(A20)
    eps = g / (math.pi * 2e-3 * math.cos(A20))
    assert SpurPair(p, w).contact_ratio == pytest.approx(eps, rel=1e-13)
    assert mesh_stiffness_c_gamma(p, w) == pytest.approx(c * (0.75 * eps + 0.25), rel=1e-13)
    assert mesh_stiffness_c_gamma(p, w, contact_ratio=1.6) == pytest.approx(c * 1.45)
    # SI: N/(mm um) = 1e9 N/m per m of face width
    assert single_pair_stiffness(p, w, si=True) == pytest.approx(c * 1e9, rel=1e-14)
    assert ISO_STIFFNESS_TO_SI == 1e9
    assert mesh_stiffness_c_gamma(p, w, si=True) == pytest.approx(
        mesh_stiffness_c_gamma(p, w) * 1e9, rel=1e-14
    )


def test_shifted_pair_and_consistency_with_the_pitch_point_stiffness():
    p, w = gear(18, 0.4, dedendum=1.2), gear(45, 0.1, dedendum=1.2)
    q = iso6336_q(18, 45, 0.4, 0.1)
    c = single_pair_stiffness(p, w)
    assert c == pytest.approx(0.8 / q, rel=1e-14)  # C_B = 1 for h_fP = 1.2 m
    # paper 004 Eq. 7 (pitch_point_stiffness): k_C = 0.8 b / q' == c' b (SI)
    b = 0.02
    k = pitch_point_stiffness(b, 18, 45, 0.4, 0.1)
    assert single_pair_stiffness(p, w, si=True) * b == pytest.approx(k, rel=1e-14)
    # a non-default centre distance changes eps_alpha, not c'
    a = SpurPair(p, w).a + 0.2e-3
    eps = SpurPair(p, w, a).contact_ratio
    assert mesh_stiffness_c_gamma(p, w, center_distance=a) == pytest.approx(c * (0.75 * eps + 0.25))


def test_material_and_low_load_factors():
    p, w = gear(20), gear(40)
    c = single_pair_stiffness(p, w)
    # E / E_st, E_st = 206000 N/mm^2
    assert single_pair_stiffness(p, w, youngs_modulus=103e9) == pytest.approx(0.5 * c)
    # specific load F_t K_A / b >= 100 N/mm: no change; 50 N/mm: times (50/100)^0.25
    assert single_pair_stiffness(p, w, specific_load=2e5) == pytest.approx(c)
    assert single_pair_stiffness(p, w, specific_load=5e4) == pytest.approx(c * 0.5**0.25)


def test_bad_input_is_named():
    p, w = gear(20), gear(40)
    with pytest.raises(ReducerlabError, match=r"^pinion.shift, wheel.shift"):
        single_pair_stiffness(gear(20, -0.1), gear(40, 0.3))
    single_pair_stiffness(gear(20, -0.1), gear(40, 0.3), check_range=False)
    with pytest.raises(ReducerlabError, match=r"^pinion"):
        single_pair_stiffness(20, w)
    with pytest.raises(ReducerlabError, match=r"^correction"):
        single_pair_stiffness(p, w, correction=0.0)
    with pytest.raises(ReducerlabError, match=r"^specific_load"):
        single_pair_stiffness(p, w, specific_load=-1.0)
    with pytest.raises(ReducerlabError, match=r"^youngs_modulus"):
        single_pair_stiffness(p, w, youngs_modulus=float("inf"))
    with pytest.raises(ReducerlabError, match=r"^contact_ratio"):
        mesh_stiffness_c_gamma(p, w, contact_ratio=0.9)
