"""Chunked runs (sweep, bifurcation) under hostile conditions: chunk files copied over
each other or from another run, corrupt or empty chunk files and manifests, absurd
worker counts, an unreachable Dask scheduler, and SIGTERM / SIGKILL of a parallel run
(no worker process may survive its parent; the finished chunks stay valid and resume).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.parameters import Axis, parse_values
from reducerlab.analysis.runfolder import chunk_path, load_chunk, open_run, save_chunk
from reducerlab.analysis.sweep import sweep
from reducerlab.analysis.workers import max_workers
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir

GEAR_PAIR = example_dir() / "gear_pair.toml"
KHV = example_dir() / "khv.toml"
DELETE = "delete it to recompute that chunk"


def _sweep(out: Path, **kw) -> object:
    d = load_design(GEAR_PAIR)
    return sweep(d, parse_values("mesh.stiffness", "lin:1e8:2e9:40"), output=out,
                 chunk_size=10, workers=1, track=False, **kw)  # fmt: skip


def _bif(out: Path | None, values=(0.45, 0.5, 0.55, 0.6), **kw) -> object:
    kw = {"periods": 20, "keep": 3, "chunk_size": 2, "workers": 1, **kw}
    return bifurcation(load_design(KHV), Axis("gears.x1", values), output=out, **kw)


# ----------------------------------------------------------------------------- stamps
def test_sweep_chunk_copied_over_another_is_refused(tmp_path):
    first = _sweep(tmp_path)
    chunks = tmp_path / "chunks"
    shutil.copy(chunks / "chunk_00003.npz", chunks / "chunk_00001.npz")
    with pytest.raises(ReducerlabError, match=r"chunk_00001\.npz: holds chunk 3, not chunk 1"):
        _sweep(tmp_path)
    # the fix the message gives works: the chunk is recomputed, the result is unchanged
    (chunks / "chunk_00001.npz").unlink()
    again = _sweep(tmp_path)
    np.testing.assert_array_equal(again.data["frequency"].values, first.data["frequency"].values)


def test_sweep_chunk_of_another_run_is_refused(tmp_path):
    _sweep(tmp_path / "a")
    d = load_design(GEAR_PAIR)
    sweep(d, parse_values("mesh.stiffness", "lin:1e8:3e9:40"), output=tmp_path / "b",
          chunk_size=10, workers=1, track=False)  # fmt: skip
    shutil.copy(tmp_path / "b" / "chunks" / "chunk_00002.npz", tmp_path / "a" / "chunks")
    with pytest.raises(ReducerlabError, match=r"chunk_00002\.npz: chunk of another run") as e:
        _sweep(tmp_path / "a")
    assert DELETE in str(e.value)


def test_chunk_with_other_values_is_refused(tmp_path):
    path = chunk_path(tmp_path, 4)
    path.parent.mkdir()
    save_chunk(path, "k" * 16, 4, np.array([1.0, 2.0]), {"poincare": np.zeros((2, 3))})
    assert load_chunk(path, "k" * 16, 4, np.array([1.0, 2.0]), ["poincare"])["poincare"].shape
    with pytest.raises(ReducerlabError, match="other parameter values than chunk 4"):
        load_chunk(path, "k" * 16, 4, np.array([1.0, 2.5]), ["poincare"])
    with pytest.raises(ReducerlabError, match="other parameter values"):
        load_chunk(path, "k" * 16, 4, np.array([1.0, 2.0, 3.0]), ["poincare"])
    with pytest.raises(ReducerlabError, match="no lam"):
        load_chunk(path, "k" * 16, 4, np.array([1.0, 2.0]), ["lam"])


def test_bifurcation_chunks_are_stamped_and_checked(tmp_path):
    first = _bif(tmp_path)
    chunks = tmp_path / "chunks"
    assert sorted(p.name for p in chunks.iterdir()) == ["chunk_00000.npz", "chunk_00001.npz"]
    shutil.copy(chunks / "chunk_00000.npz", chunks / "chunk_00001.npz")
    with pytest.raises(ReducerlabError, match=r"chunk_00001\.npz: holds chunk 0, not chunk 1"):
        _bif(tmp_path)
    (chunks / "chunk_00001.npz").unlink()
    again = _bif(tmp_path)
    np.testing.assert_array_equal(again.data["poincare"].values, first.data["poincare"].values)
    # a chunk of another bifurcation run (other values) in this folder
    _bif(tmp_path / "other", values=(0.46, 0.5, 0.55, 0.6))
    shutil.copy(tmp_path / "other" / "chunks" / "chunk_00000.npz", chunks)
    with pytest.raises(ReducerlabError, match=r"chunk_00000\.npz: chunk of another run"):
        _bif(tmp_path)


# ----------------------------------------------------------------------------- corrupt files
@pytest.mark.parametrize(
    ("content", "why"),
    [
        (b"", "EOFError"),
        (b"PK\x03\x04 truncated", "BadZipFile"),
        (b"not a zip at all", "BadZipFile|ValueError|OSError|UnpicklingError"),
    ],
)
def test_corrupt_or_empty_chunk_files(tmp_path, content, why):
    _sweep(tmp_path / "s")
    _bif(tmp_path / "b")
    for folder, run in ((tmp_path / "s", _sweep), (tmp_path / "b", _bif)):
        bad = folder / "chunks" / "chunk_00001.npz"
        bad.write_bytes(content)
        with pytest.raises(
            ReducerlabError, match=rf"chunk_00001\.npz: unreadable chunk file \(({why})"
        ) as e:
            run(folder)
        assert DELETE in str(e.value)
        bad.unlink()
        run(folder)  # recomputed


def test_truncated_chunk_file(tmp_path):
    _sweep(tmp_path)
    path = tmp_path / "chunks" / "chunk_00002.npz"
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(ReducerlabError, match=r"chunk_00002\.npz: unreadable chunk file"):
        _sweep(tmp_path)


@pytest.mark.parametrize("text", ["{", "", "[1, 2]", '{"axes": []}', "\udcff"])
def test_corrupt_manifest(tmp_path, text):
    _sweep(tmp_path / "s")
    _bif(tmp_path / "b")
    for path, run in ((tmp_path / "s" / "sweep.json", _sweep),
                      (tmp_path / "b" / "bifurcation.json", _bif)):  # fmt: skip
        path.write_bytes(text.encode("utf-8", "surrogateescape"))
        with pytest.raises(ReducerlabError, match=rf"{path.name}: unreadable run manifest"):
            run(path.parent)
        # deleting it is the fix: the chunks' own stamps are checked against the run
        path.unlink()
        run(path.parent)
        assert json.loads(path.read_text())["key"]


def test_manifest_and_chunks_leave_no_temporary_files(tmp_path):
    _sweep(tmp_path / "s")
    _bif(tmp_path / "b")
    for folder in (tmp_path / "s", tmp_path / "b"):
        names = [p.name for p in folder.rglob("*")]
        assert not [n for n in names if n.startswith(".") or "tmp" in n or "partial" in n]


def test_old_unstamped_chunk_is_refused(tmp_path):
    # a chunk file as written by earlier versions (no stamp)
    _sweep(tmp_path)
    path = tmp_path / "chunks" / "chunk_00000.npz"
    with np.load(path) as z:
        arrays = {k: z[k] for k in ("lam", "phi", "y")}
    np.savez(path, **arrays)
    with pytest.raises(ReducerlabError, match="not a chunk file of this version"):
        _sweep(tmp_path)


# ----------------------------------------------------------------------------- options
@pytest.mark.parametrize("workers", [0, -1, 10**6, True, 2.0])
def test_absurd_worker_counts(workers):
    d = load_design(GEAR_PAIR)
    with pytest.raises(ReducerlabError, match="sweep: workers must be a positive integer"):
        sweep(d, parse_values("mesh.stiffness", "1e8,2e8"), workers=workers)
    with pytest.raises(ReducerlabError, match="bifurcation: workers must be a positive"):
        _bif(None, workers=workers)
    assert max_workers() >= 4


def test_huge_chunk_size_is_one_chunk(tmp_path):
    d = load_design(GEAR_PAIR)
    res = sweep(d, parse_values("pinion.teeth", "20,21,22"), chunk_size=10**12,
                output=tmp_path / "s", workers=4)  # fmt: skip
    assert res.data.sizes["p0"] == 3
    assert [p.name for p in (tmp_path / "s" / "chunks").iterdir()] == ["chunk_00000.npz"]
    assert _bif(tmp_path / "b", chunk_size=10**12).data.sizes["p0"] == 4


def test_unreachable_dask_scheduler_is_a_clear_error():
    dask = pytest.importorskip("dask")
    pytest.importorskip("dask.distributed")
    d = load_design(GEAR_PAIR)
    with (
        dask.config.set({"distributed.comm.timeouts.connect": "1s"}),
        pytest.raises(
            ReducerlabError, match=r"cannot connect to the Dask scheduler 'tcp://127\.0\.0\.1:9'"
        ),
    ):
        sweep(d, parse_values("mesh.stiffness", "1e8,2e8"), scheduler="tcp://127.0.0.1:9")
    with (
        dask.config.set({"distributed.comm.timeouts.connect": "1s"}),
        pytest.raises(ReducerlabError, match="bifurcation: cannot connect to the Dask sched"),
    ):
        _bif(None, scheduler="tcp://127.0.0.1:9")


# ----------------------------------------------------------------------------- signals
linux = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="needs Linux /proc")

# a grid of 40000 per-point (non-affine) evaluations: minutes on 2 workers, killed early
SLOW = ["-p", "pinion.teeth", "-v", "lin:10:209:200", "--grid", "gear.teeth=lin:20:219:200"]


def _children(pid: int) -> set[int]:
    """Live processes whose parent is ``pid`` (from /proc; zombies do not count)."""
    found = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:
            continue
        state, ppid = text.rsplit(")", 1)[1].split()[:2]
        if int(ppid) == pid and state != "Z":
            found.add(int(stat.parent.name))
    return found


def _alive(pid: int) -> bool:
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return text.rsplit(")", 1)[1].split()[0] != "Z"


def _start_parallel_sweep(out: Path) -> tuple[subprocess.Popen, set[int]]:
    """A CLI sweep with 2 workers, running, with its workers up and a chunk written."""
    return _start(["sweep", str(GEAR_PAIR), *SLOW, "-o", str(out), "--chunk-size", "100",
                   "--workers", "2"], out)  # fmt: skip


def _start(args: list[str], out: Path) -> tuple[subprocess.Popen, set[int]]:
    """The CLI with ``args`` running, its workers up and a chunk written in ``out``."""
    cmd = [sys.executable, "-m", "reducerlab", *args]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 30
    workers: set[int] = set()
    while time.time() < deadline and proc.poll() is None:
        workers = _children(proc.pid)
        if len(workers) >= 2 and list((out / "chunks").glob("chunk_*.npz")):
            return proc, workers
        time.sleep(0.05)
    proc.kill()
    pytest.fail(f"the run did not start its workers: {proc.communicate()[1]}")


def _check_no_orphans(workers: set[int]) -> None:
    deadline = time.time() + 5
    while time.time() < deadline and any(_alive(p) for p in workers):
        time.sleep(0.05)
    assert not [p for p in workers if _alive(p)], "worker processes outlived their parent"


class _Stop(Exception):
    pass


def _check_chunks_resume(out: Path) -> None:
    """Every chunk on disk is a valid chunk of the run, and a re-run starts from them."""
    key = json.loads((out / "sweep.json").read_text())["key"]
    written = sorted((out / "chunks").glob("chunk_*.npz"))
    assert written
    d = load_design(GEAR_PAIR)
    pts = np.stack(np.meshgrid(np.linspace(10, 209, 200), np.linspace(20, 219, 200),
                               indexing="ij"), axis=-1).reshape(-1, 2)  # fmt: skip
    for p in written:
        i = int(p.stem.split("_")[1])
        load_chunk(p, key, i, pts[100 * i : 100 * (i + 1)], ["lam", "phi", "y"])
    seen = []

    def stop(done: int, total: int) -> None:
        seen.append((done, total))
        raise _Stop  # the first report comes after the finished chunks were checked

    axes = [parse_values("pinion.teeth", SLOW[3]), parse_values("gear.teeth", SLOW[5][11:])]
    with pytest.raises(_Stop):
        sweep(d, axes, output=out, chunk_size=100, workers=1, progress=stop)
    assert seen == [(len(written), 400)]


@linux
def test_sigterm_of_a_parallel_sweep_stops_its_workers(tmp_path):
    out = tmp_path / "run"
    proc, workers = _start_parallel_sweep(out)
    os.kill(proc.pid, signal.SIGTERM)
    try:
        _, stderr = proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("the sweep did not end on SIGTERM")
    assert proc.returncode == 128 + signal.SIGTERM, stderr
    assert "terminated (SIGTERM)" in stderr and "Traceback" not in stderr
    _check_no_orphans(workers)
    assert not (out / "sweep.nc").exists()
    _check_chunks_resume(out)


@linux
def test_sigkill_of_a_parallel_sweep_leaves_no_worker(tmp_path):
    out = tmp_path / "run"
    proc, workers = _start_parallel_sweep(out)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    _check_no_orphans(workers)
    _check_chunks_resume(out)


# 2000 values, 8 chunks of 250: each chunk's models are built in 2 forked processes
BIF = ["-p", "gears.x1", "-v", "lin:0.416:0.835:2000", "--periods", "200", "--keep", "20",
       "--workers", "2"]  # fmt: skip


@linux
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL])
def test_signals_to_a_parallel_bifurcation_leave_no_worker(tmp_path, sig):
    out = tmp_path / "run"
    proc, workers = _start(["bifurcation", str(KHV), *BIF, "-o", str(out)], out)
    os.kill(proc.pid, sig)
    try:
        _, stderr = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("the bifurcation did not end on the signal")
    assert proc.returncode == (128 + sig if sig == signal.SIGTERM else -sig), stderr
    if sig == signal.SIGTERM:
        # even when the signal lands inside the compiled kernel
        assert "terminated (SIGTERM)" in stderr and "Traceback" not in stderr
    _check_no_orphans(workers)
    written = sorted((out / "chunks").glob("chunk_*.npz"))
    assert written
    seen = []

    def stop(done: int, total: int) -> None:
        seen.append((done, total))
        raise _Stop

    with pytest.raises(_Stop):
        bifurcation(load_design(KHV), parse_values("gears.x1", BIF[3]), periods=200, keep=20,
                    output=out, workers=1, progress=stop)  # fmt: skip
    assert seen == [(250 * len(written), 2000)]


_ORPHAN = """
import os, sys, threading, time
from reducerlab.analysis import workers
pid = os.fork()
if pid == 0:
    null = os.open(os.devnull, os.O_RDWR)
    os.dup2(null, 1)  # let the test's pipe close when the parent exits
    os.dup2(null, 2)
    if sys.argv[1] == "pdeathsig":
        assert workers._set_pdeathsig()
    elif sys.argv[1] == "watchdog":
        threading.Thread(target=workers._watch_parent, args=(os.getppid(),), daemon=True).start()
    time.sleep(30)
    os._exit(0)
