"""Tooth-root stress variables of the loaded contact result (issue 29).

:func:`add_root_stress` computes the root stresses of both gears at every position of a
contact run (``contact.rootstress.contact_root_stress``, from the finite-element tooth
models built with ``root_stress=True``) and adds them to the contact dataset on the
dimensions ``gear`` (``external``, ``internal``), ``position`` and ``tooth_pair``
(the modelled tooth pairs ``-1, 0, 1`` of the contact analysis).
"""

from __future__ import annotations

import math
from functools import partial
from typing import Any

import numpy as np

from ..errors import ReducerlabError
from ..numformat import fmt

__all__ = [
    "ROOT_VARIABLES",
    "add_root_stress",
    "check_root_compliance",
    "root_stress_lines",
    "root_stress_reasons",
]

#: dataset variable, PairRootStress attribute, unit, description
ROOT_VARIABLES = (
    ("root_stress", "tensile", "Pa", "largest principal stress on the loaded flank's fillet"),
    ("root_stress_radius", "tensile_radius", "m", "its distance from the gear axis"),
    ("root_stress_face", "tensile_face", "m", "its position across the face from mid-face"),
    ("root_stress_angle", "tensile_angle", "rad", "fillet tangent angle to the tooth centre line"),
    ("root_compressive", "compressive", "Pa", "most negative principal stress, opposite fillet"),
    ("root_compressive_radius", "compressive_radius", "m", "its distance from the gear axis"),
    ("root_compressive_face", "compressive_face", "m", "its position across the face"),
    ("root_compressive_angle", "compressive_angle", "rad", "its fillet tangent angle"),
    ("root_von_mises", "von_mises", "Pa", "largest von Mises stress on either fillet"),
    (
        "root_stress_face_ends",
        "end_tensile",
        "Pa",
        "largest principal stress, loaded fillet, within one module of the end faces "
        "(not converged; excluded from the others)",
    ),
)


def check_root_compliance(compliance: tuple[Any, Any] | None, rigid: bool) -> None:
    """Refuse a root-stress request that the tooth models cannot answer: rigid teeth, or
    compliances given from a run built without the fillet influence."""
    if rigid:
        raise ReducerlabError("root_stress: needs the finite-element tooth models, not rigid")
    if compliance is not None and any(getattr(c, "fillet", None) is None for c in compliance):
        raise ReducerlabError(
            "root_stress: the given tooth compliances were built without the root-stress "
            "influence; run again without compliance= (or from a run with root_stress)"
        )


def add_root_stress(ds: Any, pair: Any, runs: list, comp_a: Any, comp_b: Any) -> Any:
    """``ds`` with the root-stress variables of :data:`ROOT_VARIABLES` (dims ``gear``,
    ``position``, ``tooth_pair``) and the peak's attributes ``root_stress_peak`` (Pa),
    ``root_stress_peak_gear``, ``_position``, ``_tooth``, ``_radius`` (m), ``_face`` (m),
    ``_angle`` (deg)."""
    from ..contact.rootstress import contact_root_stress

    rs = contact_root_stress(pair, runs, comp_a, comp_b)
    dims = ("gear", "position", "tooth_pair")
    out = ds.assign_coords(gear=["external", "internal"], tooth_pair=np.array(rs.teeth))
    out = out.assign(
        {
            name: (dims, getattr(rs, attr), {"units": unit, "long_name": text})
            for name, attr, unit, text in ROOT_VARIABLES
        }
    )
    peak = rs.peak()
    gear = ["external", "internal"][peak["gear"]]
    out.attrs.update(
        root_stress_peak=peak["stress"], root_stress_peak_gear=gear,
        root_stress_peak_position=peak["position"], root_stress_peak_tooth=peak["tooth"],
        root_stress_peak_radius=peak["radius"], root_stress_peak_face=peak["face"],
        root_stress_peak_angle=math.degrees(peak["angle"]),
    )  # fmt: skip
    return out


