"""Base class of analysis results: an xarray Dataset with provenance, saved as netCDF."""

from __future__ import annotations

import datetime as _dt
import json
from pathlib import Path
from typing import Any, ClassVar, TypeVar

import xarray as xr

from . import __version__
from .errors import ReducerlabError

__all__ = ["Result", "provenance"]

R = TypeVar("R", bound="Result")


def provenance(metadata: dict[str, Any] | None = None) -> dict[str, str]:
    """Attributes recorded in every result: package version, time, design and its hash."""
    meta = dict(metadata or {})
    attrs = {
        "reducerlab_version": __version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    design = meta.pop("design", None)
    if design is not None:
        attrs["design"] = design if isinstance(design, str) else json.dumps(design)
    for key, value in meta.items():
        attrs[key] = value if isinstance(value, str) else json.dumps(value)
    return attrs


class Result:
    """A result holding an :class:`xarray.Dataset` (``.data``).

    Subclasses set ``kind`` (stored in the file so :meth:`load` can check it).
    """

    kind: ClassVar[str] = "result"

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

    def save(self, path: str | Path) -> Path:
        """Write the dataset to a netCDF file and return its path."""
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        ds = self.data.copy()
        ds.attrs["result_kind"] = self.kind
        ds.to_netcdf(p, engine="netcdf4")
        return p

    @classmethod
    def load(cls: type[R], path: str | Path) -> R:
        """Read a result written by :meth:`save`."""
        p = Path(path)
        if not p.is_file():
            raise ReducerlabError(f"{p}: no such result file")
        with xr.open_dataset(p, engine="netcdf4") as ds:
            data = ds.load()
        kind = data.attrs.pop("result_kind", None)
        if kind != cls.kind:
            raise ReducerlabError(f"{p}: holds a {kind!r} result, not a {cls.kind!r} result")
        return cls(data)