print(pid, flush=True)
time.sleep(0.3)
os._exit(0)
"""


@linux
@pytest.mark.parametrize("guard", ["pdeathsig", "watchdog"])
def test_each_guard_alone_ends_an_orphaned_worker(guard):
    # the death signal (Linux) and the watchdog thread (the fallback elsewhere) each end
    # a process whose parent dies (with guard "none" the child sleeps on: the test fails)
    r = subprocess.run([sys.executable, "-c", _ORPHAN, guard], capture_output=True, text=True,
                       timeout=30)  # fmt: skip
    child = int(r.stdout)
    try:
        _check_no_orphans({child})
    finally:
        if _alive(child):
            os.kill(child, signal.SIGKILL)


# ----------------------------------------------------------------------------- run folders
@pytest.mark.parametrize(
    ("text", "why"),
    [
        ('{"run_key": 5}', "no 'key' field (a string)"),
        ('{"key": 5}', "no 'key' field (a string)"),
        ("[1, 2]", "a JSON list, not an object"),
    ],
)
def test_a_manifest_without_its_key_says_which_field(tmp_path, text, why):
    _sweep(tmp_path)
    (tmp_path / "sweep.json").write_text(text)
    with pytest.raises(ReducerlabError, match=re.escape(why)):
        _sweep(tmp_path)


def test_manifests_are_stamped_with_the_design_hash(tmp_path):
    design_hash = load_design(GEAR_PAIR).hash
    _sweep(tmp_path / "s")
    _bif(tmp_path / "b")
    for path in (tmp_path / "s" / "sweep.json", tmp_path / "b" / "bifurcation.json"):
        manifest = json.loads(path.read_text())
        expected = design_hash if path.name == "sweep.json" else load_design(KHV).hash
        assert manifest["design_hash"] == expected and manifest["reducerlab_version"]
    # the stamp is beside the key, not in it: the run resumes
    _sweep(tmp_path / "s")


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux /proc")
def test_a_run_folder_that_cannot_be_created_names_the_folder():
    folder = Path("/proc/reducerlab-no-such-run")
    with pytest.raises(ReducerlabError, match=re.escape(f"{folder}: cannot create or write")):
        open_run(folder, "sweep.json", {"design": None}, "sweep")
    with pytest.raises(ReducerlabError, match=re.escape(f"{folder}: cannot create or write")):
        _sweep(folder)
