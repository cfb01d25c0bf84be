"""The work and memory estimates every command checks before it allocates
(reducerlab.budget): refusals give the estimate, the limit and the setting to change."""

import math

import pytest

from reducerlab.budget import MEMORY_ENV, Estimate, format_bytes, memory_limit
from reducerlab.errors import BudgetError, ReducerlabError


def test_memory_limit_is_a_share_of_what_is_available(monkeypatch):
    monkeypatch.delenv(MEMORY_ENV, raising=False)
    limit = memory_limit()
    assert 0 < limit < math.inf


@pytest.mark.parametrize(
    "text, expected",
    [
        ("1000", 1000.0),
        ("4G", 4 * 2**30),
        ("4GiB", 4 * 2**30),
        ("512m", 512 * 2**20),
        ("2 K", 2048.0),
    ],
)
def test_the_environment_lowers_the_limit(monkeypatch, text, expected):
    monkeypatch.setenv(MEMORY_ENV, text)
    assert memory_limit() == pytest.approx(min(expected, memory_limit()))
    assert memory_limit() <= expected


@pytest.mark.parametrize("text", ["lots", "-4G", "0", "nan"])
def test_a_bad_environment_limit_is_named(monkeypatch, text):
    monkeypatch.setenv(MEMORY_ENV, text)
    with pytest.raises(BudgetError, match=MEMORY_ENV):
        memory_limit()


def test_memory_beyond_the_limit_is_refused_with_estimate_limit_and_setting(monkeypatch):
    monkeypatch.setenv(MEMORY_ENV, "1G")
    est = Estimate("contact: the cell grid", 53.6 * 2**30, 1.2e9, "cells", control="--cell")
    with pytest.raises(BudgetError) as info:
        est.check()
    msg = str(info.value)
    assert "53.6 GiB" in msg and "1 GiB" in msg and "--cell" in msg and "1.2e+09 cells" in msg
    assert isinstance(info.value, ReducerlabError)
    # within the limit: returned unchanged
    small = Estimate("contact: the cell grid", 2**20, 1e4, "cells")
    assert small.check() is small


def test_work_beyond_its_documented_bound_is_refused(monkeypatch):
    monkeypatch.delenv(MEMORY_ENV, raising=False)
    with pytest.raises(
        BudgetError, match=r"2e\+06 DOFs exceeds the limit of 1e\+06 DOFs; change tooth_size"
    ):
        Estimate("body-modal: the mesh", 1.0, 2e6, "DOFs", 1e6, control="tooth_size").check()
    with pytest.raises(BudgetError):  # NaN work is never within a bound
        Estimate("x", 1.0, math.nan, "steps", 10.0).check()
    with pytest.raises(BudgetError):
        Estimate("x", math.inf).check()


def test_format_bytes():
    assert format_bytes(512) == "512 B"
    assert format_bytes(1.5 * 2**20) == "1.5 MiB"
    assert format_bytes(53.6 * 2**30) == "53.6 GiB"
    assert "unbounded" in format_bytes(math.inf)
