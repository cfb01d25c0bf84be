"""The loaded contact's mesh stiffness into a design (paper 000 Eq. 8): as a validated
design (:func:`design_with_contact`, what ``reducerlab run`` and ``report --with``
model) or as the TOML text of the design file (:func:`design_with_mesh`, ``contact
--write-design``)."""

from __future__ import annotations

import math
from typing import Any

from ..design import Design
from ..errors import ReducerlabError

__all__ = ["design_with_contact", "design_with_mesh", "mesh_table"]


def mesh_table(result: Any) -> str:
    """The design table that takes a contact result's mesh stiffness: ``meshN`` for
    pair ``N`` of a nutation design, ``mesh`` for the KHV drive's internal pair (its one
    ``[mesh]`` table, ``drives.khv.MeshSpec``)."""
    a = result.data.attrs
    return "mesh" if a.get("pair_kind") == "internal" else f"mesh{int(a['pair'])}"


def design_with_contact(design: Design, results: Any) -> Design:
    """``design`` with each given pair's mesh stiffness from its loaded contact:
    ``[meshN]`` ``stiffness`` = k_m, ``harmonics`` = k_r and ``phases`` = phi_r of paper
    000's Eq. 8 (N = the result's pair; the KHV drive's ``[mesh]``, :func:`mesh_table`).
    Damping, backlash and error amplitude are kept. A table with ``exponent =
    "contact"`` takes the contact's load exponent ``p`` and reference deflection
    (:func:`reducerlab.analysis.contact_law.force_law`) and ``p`` times its stiffness
    law, the tangent at the operating point.

    Parameters
    ----------
    design : Design
        A design with ``[meshN]`` tables (the nutation drive) or a KHV design.
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
        table = mesh_table(res)
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
        changes[f"{table}.stiffness"] = scale * res.mean_stiffness
        changes[f"{table}.harmonics"] = [scale * a for a in amp]
        changes[f"{table}.phases"] = phase
    if not changes:
        return design
    shown = ", ".join(sorted(tables))
    return design.with_values(changes, source=f"{design.source} with {shown} from loaded contact")


def design_with_mesh(path: Any, result: Any) -> str:
    """The design file at ``path`` as TOML text whose ``[meshN]`` table (``N`` = the
    result's pair; a KHV design's ``[mesh]``) takes the contact analysis' mesh
    stiffness: ``stiffness = k_m``,
    ``harmonics = k_r`` and ``phases = phi_r`` of paper 000's Eq. 8 (time origin: tooth
    pair 0 at mid-mesh). Damping, backlash and error amplitude are kept. Comments of
    the original file are not carried over; a header names the source."""
    import tomli_w

    from ..design_files import read_toml

    data = read_toml(path)
    pair = int(result.data.attrs["pair"])
    name = mesh_table(result)
    amp, phase = result.harmonics()
    table = dict(data.get(name, {}))
    table["stiffness"] = f"{result.mean_stiffness:.6g} N/m"
    table["harmonics"] = [f"{a:.6g} N/m" for a in amp]
    table["phases"] = [f"{math.degrees(p):.6g} deg" for p in phase]
    data[name] = table
    a = result.data.attrs
    head = (
        f"# {path} with [{name}] from `reducerlab contact` (pair {pair}, "
        f"{a['profile']}, T_ext = {a['torque_external']:.6g} N m, "
        f"{result.data.sizes['position']} positions, Eq. 8 order {a['order']}, "
        f"fit residual {100 * a['fit_residual']:.2f} %)\n"
    )
    return head + tomli_w.dumps(data)
