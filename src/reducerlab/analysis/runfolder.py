"""Resumable run folders of the chunked runs (sweep, bifurcation).

A run folder holds a manifest (``sweep.json``, ``bifurcation.json``: the run's
specification and its key, a hash of that specification) and ``chunks/chunk_NNNNN.npz``,
one per finished chunk. Every chunk file is stamped with the run key, its chunk index
and the parameter values it was computed for; on resume each is checked against the
run before it is used. Every file is written atomically (a temporary file in the same
folder, then renamed: :func:`reducerlab.io.atomic_path`), and every file read on resume
goes through one loader (:func:`read_manifest`, :func:`load_chunk`) that turns any
failure into a :class:`~reducerlab.errors.ReducerlabError` naming the file and the fix.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..io import atomic_path, base_stamp

__all__ = [
    "chunk_path",
    "data_digest",
    "load_chunk",
    "open_run",
    "read_manifest",
    "run_key",
    "save_chunk",
]

_STAMP = ("run_key", "chunk_index", "chunk_values", "chunk_digest")


def data_digest(arrays: dict[str, NDArray]) -> str:
    """SHA-256 (hex) of a chunk's result arrays: names, dtypes, shapes and bytes, in
    name order. Stamped into each chunk so that data edited or damaged after writing
    (a NaN put into a stamped file, a flipped byte) is refused on resume."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def run_key(spec: dict[str, Any]) -> str:
    """The run key: 16 hex digits of the SHA-256 of the specification (sorted JSON)."""
    return hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()[:16]


def read_manifest(path: Path) -> dict[str, Any] | None:
    """The manifest at ``path`` (``None`` when there is none).

    Raises
    ------
    ReducerlabError
        When it cannot be read or is not a JSON object with a run key.
    """
    if not path.exists():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(data, dict):
            raise ValueError(f"not a run manifest: a JSON {type(data).__name__}, not an object")
        if not isinstance(data.get("key"), str):
            raise ValueError("not a run manifest: no 'key' field (a string)")
    except (OSError, ValueError) as exc:  # JSONDecodeError and UnicodeError are ValueErrors
        raise ReducerlabError(
            f"{path}: unreadable run manifest ({type(exc).__name__}: {exc}); delete it to "
            "start the run's record anew (finished chunks carry their own run stamp and "
            "are checked against the run), or choose another output folder"
        ) from None
    return data


def open_run(folder: Path, manifest: str, spec: dict[str, Any], what: str) -> str:
    """Prepare ``folder`` for the run ``spec``: check or write its manifest.

    Parameters
    ----------
    folder : Path
        The run folder (created with its ``chunks`` folder).
    manifest : str
        The manifest's file name (``"sweep.json"``).
    spec : dict
        JSON-ready specification of the run; its hash is the run key. Its ``"design"``
        entry, the design hash, is also written as ``"design_hash"`` in the stamp.
    what : str
        The kind of run, for messages (``"sweep"``, ``"bifurcation run"``).

    Returns
    -------
    str
        The run key.

    Raises
    ------
    ReducerlabError
        When the folder holds another run, its manifest is unreadable, or the folder or
        its files cannot be created (naming the folder).
    """
    key = run_key(spec)
    path = folder / manifest
    try:
        (folder / "chunks").mkdir(parents=True, exist_ok=True)
        old = read_manifest(path)
        if old is None:
            # the stamp (version, creation time, design hash) sits beside the key, not
            # in it: a later version resumes a run when the specification is the same
            stamp = {**base_stamp(), "design_hash": spec.get("design")}
            text = json.dumps({"key": key, **stamp, **spec}, indent=1)
            with atomic_path(path) as tmp:
                tmp.write_text(text, encoding="utf-8")
        elif old["key"] != key:
            shown = old.get("axes", old.get("path"))
            detail = f" ({shown})" if shown is not None else ""
            raise ReducerlabError(
                f"{folder} holds a different {what}{detail}; choose another output folder "
                "or delete it"
            )
        # temporary files of chunk writes cut short by a kill (their complete files were
        # never renamed into place): nothing reads them, so they go
        for stale in (folder / "chunks").glob(".chunk_*.partial.npz"):
            stale.unlink(missing_ok=True)
    except OSError as exc:
        raise ReducerlabError(
            f"{folder}: cannot create or write the {what} folder ({exc.strerror or exc}); "
            "choose another output folder"
        ) from None
    return key


