"""What every section of the design report reads (:class:`Context`): the design, its
file text, the results given to the report and those computed once and shared."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..design import Design
from ..model import Model

__all__ = ["Context", "repo_assumptions"]


@dataclass
class Context:
    """What every section reads: the design, its file text, and results computed once
    and shared (the model, the modal result, the responses at the operating point, the
    verdict)."""

    design: Design
    text: str = ""
    assumptions: str = ""
    results: dict[str, list[Any]] = field(default_factory=dict)
    #: ``PATH=VALUE`` settings applied to the file (``--set``).
    overrides: tuple[str, ...] = ()
    cache: dict[str, Any] = field(default_factory=dict)
    #: ``step(done, total)`` inside a long section (the report's progress display).
    step: Callable[[int, int], None] | None = None

    def given(self, kind: str) -> list[Any]:
        """Results of ``kind`` handed to the report (``--with`` files)."""
        return self.results.get(kind, [])

    def components(self) -> list[Any]:
        """Gear-body modes given to the report, for the resonance check."""
        from ..analysis.components import ComponentModes

        return [
            ComponentModes.from_body_modal(r, source=r.attrs.get("source", ""))
            for r in self.given("body-modal")
        ]

    def model(self) -> Model:
        if "model" not in self.cache:
            from ..drives import build_model

            self.cache["model"] = build_model(self.design)
        return self.cache["model"]

    def modal(self) -> Any:
        if "modal" not in self.cache:
            from ..analysis.modal import modal

            self.cache["modal"] = modal(self.model())
        return self.cache["modal"]

    def responses(self) -> tuple[list[Any], list[dict[str, Any]]]:
        """The nonlinear responses at the operating point, one per mesh line, and the
        notes where there is none (:func:`~reducerlab.analysis.verdict.operating_responses`),
        computed once for the response section and the verdict."""
        if "responses" not in self.cache and self.given("response"):
            self.cache["responses"] = (list(self.given("response")), [])  # a run's
        if "responses" not in self.cache:
            from ..analysis.verdict import operating_responses

            self.cache["responses"] = operating_responses(self.model())
        return self.cache["responses"]

    def verdict(self) -> Any:
        """The design's :class:`~reducerlab.analysis.verdict.Verdict` (the resonance
        check with the given body modes and the responses at the operating point),
        computed once for the Campbell section and the summary."""
        if "verdict" not in self.cache:
            from ..analysis.verdict import verdict

            responses, notes = self.responses()
            given = self.given("rating")
            self.cache["verdict"] = verdict(self.design, components=self.components(),
                                            responses=responses, extra_reasons=notes,
                                            rating=given[0] if given else None)  # fmt: skip
        return self.cache["verdict"]

    def has_model(self) -> bool:
        from ..drives import has_model

        return has_model(self.design)


def repo_assumptions() -> str:
    """docs/assumptions.md: of the source checkout, or the copy a wheel ships in
    ``reducerlab/data``; '' when neither is there."""
    here = Path(__file__).resolve()
    for path in (
        here.parents[3] / "docs" / "assumptions.md",
        here.parents[1] / "data" / "assumptions.md",
    ):
        if path.is_file():
            return path.read_text(encoding="utf-8")
    return ""
