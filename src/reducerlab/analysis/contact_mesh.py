"""The loaded contact's mesh stiffness into a design (paper 000 Eq. 8): as a validated
design (:func:`design_with_contact`, what ``reducerlab run`` and ``report --with``
model) or as the TOML text of the design file (:func:`design_with_mesh`, ``contact
--write-design``)."""

from __future__ import annotations

import math
from typing import Any

from ..design import Design
from ..errors import ReducerlabError

__all__ = ["design_with_contact", "design_with_mesh", "mesh_fields"]


def mesh_fields(kind: str | None, pair: int) -> tuple[str, str, str, str]:
    """Where a design of type ``kind`` takes pair ``pair``'s mesh stiffness (paper 000
    Eq. 8): its table and, in it, the fields of the mean ``k_m``, the harmonics ``k_r``
    and their phases ``phi_r``. A nutation design's ``[meshN]`` (``harmonics``,
    ``phases``), the KHV drive's one ``[mesh]`` (``drives.khv.MeshSpec``, the same
    names), a ``gear_pair``'s ``[mesh]`` (``stiffness_harmonics``,
    ``stiffness_phases``, ``drives.gear_pair.GearMesh``).

    Raises
    ------
    ReducerlabError
        A drive without a loaded contact analysis, or a pair it does not have.
    """
    if kind == "nutation" and pair in (1, 2):
        return f"mesh{pair}", "stiffness", "harmonics", "phases"
    if kind == "khv" and pair == 1:
        return "mesh", "stiffness", "harmonics", "phases"
    if kind == "gear_pair" and pair == 1:
        return "mesh", "stiffness", "stiffness_harmonics", "stiffness_phases"
    raise ReducerlabError(
        f"contact: a {kind} design has no gear pair {pair} to take a loaded contact's "
        "mesh stiffness (nutation: pairs 1 and 2; khv and gear_pair: pair 1)"
    )


def design_with_contact(design: Design, results: Any) -> Design:
    """``design`` with each given pair's mesh stiffness from its loaded contact:
    ``[meshN]`` ``stiffness`` = k_m, ``harmonics`` = k_r and ``phases`` = phi_r of paper
    000's Eq. 8 (N = the result's pair; the KHV drive's ``[mesh]``, a ``gear_pair``'s
    ``[mesh]`` ``stiffness_harmonics`` and ``stiffness_phases``: :func:`mesh_fields`).
    Damping, backlash and error amplitude are kept. A table with ``exponent =
    "contact"`` takes the contact's load exponent ``p`` and reference deflection
    (:func:`reducerlab.analysis.contact_law.force_law`) and ``p`` times its stiffness
    law, the tangent at the operating point.

    Parameters
    ----------
    design : Design
        A design with a loaded contact analysis: nutation, KHV or ``gear_pair``.
    results : iterable of ContactResult
        At most one per pair.

    Raises
    ------
    ReducerlabError
        Two results of one pair; ``exponent = "contact"`` with a result that has no
        load exponent.
    """
    from .contact_law import force_law

    changes: dict[str, Any] = {}
    pairs: list[int] = []
    tables: list[str] = []
    for res in results:
        pair = int(res.data.attrs["pair"])
        if pair in pairs:
            raise ReducerlabError(
                f"contact: two loaded-contact results of pair {pair}: give one per pair"
            )
        pairs.append(pair)
        amp, phase = res.harmonics()
        table, stiffness, harmonics, phases = mesh_fields(design.type, pair)
        tables.append(table)
        scale = 1.0
        if getattr(getattr(design, table, None), "exponent", 1.0) == "contact":
            law = force_law(res)
            if law is None:
                raise ReducerlabError(
                    f'{table}.exponent = "contact": the contact result of pair {pair} has no '
                    "load exponent (made before it was computed); run the contact again"
                )
            p, d, scale = law
            changes[f"{table}.exponent"] = p
            changes[f"{table}.reference_deflection"] = d
        changes[f"{table}.{stiffness}"] = scale * res.mean_stiffness
        changes[f"{table}.{harmonics}"] = [scale * a for a in amp]
        changes[f"{table}.{phases}"] = phase
    if not changes:
        return design
    shown = ", ".join(sorted(tables))
    return design.with_values(changes, source=f"{design.source} with {shown} from loaded contact")


def design_with_mesh(path: Any, result: Any) -> str:
    """The design file at ``path`` as TOML text whose ``[meshN]`` table (``N`` = the
    result's pair; a KHV or ``gear_pair`` design's ``[mesh]``, :func:`mesh_fields`)
    takes the contact analysis' mesh stiffness: ``stiffness = k_m``,
    ``harmonics = k_r`` and ``phases = phi_r`` of paper 000's Eq. 8 (a ``gear_pair``'s
    ``stiffness_harmonics`` and ``stiffness_phases``; time origin: tooth
    pair 0 at mid-mesh). Damping, backlash and error amplitude are kept. Comments of
    the original file are not carried over; a header names the source."""
    import tomli_w

    from ..design_files import read_toml

    data = read_toml(path)
    pair = int(result.data.attrs["pair"])
    name, stiffness, harmonics, phases = mesh_fields(data.get("type"), pair)
    amp, phase = result.harmonics()
    table = dict(data.get(name, {}))
    table[stiffness] = f"{result.mean_stiffness:.6g} N/m"
    table[harmonics] = [f"{a:.6g} N/m" for a in amp]
    table[phases] = [f"{math.degrees(p):.6g} deg" for p in phase]
    data[name] = table
    a = result.data.attrs
    head = (
        f"# {path} with [{name}] from `reducerlab contact` (pair {pair}, "
        f"{a['profile']}, T_ext = {a['torque_external']:.6g} N m, "
        f"{result.data.sizes['position']} positions, Eq. 8 order {a['order']}, "
        f"fit residual {100 * a['fit_residual']:.2f} %)\n"
    )
    return head + tomli_w.dumps(data)