def root_stress_lines(ds: Any) -> list[str]:
    """The peak root stress of a contact dataset and where, as text lines (MPa, mm,
    deg); empty when the dataset has no root stress."""
    if "root_stress" not in ds:
        return []
    a = ds.attrs
    mpa, mm = partial(fmt, kind="stress"), partial(fmt, kind="length")
    comp = ds["root_compressive"].values
    ends = []
    if "root_stress_face_ends" in ds and np.any(np.isfinite(ds["root_stress_face_ends"].values)):
        e = float(np.nanmax(ds["root_stress_face_ends"].values))
        ends = [
            f"loaded fillet within one module of the face ends: up to {mpa(e / 1e6)} MPa "
            "(not converged there: not in the peak; docs/contact.md)"
        ]
    return [
        f"peak tooth-root stress: {mpa(a['root_stress_peak'] / 1e6)} MPa (largest principal, "
        f"{a['root_stress_peak_gear']} gear, tooth pair {a['root_stress_peak_tooth']}, "
        f"position {a['root_stress_peak_position']})",
        f"  at radius {mm(a['root_stress_peak_radius'] * 1e3)} mm, "
        f"{mm(a['root_stress_peak_face'] * 1e3)} mm from mid-face, fillet tangent "
        f"{fmt(a['root_stress_peak_angle'], 'angle')} deg to the tooth centre line",
        f"compressive side (opposite fillet): {mpa(np.nanmin(comp) / 1e6)} MPa; fillet von "
        f"Mises up to {mpa(float(np.nanmax(ds['root_von_mises'].values)) / 1e6)} MPa",
        *ends,
    ]


def _permissible(rating: Any, index: int) -> float:
    """The smaller permissible tooth-root stress ``sigma_FP`` (Pa) of the two gears of
    the rating's pair ``index`` (0-based; the rating's first pair for a single-pair
    rating); NaN when the rating has none."""
    names = list(rating.pairs())
    name = names[index] if index < len(names) else names[0]
    values = []
    for gear in ("1", "2"):
        try:
            values.append(rating.value("sigma_FP", gear, name))
        except ReducerlabError:
            continue
    return min(values) if values else math.nan


def root_stress_reasons(contacts: dict[int, Any], rating: Any = None) -> list[dict[str, Any]]:
    """Reasons ``root-stress`` of the verdict: per contact result with the FE tooth-root
    stress, its peak beside the rating's permissible root stress.

    The FE peak is the static stress of the modelled teeth under the LTCA's load: the
    load distribution over the face and between tooth pairs is in it, the application
    and dynamic factors are not. ISO 6336-3:2019's criterion is ``sigma_F <= sigma_FP``
    (Eq. 4-5) with ``sigma_F = sigma_F0 K_A K_v K_Fbeta K_Falpha`` (Eq. 3), and every
    factor is at least 1, so a static FE peak above ``sigma_FP`` is a risk whatever the
    factors; one below it is a ``note`` (the load factors could still raise it beyond),
    never an ``ok`` (``docs/assumptions.md``).

    Parameters
    ----------
    contacts : dict
        Pair -> ContactResult; results without ``root_stress`` are passed over.
    rating : RatingResult, optional
        The design's rating (its ``sigma_FP`` of both gears of each pair; the smaller
        is the threshold); without it the peaks are notes with no threshold.

    Returns
    -------
    list of dict
        One reason a pair: ``value`` the FE peak (Pa), ``threshold`` ``sigma_FP`` (Pa,
        None without a rating), with ``pair`` and ``gear`` (``external`` or
        ``internal``, the gear of the peak).
    """
    from .reasons import reason

    out = []
    for pair, res in sorted(contacts.items()):
        a = res.data.attrs
        if "root_stress" not in res.data or "root_stress_peak" not in a:
            continue
        peak, gear = float(a["root_stress_peak"]), str(a["root_stress_peak_gear"])
        limit = math.nan if rating is None else _permissible(rating, int(pair) - 1)
        where = f"pair {pair}, {gear} gear, tooth pair {a['root_stress_peak_tooth']}"
        if not math.isfinite(limit):
            text = f"FE tooth-root stress {peak / 1e6:.4g} MPa ({where}; static); not rated"
            out.append(reason("root-stress", "note", text, peak, None, pair=int(pair),
                              gear=gear))  # fmt: skip
            continue
        status = "risk" if peak > limit else "note"
        rel = ">" if peak > limit else "<="
        text = (
            f"FE tooth-root stress {peak / 1e6:.4g} MPa {rel} sigma_FP = {limit / 1e6:.4g} MPa "
            f"({where}; static, without K_A K_v)"
        )
        out.append(reason("root-stress", status, text, peak, limit, pair=int(pair), gear=gear))
    return out
