"""The datasheet page of the design report (issue 31): the catalogue numbers of the
drive laid out like a catalogue page, read from the quasi-static torsion test through
the whole drive model (:func:`reducerlab.analysis.torsion_test.torsion_test`).

The section computes the test itself on the report's design (cheap: no finite
elements, 0.02 to 0.1 s on the examples): for ``reducerlab run`` that is the model
design, with each contact's k(t) in its mesh. A ``torsion-test`` result given to the
report (``--with``, checked against the design like every given result) is shown
instead; a given ``efficiency`` result adds the drive's efficiency at the design load.
Design types whose model names no input and output (lumped designs) and designs
without a model get no section.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...numformat import quantity_table
from ..blocks import Section, figure, note, table
from ..context import Context

__all__ = ["datasheet_section", "efficiency_row"]

#: What the datasheet does not compute (named on the page, with why: docs/datasheet.md).
NOT_YET = (
    "the distribution over manufacturing tolerances (reducerlab tolerances, a "
    "Monte-Carlo run of its own)",
)


def efficiency_row(res: Any) -> tuple[str, float, str]:
    """The datasheet row of an :class:`~reducerlab.analysis.efficiency.EfficiencyResult`:
    the drive efficiency (%) at the design load, linear between the two computed torques
    around it; at the nearest computed torque (named in the label) when the design load
    is outside the computed range.

    Parameters
    ----------
    res : EfficiencyResult
        A given efficiency result (kind ``efficiency``).

    Returns
    -------
    tuple of (str, float, str)
        Label, efficiency (%), unit.
    """
    ds = res.data
    T = np.asarray(ds["torque"].values, float)
    eta = np.asarray(ds["efficiency"].values, float)
    design = float(ds.attrs["design_torque"])
    mu = float(ds.attrs["mu"])
    if T.min() <= design <= T.max():
        return (f"efficiency at the design load (meshes only, mu = {mu:.3g})",
                100.0 * float(np.interp(design, T, eta)), "%")  # fmt: skip
    i = int(np.argmin(np.abs(T - design)))
    return (f"efficiency at {T[i]:.4g} N m on pair 1's gear A (design load {design:.4g} "
            f"N m outside the computed torques; meshes only, mu = {mu:.3g})",
            100.0 * float(eta[i]), "%")  # fmt: skip


def _has_bench_ends(ctx: Context) -> bool:
    """The design has a model whose input and output the torsion test knows."""
    from ...analysis.torsion_test import bench_ends
    from ...errors import ReducerlabError

    if not ctx.has_model():
        return False
    try:
        bench_ends(ctx.design, ctx.model())
    except ReducerlabError:  # a lumped design: no input and output named
        return False
    return True


def _torsion(ctx: Context) -> tuple[Any, str] | None:
    """The torsion-test result and where it comes from, or None when the design has
    no load to test at."""
    given = ctx.given("torsion-test")
    if given:
        return given[0], "a given torsion-test result (report --with)"
    from ...analysis.torsion_test import torsion_test

    rated = float(ctx.design.operating_point().output_torque or 0.0)
    if not rated > 0:
        return None
    return torsion_test(ctx.design, model=ctx.model()), "computed for this report"


def datasheet_section(ctx: Context) -> Section | None:
    """The catalogue datasheet: rated torque, backlash, lost motion, hysteresis loss,
    K1/K2/K3 with T1/T2, RV torsional rigidity and tangent stiffness at rated (N m,
    arcmin, N m/arcmin), the torsion test's loop and what is not computed yet."""
    if not ctx.given("torsion-test") and not _has_bench_ends(ctx):
        return None
    s = Section("datasheet", "Datasheet")
    got = _torsion(ctx)
    if got is None:
        s.blocks.append(
            note(
                "No datasheet: the design gives no output torque at its operating point "
                "(give output_torque or output_power, the rated torque of the test)."
            )
        )
        return s
    res, source = got
    nums = res.numbers
    cat = nums.catalogue()
    a = res.data.attrs
    rated = float(a["rated_torque"])
    rows: list[tuple[str, Any, str]] = [
        ("rated torque (test torque)", rated, "N m"),
        ("backlash (twist jump at zero torque)", cat["backlash_arcmin"], "arcmin"),
        ("lost motion at +/-3 % rated", cat["lost_motion_3pct_arcmin"], "arcmin"),
        ("lost motion at +/-4 % rated", cat["lost_motion_4pct_arcmin"], "arcmin"),
        ("hysteresis loss (loop width at zero torque)", cat["hysteresis_loss_arcmin"], "arcmin"),
        ("T1", cat["T1_N_m"], "N m"),
        ("T2", cat["T2_N_m"], "N m"),
        ("K1 (0..T1)", cat["K1_N_m_per_arcmin"], "N m/arcmin"),
        ("K2 (T1..T2)", cat["K2_N_m_per_arcmin"], "N m/arcmin"),
        ("K3 (T2..rated)", cat["K3_N_m_per_arcmin"], "N m/arcmin"),
        ("theta1 (twist at T1)", cat["theta1_arcmin"], "arcmin"),
        ("theta2 (twist at T2)", cat["theta2_arcmin"], "arcmin"),
        ("torsional rigidity (RV, 3..100 % rated)",
         cat["torsional_rigidity_rv_N_m_per_arcmin"], "N m/arcmin"),
        ("tangent stiffness at rated", cat["tangent_stiffness_at_rated_N_m_per_arcmin"],
         "N m/arcmin"),
    ]  # fmt: skip
    rows.insert(5, ("loop area (friction work per cycle)", float(nums.loop_area), "J"))
    eff = ctx.given("efficiency")
    eff_percent = None
    if eff:
        rows.append(efficiency_row(eff[0]))
        eff_percent = rows[-1][1]
        rows += _starting_rows(eff[0], rated)
    acc, acc_note = _accuracy(ctx)
    if acc is not None:
        from ...analysis.datasheet import accuracy_rows

        rows += accuracy_rows(acc)
    s.values.update(
        numbers=nums.attrs(), catalogue=cat, rated_torque=rated, source=source,
        output_dof=str(a["output_dof"]), held=str(a["held"]),
        efficiency_percent=eff_percent,
        te_peak_to_peak_arcsec=None if acc is None else acc.peak_to_peak,
    )  # fmt: skip
    s.blocks.append(
        table(
            quantity_table(rows), name="datasheet",
            caption=f"Torsion test with the input held ({a['ends']}), output torque "
            f"0 -> +{rated:.4g} -> -{rated:.4g} -> 0 N m, {a['points']} states, "
            f"{a['position']}; {source}",
        )
    )  # fmt: skip
    s.blocks.append(
        figure(
            res.figure(),
            "hysteresis loop: output twist (arcmin) against output torque (N m), the "
            "K1/K2/K3 secants, T1/T2 and the +/-3 % band",
        )
    )
    if acc is not None and not np.any(acc.data["error"].values):
        s.blocks.append(
            note(
                "Transmission error: no manufacturing or assembly error is given, so the "
                "output angle error is zero over the revolution (no figure). Give the "
                "design's error fields (e.g. gears.ring_errors.eccentricity; "
                "docs/datasheet.md) to see one."
            )
        )
    elif acc is not None:
        s.blocks.append(
            figure(
                acc.figure(),
                "transmission error: output angle error over one output revolution "
                "(arcsec) and its spectrum in orders of the output rotation",
            )
        )
    missing = list(NOT_YET)
    if not eff:
        missing.insert(0, "efficiency, starting and back-driving torque (reducerlab "
                          "datasheet computes them, or give an efficiency result: report "
                          "--with)")  # fmt: skip
    if acc_note:
        missing.insert(0, acc_note)
    s.blocks.append(note("Not computed here: " + "; ".join(missing) + "."))
    return s


def _starting_rows(eff: Any, rated: float) -> list[tuple[str, float, str]]:
    """Starting and back-driving torque rows at the rated torque from a given
    efficiency (``pipeline.datasheet.starting_torques``), none when its torques do not
    reach the rated one or it predates the output torque it needs."""
    from ...analysis.datasheet import starting_torques
    from ...errors import ReducerlabError

    if "output_torque" not in eff.data or "ratio" not in eff.data.attrs:
        return []
    try:
        st = starting_torques(eff, rated)
    except ReducerlabError:
        return []
    return [
        ("starting torque at rated output (input side, meshes)", st["starting_torque"], "N m"),
        ("back-driving torque at rated (output side, meshes)", st["backdriving_torque"], "N m"),
    ]


def _accuracy(ctx: Context) -> tuple[Any, str]:
    """A given transmission-accuracy result, else the rigid kinematics' one computed
    here (cheap) where the drive type has it; with a note when there is none."""
    from ...errors import ReducerlabError

    given = ctx.given("transmission-accuracy")
    if given:
        return given[0], ""
    from ...analysis.transmission_accuracy import transmission_accuracy

    try:
        return transmission_accuracy(ctx.design), ""
    except ReducerlabError as exc:
        return None, f"transmission accuracy ({exc})"
