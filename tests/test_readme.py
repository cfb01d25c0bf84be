"""The README's Python snippets run as written (examples are tests)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), flags=re.S)


def test_readme_has_python_snippets():
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_readme_snippet_runs(code, tmp_path, monkeypatch):
    # relative paths in the README are from the repository root; outputs go to tmp
    src = code.replace('"examples/', f'"{ROOT}/examples/')
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(src, "README.md", "exec"), namespace)
    if "res" in namespace:
        assert namespace["res"].frequencies.size == 6
        assert (tmp_path / "modal.nc").exists() and (tmp_path / "shapes.png").exists()
    if "model" in namespace:
        assert namespace["model"].n >= 2
