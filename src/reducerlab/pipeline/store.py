"""The stage cache of ``reducerlab run``: every stage's output stored under a key that
hashes only what the stage depends on (issue 27).

A key is the SHA-256 of a canonical JSON object: the stage's name, the cache schema,
the package version and the stage's inputs (the design fields it reads, as SI values,
and its settings). Changing damping therefore leaves the keys of the finite-element
stages (tooth compliance, body modes) and of the loaded contact unchanged, while it
changes the key of the dynamics. A result file is the stage's :class:`~reducerlab.results.Result`
as netCDF (``STAGE-KEY.nc``); what a result keeps in memory only (the tooth compliance
of the contact analysis, a body's mesh and mode shapes for renders) is stored beside it
(``STAGE-KEY.pkl``), and ``STAGE-KEY.json`` records the inputs the key was made from, so
that a user can see why a stage was recomputed. Every file is written to a temporary
name and moved into place: an interrupted run leaves no half-written entry, and a
damaged entry (unreadable file) is discarded and recomputed, never used.
"""

from __future__ import annotations

import json
import math
import os
import pickle
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .. import __version__
from ..errors import ReducerlabError
from ..io import FILE_MODE, digest

__all__ = ["SCHEMA", "Store", "canonical"]

#: Bumped when a stage's stored form changes: older entries are then never matched.
#: Keys hold the package version, not the code: a change to a stage's or a report
#: section's code within one version (development) needs this bumped, or a kept cache
#: answers with the old result. 4: the contact's tooth-root stress (issue 29), the
#: compliance's fillet influence in its key; 5: the contact's load exponent (issue 30).
SCHEMA = 5


def _plain(value: Any) -> Any:
    """JSON form of numpy scalars and arrays, tuples and non-finite floats."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    raise TypeError(f"not JSON: {type(value).__name__}")


def canonical(obj: Any) -> str:
    """The canonical JSON text of ``obj`` (sorted keys, no spaces): the text a key hashes."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=_plain)


class Store:
    """Stage outputs in one folder, addressed by ``(stage, key)``.

    Parameters
    ----------
    root : path
        The cache folder (created on first write).
    """

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        if self.root.exists() and not self.root.is_dir():
            raise ReducerlabError(f"cache: {self.root} exists and is not a folder")

    def key(self, stage: str, inputs: Mapping[str, Any]) -> str:
        """The key of ``stage`` with ``inputs`` (16 hex characters)."""
        return digest(
            canonical(
                {"stage": stage, "schema": SCHEMA, "version": __version__, "inputs": dict(inputs)}
            )
        )

    def file(self, stage: str, key: str, suffix: str) -> Path:
        """``ROOT/STAGE-KEY.SUFFIX`` (stage names are plain words and digits)."""
        return self.root / f"{stage}-{key}{suffix}"

    def has(self, stage: str, key: str) -> bool:
        """Whether a complete entry exists (its record is written last)."""
        return self.file(stage, key, ".json").is_file()

    def _write(self, path: Path, write: Any) -> None:
        self.root.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=self.root, prefix=".tmp-", suffix=path.suffix)
        os.close(fd)
        try:
            write(Path(tmp))
            os.chmod(tmp, FILE_MODE)  # readable as a plain open() would leave it
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise

    def put(
        self,
        stage: str,
        key: str,
        inputs: Mapping[str, Any],
        result: Any = None,
        extra: Any = None,
    ) -> Path | None:
        """Store a stage's output: ``result`` (a Result, as netCDF) and ``extra`` (any
        picklable object kept in memory only), then the record of its inputs. Returns
        the netCDF file (None without a result)."""
        nc = None
        if result is not None:
            nc = self.file(stage, key, ".nc")
            self._write(nc, result.save)
        if extra is not None:
            self._write(
                self.file(stage, key, ".pkl"),
                lambda p: p.write_bytes(pickle.dumps(extra, protocol=pickle.HIGHEST_PROTOCOL)),
            )
        record = canonical(
            {"stage": stage, "key": key, "version": __version__, "inputs": dict(inputs)}
        )
        self._write(self.file(stage, key, ".json"), lambda p: p.write_text(record + "\n"))
        return nc

    def get(self, stage: str, key: str, extra: bool = False) -> tuple[Any, Any] | None:
        """``(result, extra)`` of a stored entry, or None when there is none or it cannot
        be read (then it is removed, to be recomputed)."""
        from ..results import Result

        if not self.has(stage, key):
            return None
        nc, pkl = self.file(stage, key, ".nc"), self.file(stage, key, ".pkl")
        try:
            result = Result.load(nc) if nc.exists() else None
            if result is not None:
                result.data.load()  # read now: the file may be replaced later
            more = pickle.loads(pkl.read_bytes()) if extra and pkl.exists() else None
            if extra and not pkl.exists():
                raise FileNotFoundError(pkl)
        except Exception:  # damaged or foreign entry: never used, recomputed
            self.drop(stage, key)
            return None
        return result, more

    def drop(self, stage: str, key: str) -> None:
        """Remove an entry."""
        for suffix in (".json", ".nc", ".pkl"):
            self.file(stage, key, suffix).unlink(missing_ok=True)
