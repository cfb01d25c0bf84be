"""The optional stages of ``reducerlab run``: their settings from ``run``'s arguments,
their checks before any work, the partial results they write as they go, and the KHV
internal pair's load sharing against torque (issue 30).

The ``sharing`` stage runs :func:`~reducerlab.analysis.khv_sharing.load_sharing` on the
compliance stage's tooth models of the planet and the ring (no second finite-element
build); its key is the contact's design fields (a KHV drive's ``[gears]`` and
``[material]``; the load only where a crowned layout is sized by it, as the
``te_sweep`` stage's), the planet's operating torque, the torques (loads,
top), the positions, the cell and the tooth size. A ``khv`` design asks for it whatever
its ``[mesh] stiffness``: with ``"iso"`` the run computes the compliance stage for it
and no contact (the sharing is a contact analysis of its own; the model keeps the ISO
law).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ReducerlabError
from .stages import (
    ContactSettings,
    LayoutSettings,
    Stage,
    SweepSettings,
    check_integer,
    check_positive,
    operating_inputs,
)
from .store import Store

__all__ = [
    "SHARING_STAGE",
    "SharingSettings",
    "check_optional",
    "dask_context",
    "optional_settings",
    "pair_torque",
    "partial_writer",
    "sharing_stage",
]

#: The name of the load-sharing stage (one: a KHV drive has one internal pair).
SHARING_STAGE = "load sharing pair 1"


@dataclass(frozen=True)
class SharingSettings:
    """The KHV internal pair's load sharing against torque (``analysis.khv_sharing``).

    Attributes
    ----------
    loads : int
        Torques evenly from 0 to ``top`` times the planet's operating torque (2..41).
    top : float
        Largest torque over the operating torque, in (0, 3].
    positions : int or None
        Positions over one mesh cycle (3..1000); None: the contact's.
    """

    loads: int = 6
    top: float = 1.5
    positions: int | None = None

    def __post_init__(self) -> None:
        check_integer("sharing.loads", self.loads, 2, 41)
        check_positive("sharing.top", self.top, 3.0)
        if self.positions is not None:
            check_integer("sharing.positions", self.positions, 3, 1000)

    def positions_of(self, contact: ContactSettings) -> int:
        """The positions (its own, else the contact's), checked."""
        n = contact.positions if self.positions is None else self.positions
        check_integer("sharing.positions", n, 3, 1000)
        return n

    def estimate(self, contact: ContactSettings) -> Any:
        """The work of the sweep under the sharing (``te_sweep.sweep_estimate``'s bound
        on position-torque solves), before any; the refusal names these settings."""
        from dataclasses import replace

        from ..analysis.te_sweep import sweep_estimate

        n = self.positions_of(contact)
        est = sweep_estimate(n, self.loads)
        control = "sharing.loads or sharing.positions (--sharing N, --positions)"
        return replace(est, what=f"sharing: {n} positions x {self.loads} torques", control=control)


def optional_settings(
    te_sweep: Any, layout: Any, sharing: Any = None
) -> tuple[SweepSettings | None, LayoutSettings | None, SharingSettings | None]:
    """The optional stages' settings from ``run``'s arguments, checked."""
    if te_sweep is None or isinstance(te_sweep, SweepSettings):
        sweep = te_sweep
    elif isinstance(te_sweep, int) and not isinstance(te_sweep, bool):
        sweep = SweepSettings(loads=te_sweep)  # checks 2..41
    else:
        raise ReducerlabError(
            f"te_sweep: must be a number of torques (2..41) or a SweepSettings; got {te_sweep!r}"
        )
    if isinstance(layout, LayoutSettings):
        lay = layout
    elif isinstance(layout, bool):
        lay = LayoutSettings() if layout else None
    else:
        raise ReducerlabError(f"layout: must be true, false or a LayoutSettings; got {layout!r}")
    if sharing is None or isinstance(sharing, SharingSettings):
        share = sharing
    elif isinstance(sharing, int) and not isinstance(sharing, bool):
        share = SharingSettings(loads=sharing)  # checks 2..41
    else:
        raise ReducerlabError(
            f"sharing: must be a number of torques (2..41) or a SharingSettings; got {sharing!r}"
        )
    return sweep, lay, share


def check_optional(
    design: Any,
    pairs: list[int],
    settings: ContactSettings,
    sweep: SweepSettings | None,
    lay: LayoutSettings | None,
    share: SharingSettings | None = None,
) -> None:
    """Refuse the optional stages before any work: a design without gear pairs in
    contact (the sweep, the layout), a design other than a KHV drive (the sharing), or
    a stage beyond its work bound (their estimates)."""
    for name, asked in (("te_sweep", sweep), ("layout", lay)):
        if asked is not None and not pairs:
            raise ReducerlabError(
                f"{name}: needs a design with tooth surfaces (a gear pair's loaded "
                f"contact); this {design.type} design has none"
            )
    if share is not None and getattr(design, "type", None) != "khv":
        raise ReducerlabError(
            "sharing: the load sharing against torque is of a KHV drive's internal pair "
            f'(type = "khv"); this design is of type {design.type!r}'
        )
    if sweep is not None:
        sweep.estimate(settings).check()
    if lay is not None:
        lay.estimate().check()
    if share is not None:
        share.estimate(settings).check()


def partial_writer(out_dir: Path | None, name: str) -> Callable[[Any], None] | None:
    """``partial(result)`` writing a result's table so far to ``out_dir/name`` (a
    temporary name moved into place); None without an output folder."""
    if out_dir is None:
        return None

    def write(res: Any) -> None:
        out_dir.mkdir(parents=True, exist_ok=True)
        tmp = out_dir / f".{name}.tmp"
        tmp.write_text(res.table() + "\n")
        tmp.replace(out_dir / name)

    return write


def _quiet(_d: str, _f: float) -> None:
    return None


def sharing_stage(
    store: Store,
    design: Any,
    torque: float,
    settings: ContactSettings,
    sharing: SharingSettings,
    compliance: tuple[Any, Any],
    report: Callable[[str, float], None] = _quiet,
    partial: Callable[[Any], None] | None = None,
) -> tuple[Any, Stage]:
    """Load sharing of a KHV design's planet-ring pair from 0 to ``sharing.top`` times
    ``torque`` (N m on the planet), on the compliance stage's tooth models
    (``compliance``: planet, ring). ``partial(result)`` after each chunk of positions."""
    from ..analysis.khv_sharing import load_sharing

    positions = sharing.positions_of(settings)
    inputs = {
        "design": operating_inputs(design, 1, True),
        "torque": float(torque),
        "loads": sharing.loads,
        "top": float(sharing.top),
        "positions": positions,
        "cell": settings.cell,
        "tooth_size": settings.tooth_size,
    }
    key = store.key("sharing", inputs)
    hit = store.get("sharing", key)
    if hit is not None:
        return hit[0], Stage(SHARING_STAGE, key, "cached")
    t0 = time.perf_counter()
    name = SHARING_STAGE
    report(name, 0.0)
    res = load_sharing(
        design, loads=sharing.loads, top=float(sharing.top), torque=float(torque),
        positions=positions, cell=settings.cell, tooth_size=settings.tooth_size,
        compliance=compliance, stage=lambda s: report(f"{name}: {s}", 0.0),
        progress=lambda done, total: report(f"{name}: {done}/{total} positions", done / total),
        partial=partial,
    )  # fmt: skip
    store.put("sharing", key, inputs, res)
    return res, Stage(name, key, "computed", time.perf_counter() - t0)


def dask_context(scheduler: Any) -> Any:
    """The Dask client of ``scheduler`` (a context), or a context yielding None."""
    import contextlib

    if scheduler is None:
        return contextlib.nullcontext(None)
    from ..analysis.workers import dask_client

    return dask_client(scheduler, "run")


def pair_torque(flow: Any, pair: int) -> float:
    """The torque (N m) on pair ``pair``'s external gear at the operating point (the
    ``meshN`` of a nutation drive; a drive's only mesh, the KHV planet's); the loaded
    contact needs one."""
    mesh = flow.meshes.get(f"mesh{pair}")
    if mesh is None and len(flow.meshes) == 1:
        mesh = next(iter(flow.meshes.values()))
    torque = None if mesh is None else mesh.external_torque
    if not (torque is not None and torque > 0):
        raise ReducerlabError(
            "run: the design has no load at its operating point (give output_torque or "
            "output_power): the loaded tooth contact of its gear pairs needs a torque"
        )
    return torque
