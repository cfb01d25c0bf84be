"""Bundled example designs (``examples/*.toml`` of the source tree, shipped in wheels)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["example_dir", "example_files"]


def example_dir() -> Path:
    """Folder holding the bundled example design files."""
    packaged = resources.files("reducerlab") / "data" / "examples"
    if packaged.is_dir():  # installed from a wheel
        return Path(str(packaged))
    return Path(__file__).resolve().parents[2] / "examples"  # source checkout / editable


def example_files() -> list[Path]:
    """All bundled ``*.toml`` designs, sorted by name."""
    return sorted(example_dir().glob("*.toml"))