def chunk_path(folder: Path, index: int) -> Path:
    """The file of chunk ``index`` in the run folder ``folder``."""
    return folder / "chunks" / f"chunk_{index:05d}.npz"


def save_chunk(
    path: str | Path, key: str, index: int, values: NDArray, arrays: dict[str, NDArray]
) -> None:
    """Write one finished chunk atomically, stamped with its run, index and values.

    Parameters
    ----------
    path : path
        The chunk file (``.npz``).
    key : str
        Run key (:func:`run_key`).
    index : int
        Chunk index in the run.
    values : ndarray
        The parameter values of the chunk's points (SI).
    arrays : dict
        The results of the chunk.
    """
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(
            f,
            run_key=np.asarray(key),
            chunk_index=np.asarray(index, dtype=np.int64),
            chunk_values=np.asarray(values, dtype=float),
            chunk_digest=np.asarray(data_digest(arrays)),
            **arrays,
        )
        f.flush()
        os.fsync(f.fileno())


def load_chunk(
    path: Path,
    key: str,
    index: int,
    values: NDArray,
    names: Iterable[str] = (),
    finite: bool = False,
) -> dict[str, NDArray]:
    """Read chunk ``index`` of run ``key`` and check its stamp.

    Parameters
    ----------
    path : Path
        The chunk file.
    key, index, values
        What the file must be stamped with: run key, chunk index, and the parameter
        values of the chunk's points (compared exactly).
    names : iterable of str
        The result arrays to read (their first axis must match ``values``); none to
        check the stamp only.
    finite : bool
        Whether every value of the arrays must be finite (a modal sweep's are; a
        bifurcation marks a diverged point with NaN).

    Returns
    -------
    dict
        The arrays named in ``names``.

    Raises
    ------
    ReducerlabError
        When the file cannot be read (empty, truncated, not a chunk file), belongs to
        another run, chunk or set of values, or its data do not match their stamp or
        break ``finite``; the message names the file and tells to delete it, after
        which the next run recomputes that chunk.
    """
    fix = "delete it to recompute that chunk"
    values = np.asarray(values, dtype=float)
    names = tuple(names)
    try:
        with np.load(path, allow_pickle=False) as z:
            missing = [n for n in (*_STAMP, *names) if n not in z.files]
            if missing:
                raise ValueError(f"not a chunk file of this version (no {', '.join(missing)})")
            got_key = str(z["run_key"])
            got_index = int(z["chunk_index"])
            got_values = z["chunk_values"]
            got_digest = str(z["chunk_digest"])
            stored = {n: z[n] for n in z.files if n not in _STAMP}
            arrays = {n: stored[n] for n in names}
    except Exception as exc:  # BadZipFile, EOFError, OSError, ValueError...
        raise ReducerlabError(
            f"{path}: unreadable chunk file ({type(exc).__name__}: {exc}); {fix}"
        ) from None
    if got_key != key:
        raise ReducerlabError(
            f"{path}: chunk of another run (run key {got_key}, this run's is {key}); {fix}"
        )
    if got_index != index:
        raise ReducerlabError(
            f"{path}: holds chunk {got_index}, not chunk {index} (copied or renamed?); {fix}"
        )
    if got_values.shape != values.shape or not np.array_equal(got_values, values):
        raise ReducerlabError(
            f"{path}: computed for other parameter values than chunk {index} of this run; {fix}"
        )
    if data_digest(stored) != got_digest:
        raise ReducerlabError(
            f"{path}: its data do not match its stamp (changed or damaged after it was "
            f"written); {fix}"
        )
    for n, a in arrays.items():
        if finite and not np.all(np.isfinite(a)):
            raise ReducerlabError(f"{path}: array {n!r} holds values that are not finite; {fix}")
        if a.ndim == 0 or a.shape[0] != values.shape[0]:
            raise ReducerlabError(
                f"{path}: array {n!r} has shape {a.shape}, not one row per point of the "
                f"chunk ({values.shape[0]}); {fix}"
            )
    return arrays
