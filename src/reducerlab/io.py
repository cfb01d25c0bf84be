"""Output files: where results go, written atomically, each stamped with its provenance.

One convention for every command of the command line and for the API's ``save``:

- An *output directory* (``-o DIR``) receives a set of files (``modal.nc``,
  ``modal.json``, figures...). :func:`prepare_output_dir` checks it before any
  computation; an :class:`OutputSet` stages every file of the set in a temporary sibling
  directory and moves them into place only when all of them were written, so a failure
  (a figure that cannot be drawn, a full disk) leaves the previous outputs untouched and
  no partial set behind.
- An *output file* (``--export part.stl``) is checked by :func:`prepare_output_file`:
  its suffix, and that its folder can be created, before any computation.
- Existing files are replaced, never silently: every replaced file is reported
  (``replaced DIR/modal.nc``), every new one too (``wrote DIR/modal.json``).
- Single files are written through a temporary name in the same folder and renamed
  (:func:`atomic_path`), so a reader never sees a half-written file; the file gets the
  permissions a plain ``open()`` would give it (``0o666`` less the umask).
- Writability is tested for real, by creating and removing a temporary file (a check of
  permission bits passes everywhere for root, and says nothing of ``/proc`` or a
  read-only file system); failures name the output, never a temporary name.
- Every JSON result file carries :func:`stamp`: package version, creation time, the
  design (SI JSON) and its hash, as the netCDF files do in their attributes.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import hashlib
import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from types import TracebackType
from typing import Any

from . import __version__
from .errors import ReducerlabError

__all__ = [
    "OutputSet",
    "atomic_path",
    "base_stamp",
    "digest",
    "png_metadata",
    "prepare_output_dir",
    "prepare_output_file",
    "stamp",
]

PROVENANCE_KEYS = ("reducerlab_version", "created", "design_hash")


def _read_umask() -> int:
    """The process's umask (set back at once: ``os.umask`` can only read it by setting)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


#: Permissions of every file written (:func:`atomic_path`): those a plain ``open()`` gives.
FILE_MODE = 0o666 & ~_read_umask()


def _probe(directory: Path) -> str | None:
    """Create and remove a temporary file in ``directory``: None when that works, else
    the reason (the system's error text)."""
    try:
        fd, name = tempfile.mkstemp(dir=directory, prefix=".reducerlab-probe-")
    except OSError as exc:
        return exc.strerror or type(exc).__name__
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(name)
    return None


def _writable_ancestor(path: Path, option: str) -> None:
    """Check that ``path`` (which does not exist) could be created: its nearest existing
    ancestor is a directory in which a file can be created."""
    parent = path.parent
    while not parent.exists():
        if parent == parent.parent:  # pragma: no cover - the root always exists
            break
        parent = parent.parent
    if not parent.is_dir():
        raise ReducerlabError(f"{option} {path}: {parent} is a file, not a directory")
    why = _probe(parent)
    if why is not None:
        raise ReducerlabError(
            f"{option} {path}: cannot create it, {parent} is not writable ({why})"
        )


def prepare_output_dir(path: str | Path, option: str = "-o") -> Path:
    """Check that ``path`` can be an output directory, without creating it.

    Parameters
    ----------
    path : str or Path
        The directory: existing (then it must be a writable directory) or not yet
        (then its nearest existing ancestor must be a writable directory).
    option : str
        The option that named it, for the error message.

    Returns
    -------
    Path

    Raises
    ------
    ReducerlabError
        Naming ``option`` and the rule, when the path is an existing file or cannot be
        written.
    """
    p = Path(path)
    if p.exists():
        if not p.is_dir():
            raise ReducerlabError(
                f"{option} {p}: is an existing file; {option} names an output directory"
            )
        why = _probe(p)
        if why is not None:
            raise ReducerlabError(f"{option} {p}: the directory is not writable ({why})")
    else:
        _writable_ancestor(p, option)
    return p


def prepare_output_file(path: str | Path, option: str, suffixes: Iterable[str]) -> Path:
    """Check that ``path`` can be an output file of one of the types ``suffixes``.

    Parameters
    ----------
    path : str or Path
    option : str
        The option that named it, for the error message.
    suffixes : iterable of str
        Accepted suffixes, lower case with the dot (``".stl"``).

    Raises
    ------
    ReducerlabError
        When the suffix is not one of ``suffixes``, the path is a directory, or its
        folder cannot be created or written.
    """
    p = Path(path)
    allowed = tuple(suffixes)
    if p.suffix.lower() not in allowed:
        raise ReducerlabError(
            f"{option}: unknown file type {p.suffix or '(none)'!r} in {p}; "
            f"use one of {', '.join(allowed)}"
        )
    if p.is_dir():
        raise ReducerlabError(f"{option} {p}: is a directory; {option} names one file")
    if p.exists():
        why = "read-only" if not os.access(p, os.W_OK) else _probe(p.parent)
        if why is not None:
            raise ReducerlabError(f"{option} {p}: the file is not writable ({why})")
    else:
        _writable_ancestor(p, option)
    return p


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary name next to ``path``; when the block succeeds, rename it to
    ``path`` (atomic on one file system), otherwise delete it.

    The folder of ``path`` is created if needed. The temporary name keeps the suffix
    (libraries that choose a format from it see the right one). The file gets the
    permissions of a plain ``open()`` (:data:`FILE_MODE`), not the owner-only ones of a
    temporary file.

    Raises
    ------
    ReducerlabError
        Naming ``path`` (not the temporary name) when its folder or the file cannot be
        created or renamed into place. Errors of the block itself pass unchanged.
    """
    p = Path(path)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=p.parent, prefix=f".{p.stem}.", suffix=f".partial{p.suffix}")
        os.close(fd)
    except OSError as exc:
        raise ReducerlabError(f"{p}: cannot write it ({exc.strerror or exc})") from None
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        try:
            os.chmod(tmp_path, FILE_MODE)
            os.replace(tmp_path, p)
        except OSError as exc:
            raise ReducerlabError(f"{p}: cannot write it ({exc.strerror or exc})") from None
    finally:
        tmp_path.unlink(missing_ok=True)


def stamp(attrs: dict[str, Any]) -> dict[str, Any]:
    """Provenance of a result for its JSON file, from its dataset attributes.

    Returns ``{"reducerlab_version", "created", "design_hash", "design"}`` (the design
    as a JSON object, ``None`` when the result was not computed from a design).
    """
    out: dict[str, Any] = {k: attrs.get(k) for k in PROVENANCE_KEYS}
    design = attrs.get("design")
    out["design"] = json.loads(design) if isinstance(design, str) and design else design
    return out


def digest(text: str) -> str:
    """SHA-256 of ``text`` (hex, 16 characters): the hash of a design's JSON."""
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def base_stamp() -> dict[str, str]:
    """``{"reducerlab_version", "created"}``: the stamp of every file written (results,
    figures, run manifests), created now (UTC, to the second)."""
    return {
        "reducerlab_version": __version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }


