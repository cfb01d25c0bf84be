"""Quantity options of the command line (issue 26, item 1): a bare number (SI) and a
number with a unit pass one mechanism and the same range of their kind
(``units.QUANTITIES``), so ``--power 1e-300`` is refused like ``--power "1e-300 W"``,
before any work (the reproducers exited 0 with NaN, or allocated 21 GB)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.cli.options import quantity_option, signed_quantity
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.units import QUANTITIES

runner = CliRunner()
EX = example_dir()


@pytest.mark.parametrize("kind", ["power", "torque", "length", "time", "frequency"])
@pytest.mark.parametrize("side", ["lo", "hi"])
def test_bare_number_and_number_with_unit_share_the_range(kind, side):
    q = QUANTITIES[kind]
    bad = q.lo * 1e-3 if side == "lo" else q.hi * 1e3
    good = q.lo * 10 if side == "lo" else q.hi / 10
    assert quantity_option(repr(good), "--x", kind) == pytest.approx(good)
    assert quantity_option(f"{good!r} {q.si_unit}", "--x", kind) == pytest.approx(good)
    for text in (repr(bad), f"{bad!r} {q.si_unit}"):
        with pytest.raises(ReducerlabError, match=rf"--x: .*outside the range of a {kind}"):
            quantity_option(text, "--x", kind)


def test_signed_quantities_check_their_magnitude():
    assert signed_quantity("-0.05 mm", "--offset", "length") == pytest.approx(-5e-5)
    assert signed_quantity("0", "--offset", "length") == 0.0
    for text in ("-1e-300", "1e300", "-1e300 m"):
        with pytest.raises(ReducerlabError, match=r"--offset: .*outside the range of a length"):
            signed_quantity(text, "--offset", "length")


@pytest.mark.parametrize(
    "args, message",
    [
        (["contact", str(EX / "nutation_surface.toml"), "--power", "1e-300"],
         "--power: 1e-300 W is outside the range of a power"),
        (["contact", str(EX / "nutation_surface.toml"), "--power", "3kW", "--cell", "1e-12"],
         "--cell: 1e-12 m is outside the range of a length"),
        (["response", str(EX / "gear_pair.toml"), "--frequency", "1e300"],
         "--frequency: 1e+300 Hz is outside the range of a frequency"),
        (["body-modal", str(EX / "nutation_double_sided.toml"), "--tooth-size", "1e-12"],
         "--tooth-size: 1e-12 m is outside the range of a length"),
    ],
)  # fmt: skip
def test_the_reproducers_are_refused_before_any_work(tmp_path, args, message):
    r = runner.invoke(app, [*args, "-o", str(tmp_path / "out")])
    assert r.exit_code == 2, r.output
    assert message in r.output
    assert "Traceback" not in r.output
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
