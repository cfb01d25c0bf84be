"""The README's Python snippets run as written and its CLI error example is what the CLI
prints (examples are tests)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
BLOCKS = re.findall(r"```python\n(.*?)```", README, flags=re.S)


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


def test_readme_error_example_is_what_the_cli_prints(tmp_path, monkeypatch):
    # the README's example message, dimension brackets included, printed verbatim
    from typer.testing import CliRunner

    from reducerlab.cli import app

    shown = re.search(r"```\n(error: invalid design:\n.*?)```", README, flags=re.S)
    assert shown is not None
    text = (ROOT / "examples" / "gear_pair.toml").read_text()
    text = text.replace('mass = "1.25 kg"', 'mass = "-642 g"', 1)
    text = re.sub(r'^stiffness = ".*?"', 'stiffness = "5 kg"', text, count=1, flags=re.M)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.toml").write_text(text)
    r = CliRunner().invoke(app, ["modal", "bad.toml"])
    assert r.exit_code == 2
    assert r.output == shown.group(1)
