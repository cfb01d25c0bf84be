"""Sections of the design report (issue 18). Each builder takes the report's
:class:`~reducerlab.reporting.context.Context` and returns a
:class:`~reducerlab.reporting.blocks.Section`, or None when the design does not support
it (a kinematics-only design has no modes). Builders call the same API a user would
(``modal``, ``verdict``, ``response`` ...), so the numbers in the report are the
API's; figures come from :mod:`reducerlab.plot`.

One module per group: :mod:`.inputs` (design inputs, kinematics), :mod:`.modes`
(natural frequencies, sensitivity, Campbell diagram and verdict, gear bodies),
:mod:`.motion` (nonlinear response, bifurcation, regime map), :mod:`.geometry` (tooth
surfaces, closed graph, loaded contact), :mod:`.capacity` (load capacity), :mod:`.datasheet`
(the catalogue datasheet from the torsion test).
"""

from __future__ import annotations

from collections.abc import Callable

from ..blocks import Section
from ..context import Context
from .capacity import capacity_section
from .datasheet import datasheet_section
from .geometry import (
    ball_track_section,
    closed_graph_section,
    contact_section,
    surfaces_section,
)
from .inputs import design_section, kinematics_section
from .modes import bodies_section, campbell_section, modal_section, sensitivity_section
from .motion import bifurcation_section, regime_map_section, response_section

__all__ = ["SECTIONS"]

#: Section builders in report order (provenance is added by the report itself).
SECTIONS: list[tuple[str, str, Callable[[Context], Section | None]]] = [
    ("design", "Design inputs", design_section),
    ("kinematics", "Kinematics", kinematics_section),
    ("modal", "Natural frequencies and mode shapes", modal_section),
    ("sensitivity", "Sensitivity", sensitivity_section),
    ("campbell", "Campbell diagram and verdict", campbell_section),
    ("bodies", "Gear-body modes", bodies_section),
    ("response", "Nonlinear response", response_section),
    ("bifurcation", "Bifurcation diagram", bifurcation_section),
    ("regime-map", "Regime map", regime_map_section),
    ("surfaces", "Tooth surfaces", surfaces_section),
    ("closed-graph", "Closed graph", closed_graph_section),
    ("ball-track", "Ball track", ball_track_section),
    ("contact", "Loaded tooth contact", contact_section),
    ("capacity", "Load capacity", capacity_section),
    ("datasheet", "Datasheet", datasheet_section),
]
