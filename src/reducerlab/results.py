"""Base class of analysis results: an xarray Dataset with provenance, saved as netCDF."""

from __future__ import annotations

import importlib
import json
from pathlib import Path
from typing import Any, ClassVar, TypeVar

import xarray as xr

from .errors import ReducerlabError
from .inputs import input_record
from .io import atomic_path, base_stamp, stamp

__all__ = ["Result", "provenance"]

R = TypeVar("R", bound="Result")


def provenance(metadata: dict[str, Any] | None = None) -> dict[str, str]:
    """Attributes recorded in every result: package version, time, design and its hash."""
    meta = dict(metadata or {})
    attrs = base_stamp()
    design = meta.pop("design", None)
    if design is not None:
        attrs["design"] = design if isinstance(design, str) else json.dumps(design)
    for key, value in meta.items():
        attrs[key] = value if isinstance(value, str) else json.dumps(value)
    return attrs


#: Where each kind of result is defined, so that :meth:`Result.load` finds the class of a
#: file whose module was not imported yet. Each class registers itself on definition
#: (:meth:`Result.__init_subclass__`); this map only names the module to import.
_KNOWN_KINDS: dict[str, str] = {
    "modal": "reducerlab.analysis.modal",
    "sensitivity": "reducerlab.analysis.modal",
    "campbell": "reducerlab.analysis.campbell",
    "sweep": "reducerlab.analysis.sweep",
    "bifurcation": "reducerlab.analysis.bifurcation",
    "response": "reducerlab.analysis.response",
    "frequency-response": "reducerlab.analysis.frequency_response",
    "regime-map": "reducerlab.analysis.regime_map",
    "complex-modal": "reducerlab.analysis.complex_modal",
    "complex-campbell": "reducerlab.analysis.complex_modal",
    "kinematics": "reducerlab.analysis.kinematics",
    "body-modal": "reducerlab.analysis.body_modal",
    "contact": "reducerlab.analysis.contact",
    "rating": "reducerlab.analysis.rating",
    "te-sweep": "reducerlab.analysis.te_sweep",
    "khv-sharing": "reducerlab.analysis.khv_sharing",
    "layout": "reducerlab.analysis.layout",
    "ball-track": "reducerlab.analysis.ball_track",
    "torsion-test": "reducerlab.analysis.torsion_test",
    "efficiency": "reducerlab.analysis.efficiency",
    "transmission-accuracy": "reducerlab.analysis.transmission_accuracy",
    "tolerances": "reducerlab.analysis.tolerances",
}


class Result:
    """A result holding an :class:`xarray.Dataset` (``.data``).

    Subclasses set ``kind`` (stored in the file so :meth:`load` can check it); each
    subclass is registered by its kind, so that ``Result.load`` returns a result of the
    class the file was saved from.
    """

    kind: ClassVar[str] = "result"
    _registry: ClassVar[dict[str, type[Result]]] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:  # a subclass that inherits its kind is no new kind
            Result._registry[cls.kind] = cls

    @classmethod
    def _class_of(cls, kind: str) -> type[Result] | None:
        """The registered class of results of ``kind`` (its module imported if needed)."""
        if kind not in Result._registry and kind in _KNOWN_KINDS:
            importlib.import_module(_KNOWN_KINDS[kind])
        return Result._registry.get(kind)

    def __init__(self, data: xr.Dataset) -> None:
        self.data = data

    @property
    def attrs(self) -> dict[str, Any]:
        """Dataset attributes (provenance)."""
        return dict(self.data.attrs)

    @property
    def design(self) -> dict[str, Any] | None:
        """The design the result was computed from (SI values), if known."""
        text = self.data.attrs.get("design")
        return json.loads(text) if text else None

    @property
    def provenance(self) -> dict[str, Any]:
        """Version, creation time, design hash and design (a JSON object) of the result,
        as stamped into every JSON result file (:func:`reducerlab.io.stamp`)."""
        return stamp(self.data.attrs)

    def save(self, path: str | Path) -> Path:
        """Write the dataset to a netCDF file and return its path.

        The file is written under a temporary name in the same folder and renamed when
        complete: an interrupted save never leaves a truncated file at ``path``. The
        file records the design inputs the result depends on (``inputs``, see
        :mod:`reducerlab.inputs`), so that a command reading it back can check it
        against its design.
        """
        p = Path(path)
        ds = self.data.copy()
        ds.attrs["result_kind"] = self.kind
        ds.attrs.update(input_record(self.kind, ds.attrs))
        with atomic_path(p) as tmp:
            ds.to_netcdf(tmp, engine="netcdf4")
        return p

    @classmethod
    def load(cls: type[R], path: str | Path) -> R:
        """Read a result written by :meth:`save`.

        ``Result.load`` reads a result of any kind and returns it as its own class
        (:class:`~reducerlab.analysis.modal.ModalResult`, ...); a subclass's ``load``
        reads only results of its kind.

        Raises
        ------
        ReducerlabError
            Naming the file when it is missing, unreadable (not netCDF, truncated,
            empty), not a reducerlab result, a result of an unknown kind, or (for a
            subclass) a result of another kind.
        """
        p = Path(path)
        if p.is_dir():
            raise ReducerlabError(
                f"{p}: a folder, not a result file; give the .nc file in it "
                "(e.g. body_modal.nc, contact.nc)"
            )
        if not p.exists():
            raise ReducerlabError(f"{p}: no such result file")
        if not p.is_file():
            raise ReducerlabError(
                f"{p}: not a regular file (a device or a pipe), not a result file"
            )
        try:
            with xr.open_dataset(p, engine="netcdf4") as ds:
                data = ds.load()
        except Exception as exc:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError...
            raise ReducerlabError(
                f"{p}: not a readable result file (netCDF): {type(exc).__name__}: {exc}"
            ) from None
        kind = data.attrs.pop("result_kind", None)
        if kind is None:
            raise ReducerlabError(
                f"{p}: a netCDF file but not a reducerlab result (no 'result_kind' attribute)"
            )
        if cls is Result:
            found = cls._class_of(str(kind))
            if found is None:
                raise ReducerlabError(
                    f"{p}: holds a result of unknown kind {kind!r} (known: "
                    f"{', '.join(sorted(_KNOWN_KINDS))})"
                )
            return found(data)  # type: ignore[return-value]
        if kind != cls.kind:
            raise ReducerlabError(f"{p}: holds a {kind!r} result, not a {cls.kind!r} result")
        return cls(data)