def png_metadata(attrs: dict[str, Any]) -> dict[str, str]:
    """The provenance of a figure as PNG text chunks (``Software``, ``reducerlab_version``,
    ``created``, ``design_hash``, ``design``), from a result's attributes or a design's
    provenance; read back with e.g. ``PIL.Image.open(path).text``."""
    out = {"Software": f"reducerlab {__version__}"}
    for key in (*PROVENANCE_KEYS, "design"):
        value = attrs.get(key)
        if isinstance(value, str) and value:
            out[key] = value
    if "design" in out and "design_hash" not in out:
        out["design_hash"] = digest(out["design"])
    return {**base_stamp(), **out}


class OutputSet:
    """The files one command writes into an output directory, moved into place together.

    Use as a context manager: :meth:`path` gives the (staged) path of each file to
    write; when the block ends without an exception every staged file is moved into
    ``directory`` (replacing older files, reported); on an exception nothing in
    ``directory`` changes.

    Parameters
    ----------
    directory : str or Path
        The output directory (checked with :func:`prepare_output_dir`).
    option : str
        The option that named it, for error messages.
    report : callable, optional
        Called with one line per file: ``"wrote PATH"`` or ``"replaced PATH"``.
    """

    def __init__(
        self,
        directory: str | Path,
        option: str = "-o",
        report: Callable[[str], None] | None = None,
    ) -> None:
        self.directory = prepare_output_dir(directory, option)
        self.option = option
        self.report = report
        self._names: list[str] = []
        self._stage: Path | None = None

    def __enter__(self) -> OutputSet:
        # stage inside the directory when it exists, else in its nearest existing
        # ancestor (both checked writable): same file system, nothing created on failure
        anchor = self.directory.resolve()
        while not anchor.is_dir():
            anchor = anchor.parent
        try:
            self._stage = Path(tempfile.mkdtemp(dir=anchor, prefix=".reducerlab-partial-"))
        except OSError as exc:
            raise ReducerlabError(
                f"{self.option} {self.directory}: cannot write into it ({exc.strerror or exc})"
            ) from None
        return self

    def path(self, name: str) -> Path:
        """Staged path of the file ``name`` (a plain file name) of the set."""
        if self._stage is None:
            raise RuntimeError("OutputSet.path() outside its 'with' block")
        if Path(name).name != name or name in ("", ".", ".."):
            raise ValueError(f"OutputSet: {name!r} is not a plain file name")
        if name not in self._names:
            self._names.append(name)
        return self._stage / name

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        stage, self._stage = self._stage, None
        assert stage is not None
        try:
            if exc_type is None:
                self._commit(stage)
        finally:
            shutil.rmtree(stage, ignore_errors=True)

    def _commit(self, stage: Path) -> None:
        missing = [n for n in self._names if not (stage / n).is_file()]
        if missing:
            raise ReducerlabError(
                f"{self.option} {self.directory}: {', '.join(missing)} were not written"
            )
        for name in self._names:
            if (self.directory / name).is_dir():
                raise ReducerlabError(
                    f"{self.option} {self.directory / name}: is a directory, not a file"
                )
        target = self.directory
        created = not self.directory.exists()
        moved: list[tuple[Path, Path | None]] = []  # (target, backup of the old file)
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            for name in self._names:
                target = self.directory / name
                backup = None
                if target.exists():  # kept until the whole set is in place
                    backup = stage / f".old.{name}"
                    try:
                        os.link(target, backup)
                    except OSError:  # a file system without hard links
                        shutil.copy2(target, backup)
                os.chmod(stage / name, FILE_MODE)
                os.replace(stage / name, target)
                moved.append((target, backup))
        except OSError as exc:  # put the previous set back; name the output, not the stage
            for done, backup in reversed(moved):
                with contextlib.suppress(OSError):
                    if backup is None:
                        done.unlink()
                    else:
                        os.replace(backup, done)
            if created:
                with contextlib.suppress(OSError):
                    self.directory.rmdir()
            raise ReducerlabError(
                f"{self.option} {target}: cannot write it ({exc.strerror or exc}); the "
                "previous outputs are unchanged"
            ) from None
        for done, backup in moved:
            if self.report is not None:
                self.report(f"{'replaced' if backup is not None else 'wrote'} {done}")
