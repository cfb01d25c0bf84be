"""Hostile command lines for the newer commands (issue 26): ``body-modal``, ``contact``,
``check`` and ``report``, each option given values that must be refused (non-finite,
negative, zero, absurdly small or large, a wrong unit, misreadable text, a device or a
folder where a file is expected, another design's result).

Every case must be refused with exit code 2 and one clean message that names the option
or the design field, before any meshing or contact solving, and never with a traceback.
The suite runs the cases in-process (``tests/test_fuzz_commands.py``);
``benchmarks/fuzz_commands.py`` runs them (and seeded random combinations) as separate
processes under a memory cap and a time limit and counts the outcomes
(``docs/reliability.md``).
"""

from __future__ import annotations

import random
from dataclasses import dataclass

from reducerlab.examples import example_dir

SURFACE = str(example_dir() / "nutation_surface.toml")
GEAR = str(example_dir() / "gear_pair.toml")

#: Hostile values of a quantity option (a length, a power, an angle): each must be refused.
QUANTITY = ["nan", "inf", "-1", "0", "1e300", "1e-300", "5 kg", "abc", "", "1,5", "1e3e3"]
#: Hostile values of a count option.
COUNT = ["-1", "0", "1000000000", "abc", "1.5"]

#: Extra hostile values of the size options, inside their kind's range but far beyond
#: the memory or work a run may take (refused by the estimate before meshing).
TINY_CELLS = ["1e-4 mm", "1e-6 m", "1e-9"]
TINY_ELEMENTS = ["0.01 mm", "1e-5 m", "1e-9"]


@dataclass(frozen=True)
class Case:
    """One command line and the words its refusal must contain (any one of them)."""

    args: tuple[str, ...]
    names: tuple[str, ...]

    @property
    def label(self) -> str:
        return " ".join(a if len(a) < 40 else a[:37] + "..." for a in self.args)


def _option(base: list[str], option: str, values: list[str], names=None) -> list[Case]:
    return [Case((*base, option, v), tuple(names or (option,))) for v in values]


def cases(tmp: str) -> list[Case]:
    """Every single-option case; ``tmp`` is a scratch folder (a folder and a text file
    in it stand for wrong paths)."""
    folder, text = f"{tmp}/folder", f"{tmp}/note.txt"
    body = ["body-modal", SURFACE, "--gear", "1", "--no-renders", "--no-convergence",
            "-o", f"{tmp}/bm"]  # fmt: skip
    contact = ["contact", SURFACE, "--power", "1 kW", "-o", f"{tmp}/ct"]
    out: list[Case] = []
    out += _option(body, "--tooth-size", QUANTITY + TINY_ELEMENTS, ["--tooth-size", "tooth size"])
    out += _option(body, "--body-size", QUANTITY + TINY_ELEMENTS, ["--body-size", "body size"])
    out += _option(body, "--modes", COUNT)
    out += _option(body, "--gear", ["0", "3", "99", "x"])
    out += _option(body, "--boundary", ["clamped", ""])
    out += _option(body, "--set", ["surface.rim=nan", "surface.rim=-1 mm", "surface.rim=5 kg",
                                   "surface.face_width=1e300"], ["surface."])  # fmt: skip
    # a blank that reaches past the axis of the external gear 2 (gmsh "Could not revolve")
    body2 = [*body[:3], "2", *body[4:]]
    out += _option(body2, "--set", ["surface.rim=40 mm", "surface.rim=1 m"], ["rim"])
    power = ["contact", SURFACE, "-o", f"{tmp}/ct"]
    out += _option(power, "--power", QUANTITY)
    out += _option(power, "--torque", QUANTITY)
    out += _option(contact, "--cell", QUANTITY + TINY_CELLS, ["--cell", "cell"])
    out += _option(
        contact, "--tooth-size", QUANTITY + TINY_ELEMENTS, ["--tooth-size", "tooth size"]
    )
    out += _option(contact, "--positions", COUNT)
    out += _option(contact, "--order", ["-1", "1000000000", "x"], ["--order", "order"])
    out += _option(contact, "--pair", ["0", "9", "x"], ["--pair", "pair"])
    out += _option(contact, "--profile", ["cycloid", ""])
    for misalign in ("--axial-external", "--axial-internal", "--offset"):
        out += _option(contact, misalign, ["nan", "inf", "1e300", "5 kg", "abc", "1 km"],
                       [misalign, "misalignment."])  # fmt: skip
    out += _option(contact, "--shaft-angle", ["nan", "inf", "1e300", "5 kg", "90 deg"],
                   ["--shaft-angle", "misalignment.shaft_angle"])  # fmt: skip
    out += _option(contact, "--write-design", [f"{text}/x.toml", folder, "/dev/null"],
                   ["--write-design"])  # fmt: skip
    check = ["check", GEAR]
    out += _option(check, "--body-modes", ["/dev/null", folder, f"{tmp}/missing.nc", text],
                   ["--body-modes", "result", "file"])  # fmt: skip
    out += _option(check, "--margin", ["nan", "-0.1", "2", "inf", "x"], ["margin"])
    out += _option(check, "--speed-range", ["1000", "3000,1000", "nan,1", "1,1e30", "a,b", ""],
                   ["--speed-range"])  # fmt: skip
    out += _option(check, "--format", ["xml", ""])
    report = ["report", GEAR]
    out += _option(report, "--with", ["/dev/null", folder, f"{tmp}/missing.nc", text],
                   ["--with", "result", "file"])  # fmt: skip
    out += _option(report, "--section", ["nonexistent", ""], ["--section", "section"])
    out += _option(report, "-o", ["/dev/null/r.html", f"{tmp}/r.txt", f"{text}/r.html"],
                   ["-o", "--output", "output"])  # fmt: skip
    return out


def combinations(tmp: str, n: int, seed: int) -> list[Case]:
    """``n`` seeded random cases of two hostile options each (same command)."""
    rng = random.Random(seed)
    singles = cases(tmp)
    by_base: dict[tuple[str, ...], list[Case]] = {}
    for c in singles:
        by_base.setdefault(c.args[:-2], []).append(c)
    out = []
    bases = sorted(by_base)
    while len(out) < n:
        group = by_base[rng.choice(bases)]
        a, b = rng.sample(group, 2) if len(group) > 1 else (group[0], group[0])
        if a.args[-2] == b.args[-2]:
            continue
        out.append(Case((*a.args, *b.args[-2:]), a.names + b.names))
    return out
