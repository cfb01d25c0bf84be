"""``datasheet``: a reducer's catalogue page computed from its design (issue 31).

One call gathers what a precision-reducer catalogue prints, each from its own analysis:

* the **torsion test** with the input held (``analysis.torsion_test``; Coulomb friction
  at the sliding tooth contacts): backlash, lost motion, hysteresis loss and loop area,
  K1/K2/K3 with T1/T2, RV torsional rigidity;
* the **transmission accuracy** over one output revolution (``analysis.
  transmission_accuracy``: the design's manufacturing errors through the kinematics,
  and under the rated torque every mesh's loaded TE, or the cycloid-ball track's
  wind-up);
* the **efficiency** from Coulomb friction at the loaded tooth contacts
  (``analysis.efficiency``) at 1/4, 1/2 and 1 times the rated torque, with the
  **starting torque** (the input torque that starts the drive against the rated output
  torque) and the **back-driving torque** (the output torque that starts turning the
  input against the input torque equivalent to rated), from it; for the cycloid-ball
  drive from the spin and differential sliding of its balls
  (``analysis.cycloid_efficiency``, no contact stage).

The finite-element tooth models of the contact analyses (efficiency, loaded TE) are
the run's compliance stage (:func:`.stages.compliance_stage`) in the same stage cache,
and the efficiency and loaded TE are cached by their inputs (:class:`.store.Store`): a
datasheet after a ``reducerlab run`` of the same design with the same cache builds no
tooth model, and a second datasheet reads everything.

**Starting and back-driving torque.** With static and sliding coefficients equal
(``mu``), the drive starts when the input torque reaches the running one:
``T_start = T_r / (|i| eta(T_r))``. Back-driving, the output drives and the same mesh
forces lose, to first order in the loss, the same power, so the reverse efficiency is
``eta_b = 1 - P_V / P_0 = eta`` (``analysis.efficiency``'s first-order torque flow) and
the output torque that turns the input against ``T_r / |i|`` is ``T_r / eta_b``. Only
the meshes' friction enters: without load it vanishes, so the no-load starting torque
of a catalogue (bearings, seals, lubricant) is not computed.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..analysis.datasheet import accuracy_rows, starting_torques
from ..errors import ReducerlabError
from .stages import ContactSettings, Stage, compliance_stage, design_inputs
from .store import Store

__all__ = ["Datasheet", "datasheet", "datasheet_stages", "loaded_sweeps"]

#: Fractions of the rated torque at which the datasheet computes the efficiency.
EFFICIENCY_LOADS = (0.25, 0.5, 1.0)
#: Mesh positions a cycle of the datasheet's contact stages (the command's and the
#: run's: one key, so each serves the other from the stage cache).
POSITIONS = 12


def _quiet(_d: str, _f: float) -> None:
    return None


@dataclass
class Datasheet:
    """The results behind a datasheet page, each with why it is missing when it is.

    Attributes
    ----------
    torsion : TorsionTestResult
    accuracy : TransmissionAccuracyResult or None
    efficiency : EfficiencyResult or None
    notes : dict of str to str
        Why ``accuracy`` or ``efficiency`` is None (keys ``"accuracy"``, ``"efficiency"``).
    stages : list of Stage
        The efficiency's stages (tooth models, contact), computed or read from the cache.
    """

    torsion: Any
    accuracy: Any = None
    efficiency: Any = None
    notes: dict[str, str] = field(default_factory=dict)
    stages: list[Stage] = field(default_factory=list)

    @property
    def results(self) -> list[Any]:
        """The computed results (for the report's ``results=``)."""
        return [r for r in (self.torsion, self.accuracy, self.efficiency) if r is not None]

    def starting(self) -> dict[str, float] | None:
        """Starting and back-driving torques at the rated torque
        (:func:`starting_torques`), or None without an efficiency."""
        if self.efficiency is None:
            return None
        rated = float(self.torsion.data.attrs["rated_torque"])
        return starting_torques(self.efficiency, rated)

    def table(self) -> str:
        """The datasheet as plain text: the torsion test's table, then accuracy and
        efficiency lines (or why they are missing)."""
        rows: list[tuple[str, float, str]] = []
        notes = []
        if self.accuracy is not None:
            rows += accuracy_rows(self.accuracy)
        else:
            notes.append(f"transmission error: {self.notes.get('accuracy', 'not computed')}")
        st = self.starting()
        if st is None:
            notes.append(f"efficiency: {self.notes.get('efficiency', 'not computed')}")
        else:
            rows += [
                ("efficiency at rated torque (meshes)", 100 * st["efficiency"], "%"),
                ("starting torque at rated output (input)", st["starting_torque"], "N m"),
                ("back-driving torque at rated (output)", st["backdriving_torque"], "N m"),
            ]
        return "\n".join([self.torsion.table_data(rows).text(), *notes])


def _stored(store: Store | None, stage: str, inputs: dict[str, Any]) -> tuple[str, Any]:
    """``(key, result or None)`` of a stage in ``store`` (no store: no key, no hit)."""
    if store is None:
        return "", None
    key = store.key(stage, inputs)
    hit = store.get(stage, key)
    return key, None if hit is None else hit[0]


def _tooth_models(
    store: Store | None, design: Any, pairs: tuple[int, ...], settings: ContactSettings,
    report: Callable[[str, float], None],
) -> tuple[list[Any] | None, list[Stage]]:  # fmt: skip
    """Every pair's tooth compliances: from the compliance stage (the run's, cached) for
    the drives the run takes (nutation, KHV); for a gear pair built here once (its
    efficiency and loaded TE share them) and cached as a stage of its own
    (``"compliance pair"``: the run takes no gear pair). None without a store for the
    former (each analysis builds its own)."""
    from ..drives.gear_pair import GearPairDesign

    if isinstance(design, GearPairDesign):
        return _pair_models(store, design, settings, report)
    if store is None:
        return None, []
    comps, stages = [], []
    for p in pairs:
        comp, sts = compliance_stage(store, design, p, settings, report)
        comps.append(comp)
        stages += sts
    return comps, stages


def _pair_models(
    store: Store | None, design: Any, settings: ContactSettings,
    report: Callable[[str, float], None],
) -> tuple[list[Any], list[Stage]]:  # fmt: skip
    """A gear pair's tooth compliances (pinion, gear), read from ``store`` or built
    (``PairSetup.compliances``, the unmodified teeth, as ``te_sweep`` builds them) and
    stored; keyed on the pair's fields without its load and flank modifications."""
    from ..analysis.contact_setup import pair_setup

    base = {k: v for k, v in design_inputs("contact", design, {"pair": 1}).items()
            if "modifications" not in k and "errors" not in k
            and not k.startswith("operating")}  # fmt: skip
    inputs = {"design": base, "tooth_size": settings.tooth_size}
    key = store.key("compliance_pair", inputs) if store is not None else ""
    hit = store.get("compliance_pair", key, extra=True) if store is not None else None
    if hit is not None:
        return [hit[1]], [Stage("tooth models", key, "cached")]
    t0 = time.perf_counter()
    setup = pair_setup(design, 1)
    setup.compliance_estimate(settings.tooth_size).check()
    report("tooth models", 0.0)
    comp = setup.compliances(settings.tooth_size, lambda t: report(t, 0.0), None)
    if store is not None:
        store.put("compliance_pair", key, inputs, extra=comp)
    return [comp], [Stage("tooth models", key, "computed", time.perf_counter() - t0)]


def efficiency_stage(
    store: Store | None,
    design: Any,
    rated: float,
    *,
    mu: float | None,
    positions: int,
    rigid: bool,
    settings: ContactSettings,
    compliance: list[Any] | None = None,
    report: Callable[[str, float], None] = _quiet,
) -> tuple[Any, Stage]:
    """The drive's efficiency at :data:`EFFICIENCY_LOADS` times ``rated`` (N m on the
    output), on the given tooth models (``compliance``, one pair of each gear pair;
    none with ``rigid``), cached in ``store`` by its inputs."""
    from ..analysis.efficiency import efficiency, friction_coefficient
    from ..analysis.te_sweep import design_load

    mu = friction_coefficient(design, mu)
    T_design = float(design.operating_point().output_torque or 0.0)
    if not T_design > 0:
        raise ReducerlabError("datasheet: the design has no output torque for the efficiency")
    torques = [design_load(design, 1) * f * rated / T_design for f in EFFICIENCY_LOADS]
    inputs = {
        "design": design_inputs("efficiency", design, {}), "mu": mu, "torques": torques,
        "positions": positions, "rigid": bool(rigid), "cell": settings.cell,
        "tooth_size": settings.tooth_size,
    }  # fmt: skip
    key, hit = _stored(store, "efficiency", inputs)
    if hit is not None:
        return hit, Stage("efficiency", key, "cached")
    t0 = time.perf_counter()
    report("efficiency", 0.0)
    res = efficiency(
        design, mu=mu, torques=torques, positions=positions, cell=settings.cell,
        tooth_size=settings.tooth_size, rigid=rigid, compliance=compliance,
        stage=lambda s: report(f"efficiency: {s}", 0.0),
        progress=lambda d, t: report(f"efficiency: {d}/{t} positions", d / t),
    )  # fmt: skip
    if store is not None:
        store.put("efficiency", key, inputs, res)
    return res, Stage("efficiency", key, "computed", time.perf_counter() - t0)


def loaded_sweeps(
    store: Store | None,
    design: Any,
    t_out: float,
    *,
    positions: int,
    rigid: bool,
    tooth_size: float | None,
    compliance: list[Any] | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[list[Any], list[str], bool]:
    """Every pair's loaded TE at the output torque ``t_out`` (N m; each pair's gear A
    at its lossless share), read from ``store`` or computed on the given tooth models
    (``compliance``, in pair order) and stored. Key of each pair: the design's fields
    without the gears' ``errors`` tables (the contact of perfect teeth does not read
    them), the pair, its torque, positions, rigid teeth and tooth size. Returns the
    sweeps (pair order), their keys and whether any was computed."""
    from ..analysis.efficiency import gear_pairs
    from ..analysis.loaded_accuracy import mesh_te, mesh_torque

    if _is_nutation(design):
        from ..analysis.loaded_accuracy_nutation import pair_torques

        torques = pair_torques(design, t_out)
    else:
        torques = [mesh_torque(design, t_out)]
    sweeps, keys, computed = [], [], False
    for k, (p, torque) in enumerate(zip(gear_pairs(design), torques, strict=True)):
        fields = {f: v for f, v in design_inputs("te-sweep", design, {"pair": p}).items()
                  if "errors" not in f}  # fmt: skip
        inputs = {"design": fields, "pair": p, "torque": torque, "positions": positions,
                  "rigid": bool(rigid), "tooth_size": tooth_size}  # fmt: skip
        key, te = _stored(store, "accuracy_mesh_te", inputs)
        if te is None:
            computed = True
            if stage is not None:
                stage(f"loaded transmission error pair {p}")
            te = mesh_te(
                design, torque, pair=p, positions=positions, rigid=rigid,
                tooth_size=tooth_size, compliance=None if compliance is None else compliance[k],
                stage=stage, progress=progress,
            )  # fmt: skip
            te.compliance = None
            if store is not None:
                store.put("accuracy_mesh_te", key, inputs, te)
        sweeps.append(te)
        keys.append(key)
    return sweeps, keys, computed


def accuracy_stage(
    store: Store | None,
    design: Any,
    rated: float,
    *,
    positions: int,
    rigid: bool,
    settings: ContactSettings,
    compliance: list[Any] | None = None,
    report: Callable[[str, float], None] = _quiet,
) -> tuple[Any, Stage]:
    """The transmission accuracy at the rated output torque ``rated`` (N m): the rigid
    kinematics' error of the design's manufacturing errors plus every mesh's loaded TE
    (``analysis.loaded_accuracy``; a nutation drive's two meshes,
    ``analysis.loaded_accuracy_nutation``), each pair's contact from
    :func:`loaded_sweeps` (cached in ``store``)."""
    from ..analysis.transmission_accuracy import transmission_accuracy

    t0 = time.perf_counter()
    sweeps, keys, computed = loaded_sweeps(
        store, design, rated, positions=positions, rigid=rigid,
        tooth_size=settings.tooth_size, compliance=compliance,
        stage=lambda s: report(s, 0.0),
        progress=lambda d, t: report(f"loaded TE: {d}/{t} positions", d / t),
    )  # fmt: skip
    res = transmission_accuracy(design, load=rated, rigid=rigid, positions=positions,
                                tooth_size=settings.tooth_size,
                                mesh_te=sweeps if len(sweeps) > 1 else sweeps[0])  # fmt: skip
    status = "computed" if computed else "cached"
    return res, Stage("loaded transmission error", ",".join(keys), status,
                      time.perf_counter() - t0)  # fmt: skip


def datasheet(
    design: Any,
    *,
    rated: float | None = None,
    steps: int = 20,
    t1: float = 0.2,
    t2: float = 0.7,
    mu: float | None = None,
    efficiency: bool = True,
    loaded: bool = True,
    rigid: bool = False,
    positions: int = POSITIONS,
    cache: str | Path | None = None,
    contact: ContactSettings | None = None,
    progress: Callable[[str, float], None] = _quiet,
) -> Datasheet:
    """The catalogue datasheet of ``design`` (see the module).

    Parameters
    ----------
    design : Design
        A drive design.
    rated : float, optional
        Rated output torque (N m); default the design's output torque.
    steps, t1, t2, mu
        As :func:`reducerlab.analysis.torsion_test.torsion_test` (``mu`` also for the
        efficiency).
    efficiency : bool
        Compute the efficiency (a loaded contact analysis of every gear pair; designs
        with tooth surfaces: gear pair, KHV, nutation with ``[surface]``).
    loaded : bool
        The transmission accuracy under the rated torque (gear pair, KHV, nutation with
        ``[surface]``: every mesh's loaded TE added to the rigid kinematics' error;
        cycloid ball: its ball track's wind-up over a ball pitch); else the rigid error
        alone.
    rigid : bool
        Teeth rigid beyond the contact half-space in the contact analyses (fast, for
        checks).
    positions : int
        Mesh positions a cycle in the contact analyses (>= 3; the loaded transmission
        error joins them linearly, ``analysis.loaded_accuracy``).
    cache : path, optional
        Stage cache folder (``reducerlab run``'s ``OUTPUT/cache``): the tooth models and
        the contact results are read from it when there and stored in it when computed.
    contact : ContactSettings, optional
        The tooth models' settings (default the run's, so that its cache serves).
    progress : callable
        ``progress(description, fraction)`` of the contact stages.

    Returns
    -------
    Datasheet
    """
    from ..analysis.efficiency import gear_pairs
    from ..analysis.torsion_test import torsion_test
    from ..analysis.transmission_accuracy import transmission_accuracy

    sheet = Datasheet(torsion_test(design, rated=rated, steps=steps, t1=t1, t2=t2, mu=mu))
    rated_T = float(sheet.torsion.data.attrs["rated_torque"])
    surfaces = _has_surfaces(design)
    with_load = loaded and surfaces
    want_eff = efficiency and surfaces
    settings = contact or ContactSettings()
    store = Store(cache) if cache is not None else None
    comps, sheet.stages = (None, [])
    if (want_eff or with_load) and not rigid:
        comps, sheet.stages = _tooth_models(store, design, gear_pairs(design), settings,
                                            progress)  # fmt: skip
    try:
        if with_load:
            sheet.accuracy, st = accuracy_stage(
                store, design, rated_T, positions=positions, rigid=rigid,
                settings=settings, compliance=comps, report=progress,
            )  # fmt: skip
            sheet.stages.append(st)
        else:
            # the cycloid-ball drive under load: its ball track's static wind-up
            # (no contact stage; analysis.loaded_accuracy_cycloid, seconds)
            cycloid = loaded and getattr(design, "type", None) == "cycloid_ball"
            sheet.accuracy = transmission_accuracy(design, load=rated_T if cycloid else None)
    except ReducerlabError as exc:
        sheet.notes["accuracy"] = str(exc)
    if not efficiency:
        sheet.notes["efficiency"] = "not asked for (--no-efficiency)"
    elif getattr(design, "type", None) == "cycloid_ball":
        # the balls' spin and sliding (analysis.cycloid_efficiency, no contact stage)
        from ..analysis.cycloid_efficiency import cycloid_efficiency
        from ..drives.cycloid_ball import centre_disc_torque

        per_out = centre_disc_torque(design) / abs(design.operating_point().output_torque)
        try:
            sheet.efficiency = cycloid_efficiency(
                design, mu=mu, torques=[f * rated_T * per_out for f in EFFICIENCY_LOADS]
            )
        except ReducerlabError as exc:
            sheet.notes["efficiency"] = str(exc)
    elif not surfaces:
        sheet.notes["efficiency"] = (
            "needs tooth surfaces (a gear pair, a KHV drive, a nutation drive with [surface])"
        )
    else:
        sheet.efficiency, st = efficiency_stage(
            store, design, rated_T, mu=mu, positions=positions, rigid=rigid,
            settings=settings, compliance=comps, report=progress,
        )  # fmt: skip
        sheet.stages.append(st)
    return sheet


def datasheet_stages(
    store: Store,
    model_design: Any,
    compliance: dict[int, Any],
    settings: ContactSettings,
    report: Callable[[str, float], None] = _quiet,
) -> tuple[list[Any], list[Stage]]:
    """The datasheet's contact stages inside ``reducerlab run`` (``run(datasheet=True)``):
    the efficiency of every pair and, for a KHV or nutation drive, the transmission
    accuracy under the design's output torque, on the run's tooth models (``compliance``: pair ->
    both gears' compliances, the run's compliance stage), at :data:`POSITIONS`.
    Computed on the run's model design (its contact's k(t) in the meshes, which neither
    reads) so that its report takes them."""
    from ..analysis.efficiency import gear_pairs

    rated = float(model_design.operating_point().output_torque or 0.0)
    if not rated > 0:
        raise ReducerlabError("datasheet: the design has no output torque (the rated load)")
    pairs = list(gear_pairs(model_design))
    compliance, stages = dict(compliance), []
    for p in pairs:  # a pair without contact in the run (a KHV mesh on ISO stiffness)
        if p not in compliance:  # the compliance's key reads the teeth, not the meshes
            compliance[p], sts = compliance_stage(store, model_design, p, settings, report)
            stages += sts
    eff, st = efficiency_stage(
        store, model_design, rated, mu=None, positions=POSITIONS, rigid=False,
        settings=settings, compliance=[compliance[p] for p in pairs], report=report,
    )  # fmt: skip
    results = [eff]
    stages.append(st)
    if getattr(model_design, "type", None) in ("khv", "nutation"):
        acc, st = accuracy_stage(
            store, model_design, rated, positions=POSITIONS, rigid=False,
            settings=settings, compliance=[compliance[p] for p in pairs], report=report,
        )  # fmt: skip
        results.append(acc)
        stages.append(st)
    return results, stages


def _is_nutation(design: Any) -> bool:
    return str(getattr(design, "type", "")).startswith("nutation")


def _has_surfaces(design: Any) -> bool:
    """Whether the efficiency's contact analysis applies to ``design``."""
    from ..drives.gear_pair import GearPairDesign

    if isinstance(design, GearPairDesign) or getattr(design, "type", None) == "khv":
        return True
    return getattr(design, "surface", None) is not None
