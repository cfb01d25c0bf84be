"""Chunk data checked on resume (issue 26, item 5): a chunk whose stamps are valid but
whose data were changed after it was written (the reproducer put NaN into a stamped
sweep chunk: "crossing at nan"; into a regime-map chunk: a point became "diverged") is
refused with the file named, and recomputed once deleted."""

from __future__ import annotations

import numpy as np
import pytest

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.parameters import Axis, parse_values
from reducerlab.analysis.runfolder import chunk_path, data_digest, load_chunk, save_chunk
from reducerlab.analysis.sweep import sweep
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir

GEAR_PAIR = example_dir() / "gear_pair.toml"
KHV = example_dir() / "khv.toml"
DELETE = "delete it to recompute that chunk"


def _sweep(out):
    d = load_design(GEAR_PAIR)
    return sweep(d, parse_values("mesh.stiffness", "lin:1e8:2e9:40"), output=out,
                 chunk_size=10, workers=1, track=False)  # fmt: skip


def _bif(out):
    return bifurcation(load_design(KHV), Axis("gears.x1", (0.45, 0.5, 0.55, 0.6)), output=out,
                       periods=20, keep=3, chunk_size=2, workers=1)  # fmt: skip


def _forge(path, **changes):
    """Rewrite a chunk with its stamps kept and some arrays replaced."""
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays.update(changes)
    np.savez(path, **arrays)


def test_digest_sees_every_byte_name_and_shape():
    a = {"x": np.arange(6.0).reshape(2, 3), "y": np.zeros(2)}
    d = data_digest(a)
    assert data_digest({k: v.copy() for k, v in a.items()}) == d
    assert data_digest({"x": a["x"].reshape(3, 2), "y": a["y"]}) != d
    assert data_digest({"z": a["x"], "y": a["y"]}) != d
    b = a["x"].copy()
    b[1, 2] = np.nextafter(b[1, 2], 10)
    assert data_digest({"x": b, "y": a["y"]}) != d


def test_forged_nan_in_a_sweep_chunk_is_refused_then_recomputed(tmp_path):
    first = _sweep(tmp_path)
    path = tmp_path / "chunks" / "chunk_00001.npz"
    with np.load(path) as z:
        lam = z["lam"].copy()
    lam[3] = np.nan
    _forge(path, lam=lam)
    with pytest.raises(ReducerlabError, match=r"chunk_00001\.npz: its data do not match") as e:
        _sweep(tmp_path)
    assert DELETE in str(e.value)
    path.unlink()
    again = _sweep(tmp_path)
    np.testing.assert_array_equal(again.data["frequency"].values, first.data["frequency"].values)


def test_a_sweep_chunk_must_be_finite_even_when_stamped_anew(tmp_path):
    path = chunk_path(tmp_path, 0)
    path.parent.mkdir()
    save_chunk(path, "k" * 16, 0, np.array([1.0, 2.0]), {"lam": np.array([[1.0], [np.nan]])})
    assert np.isnan(load_chunk(path, "k" * 16, 0, np.array([1.0, 2.0]), ["lam"])["lam"][1, 0])
    with pytest.raises(ReducerlabError, match="array 'lam' holds values that are not finite"):
        load_chunk(path, "k" * 16, 0, np.array([1.0, 2.0]), ["lam"], finite=True)


def test_forged_bifurcation_chunk_is_refused(tmp_path):
    _bif(tmp_path)
    path = tmp_path / "chunks" / "chunk_00000.npz"
    with np.load(path) as z:
        pts = np.full_like(z["poincare"], np.nan)  # every point "diverged"
    _forge(path, poincare=pts)
    with pytest.raises(ReducerlabError, match=r"chunk_00000\.npz: its data do not match"):
        _bif(tmp_path)
