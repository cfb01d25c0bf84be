"""Stiffness / error laws, their flat export, and the backlash conventions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reducerlab.errors import ModelError
from reducerlab.model import Backlash, Constant, Fourier, PiecewisePolynomial, dead_zone
from reducerlab.model.laws import evaluate_flat

T = np.linspace(-0.013, 0.029, 401)


def _laws():
    return [
        Constant(2.1168e8),
        Fourier(mean=2.1168e8, amplitudes=(1.2e7, -4e6, 2e6), phases=(0.3, 1.1, -2.0), omega=950.0),
        # paper 004 Eq. 9 shape: two parabolic pieces per mesh period
        PiecewisePolynomial(
            period=1.3e-3, breaks=(0.0, 0.62), coefficients=((1.0e8, 2e8, -3e8), (4e8, -5e8, 2e8))
        ),
    ]


def test_fourier_matches_paper_000_eq8_written_out():
    law = Fourier(mean=5.0, amplitudes=(1.0, 0.5), phases=(0.2, -0.4), omega=3.0)
    t = 0.77
    expected = 5.0 + 1.0 * math.cos(3.0 * t + 0.2) + 0.5 * math.cos(6.0 * t - 0.4)
    assert float(law(t)) == pytest.approx(expected, rel=1e-15)
    assert law.mean == 5.0
    assert law.period == pytest.approx(2 * math.pi / 3.0)


@pytest.mark.parametrize("law", _laws(), ids=["constant", "fourier", "piecewise"])
def test_flat_export_evaluates_like_the_object(law):
    kind, params = law.flat()
    vals = np.array([evaluate_flat(kind, params, t) for t in T])
    np.testing.assert_allclose(vals[:, 0], law(T), rtol=1e-13)
    np.testing.assert_allclose(vals[:, 1], law.derivative(T), rtol=1e-10, atol=1e-3)


@pytest.mark.parametrize("law", _laws()[1:], ids=["fourier", "piecewise"])
def test_derivative_matches_central_difference(law):
    # away from the piecewise breaks: h = 1e-9 s, truncation ~ h^2 k''' tiny,
    # round-off ~ eps k / h ~ 1e-7 * k / period: compare at 1e-5 relative
    t = np.array([0.0003, 0.0011, 0.0021])
    h = 1e-9
    fd = (law(t + h) - law(t - h)) / (2 * h)
    np.testing.assert_allclose(law.derivative(t), fd, rtol=1e-5)


def test_piecewise_mean_is_the_exact_integral():
    law = _laws()[2]
    s = np.linspace(0, 1, 200001)
    numeric = np.trapezoid(law(s * law.period), s)
    # trapezoid on 2e5 intervals with one jump: error ~ jump / n ~ 1e-5 relative
    assert law.mean == pytest.approx(numeric, rel=1e-5)
    c = np.array(law.coefficients)
    exact = (
        c[0, 0] * 0.62 + c[0, 1] * 0.62**2 / 2 + c[0, 2] * 0.62**3 / 3
        + c[1, 0] * 0.38 + c[1, 1] * (1 - 0.62**2) / 2 + c[1, 2] * (1 - 0.62**3) / 3
    )  # fmt: skip
    assert law.mean == pytest.approx(exact, rel=1e-14)


def test_piecewise_breakpoints_and_periodicity():
    law = _laws()[2]
    bp = law.breakpoints(0.0, 2.6e-3)
    np.testing.assert_allclose(bp, [0.0, 0.806e-3, 1.3e-3, 2.106e-3, 2.6e-3], rtol=1e-12)
    np.testing.assert_allclose(law(T + law.period), law(T), rtol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(period=1.0, breaks=(0.1, 0.5), coefficients=((1,), (2,))), "start at 0"),
        (dict(period=1.0, breaks=(0.0, 0.5), coefficients=((1,),)), "2 breaks but 1"),
        (dict(period=-1.0, breaks=(0.0,), coefficients=((1,),)), "period must be > 0"),
        (dict(period=1.0, breaks=(0.0, 1.0), coefficients=((1,), (2,))), "stay < 1"),
    ],
)
def test_piecewise_rejects_bad_input(kwargs, match):
    with pytest.raises(ModelError, match=match):
        PiecewisePolynomial(**kwargs)


def test_fourier_rejects_bad_input():
    with pytest.raises(ModelError, match="omega must be > 0"):
        Fourier(mean=1.0, amplitudes=(0.1,), omega=0.0)
    with pytest.raises(ModelError, match="2 amplitudes but 1 phases"):
        Fourier(mean=1.0, amplitudes=(0.1, 0.2), phases=(0.0,), omega=1.0)
    with pytest.raises(ModelError, match="finite"):
        Constant(math.nan)


def test_backlash_conventions_full_and_half():
    # paper 000 Eq. 6: b is the full backlash, dead zone |delta| <= b/2
    # paper 004 Eq. 11: b is half the backlash, dead zone |delta| <= b
    b = 1e-4
    full, half = Backlash.full(b), Backlash.half(b)
    assert full.half_width == b / 2 and half.half_width == b
    assert full.full_width == b and half.full_width == 2 * b
    d = np.array([-2e-4, -1e-4, -0.6e-4, -0.4e-4, 0.0, 0.4e-4, 0.6e-4, 1e-4, 2e-4])
    np.testing.assert_allclose(
        full(d), [-1.5e-4, -0.5e-4, -0.1e-4, 0, 0, 0, 0.1e-4, 0.5e-4, 1.5e-4]
    )
    np.testing.assert_allclose(half(d), [-1e-4, 0, 0, 0, 0, 0, 0, 0, 1e-4], atol=1e-20)
    with pytest.raises(ModelError, match=">= 0"):
        Backlash(-1.0)


@settings(max_examples=200, deadline=None)
@given(
    st.floats(-1e-3, 1e-3, allow_nan=False),
    st.floats(0.0, 5e-4, allow_nan=False),
)
def test_dead_zone_properties(delta, h):
    f = float(dead_zone(delta, h))
    assert f == pytest.approx(-float(dead_zone(-delta, h)), abs=1e-18)  # odd
    if abs(delta) <= h:
        assert f == 0.0
    else:
        assert abs(f) == pytest.approx(abs(delta) - h, abs=1e-18)
        assert math.copysign(1.0, f) == math.copysign(1.0, delta)
