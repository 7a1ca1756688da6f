"""Every Python block of docs/python.md runs, in order, in one namespace
(as a reader would paste them), in a scratch folder holding configs/."""
import os
import re

import pytest

SOURCE = os.environ.get("ORRERY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def python_blocks(path):
    with open(path) as f:
        return re.findall(r"```python\n(.*?)```", f.read(), re.S)


def test_docs_python_blocks_run(tmp_path, monkeypatch, capsys):
    pytest.importorskip("PIL")
    blocks = python_blocks(os.path.join(SOURCE, "docs", "python.md"))
    assert len(blocks) >= 4
    os.symlink(os.path.join(SOURCE, "configs"), tmp_path / "configs")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
    assert (tmp_path / "python-dome.png").exists()
    out = capsys.readouterr().out
    assert "unknown key 'cmaera'" in out and "array positions: shape (10000, 2)" in out
