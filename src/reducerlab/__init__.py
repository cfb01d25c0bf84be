"""reducerlab: design and dynamic analysis of compact high-ratio gear reducers.

The flow is design file -> Design -> builder -> Model -> analyses -> Results::

    import reducerlab as rl
    design = rl.load_design("examples/gear_pair.toml")
    model = rl.build_model(design)
    result = rl.modal(model)
    print(result.table())

Heavy imports (pint, xarray, matplotlib) happen on first use, not at import time.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

_LAZY = {
    "load_design": "reducerlab.drives",
    "build_model": "reducerlab.drives",
    "modal": "reducerlab.analysis.modal",
    "ModalResult": "reducerlab.analysis.modal",
    "frequency_sensitivity": "reducerlab.analysis.modal",
    "mac": "reducerlab.analysis.modal",
    "campbell": "reducerlab.analysis.campbell",
    "resonance_check": "reducerlab.analysis.resonance",
    "verdict": "reducerlab.analysis.verdict",
    "Verdict": "reducerlab.analysis.verdict",
    "Thresholds": "reducerlab.design",
    "Model": "reducerlab.model",
    "Dof": "reducerlab.model",
    "DesignError": "reducerlab.errors",
    "ModelError": "reducerlab.errors",
    "ReducerlabError": "reducerlab.errors",
    "report": "reducerlab.reporting",
    "Report": "reducerlab.reporting",
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'reducerlab' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
