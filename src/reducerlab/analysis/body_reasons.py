"""The verdict's reasons about gear bodies (issue 27): body modes crossing or near an
excitation line, and coinciding with system modes, ranked by margin; a repeated root
(a body's degenerate pair, a repeated system mode) named once with all its mode
numbers."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from .reasons import reason
from .resonance import ResonanceResult

__all__ = ["REPEATED", "body_reasons"]


#: Two roots within this relative distance are one repeated root (the degenerate
#: pairs of an axisymmetric body, split by its mesh; the repeated modes of the nutating
#: gear): the verdict names them together once.
REPEATED = 1e-3


def _repeated(a: float, b: float) -> bool:
    return abs(a - b) <= REPEATED * max(abs(a), abs(b))


def _merged(rows: Sequence[dict[str, Any]], freq: str, other: str | None) -> list[dict[str, Any]]:
    """Rows of one body check with the repeated roots merged: rows of one component at
    one speed whose body frequencies (``freq``) are one repeated root, and, for
    coincidences, whose system frequencies (``other``) are too, become one row whose
    ``modes`` (and ``system_modes``) list them all. Order kept (the first row's)."""
    groups: list[dict[str, Any]] = []
    for r in rows:
        for g in groups:
            if (
                g["component"] == r["component"]
                and g.get("excitation") == r.get("excitation")
                and _repeated(g["speed_rpm"], r["speed_rpm"])
                and _repeated(g[freq], r[freq])
                and (other is None or _repeated(g[other], r[other]))
            ):
                if r["mode"] not in g["modes"]:
                    g["modes"].append(r["mode"])
                if other is not None and r["system_mode"] not in g["system_modes"]:
                    g["system_modes"].append(r["system_mode"])
                break
        else:
            g = {**r, "modes": [r["mode"]]}
            if other is not None:
                g["system_modes"] = [r["system_mode"]]
            groups.append(g)
    for g in groups:
        g["modes"].sort()
        if other is not None:
            g["system_modes"].sort()
    return groups


def _numbers(word: str, ks: Sequence[int]) -> str:
    """``"mode 3"``, ``"modes 1, 2"``."""
    return f"{word}{'s' if len(ks) > 1 else ''} " + ", ".join(str(k) for k in ks)


def body_reasons(res: ResonanceResult) -> list[dict[str, Any]]:
    """Body-mode crossings and near misses with the excitations, and coincidences with
    system modes, ranked by margin (a crossing first: margin 0); a repeated root (body
    or system) is named once, with all its mode numbers."""
    rows = []
    crossed = set()
    for c in _merged(res.get("component_crossings", ()), "frequency_hz", None):
        crossed.update((c["component"], m, c["excitation"]) for m in c["modes"])
        rows.append((0.0, reason(
            "body-crossing", "risk", f"{_body(c)} ({c['frequency_hz']:.5g} Hz) crosses "
            f"{c['excitation']} at {c['speed_rpm']:.5g} rpm", 0.0, res["margin"],
            component=c["component"], mode=c["mode"], modes=c["modes"],
            excitation=c["excitation"], speed_rpm=c["speed_rpm"],
            frequency_hz=c["frequency_hz"])))  # fmt: skip
    near = [r for r in res.get("component_near", ())
            if (r["component"], r["mode"], r["excitation"]) not in crossed]  # fmt: skip
    for r in _merged(near, "natural_hz", None):
        rows.append((r["distance"], reason(
            "body-near", "risk", f"{_body(r)} ({r['natural_hz']:.5g} Hz) within "
            f"{100 * r['distance']:.2f} % of {r['excitation']} ({r['excitation_hz']:.5g} Hz) at "
            f"{r['speed_rpm']:.5g} rpm", r["distance"], res["margin"],
            component=r["component"], mode=r["mode"], modes=r["modes"],
            excitation=r["excitation"], speed_rpm=r["speed_rpm"],
            frequency_hz=r["natural_hz"])))  # fmt: skip
    for r in _merged(res.get("coincidences", ()), "natural_hz", "system_hz"):
        rows.append((r["distance"], reason(
            "body-coincidence", "risk", f"{_body(r)} ({r['natural_hz']:.5g} Hz) within "
            f"{100 * r['distance']:.2f} % of {_numbers('system mode', r['system_modes'])} "
            f"({r['system_hz']:.5g} Hz) at {r['speed_rpm']:.5g} rpm", r["distance"],
            res["margin"], component=r["component"], mode=r["mode"], modes=r["modes"],
            system_mode=r["system_mode"], system_modes=r["system_modes"],
            speed_rpm=r["speed_rpm"])))  # fmt: skip
    rows.sort(key=lambda x: x[0])
    out = [r for _, r in rows]
    if res.get("components") and not out:
        labels = ", ".join(c["label"] for c in res["components"])
        out.append(reason("body", "ok", f"the gear-body modes ({labels}) keep more than "
                           f"{100 * res['margin']:g} % from every excitation and system mode",
                           None, res["margin"]))  # fmt: skip
    return out


def _body(row: dict[str, Any]) -> str:
    kind = f" ({row['type']})" if row.get("type") else ""
    return f"{row['component']} {_numbers('mode', row.get('modes', [row['mode']]))}{kind}"
