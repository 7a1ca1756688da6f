"""The example notebook examples/python/stellar_ages.ipynb runs: its code
cells are executed in order, in one namespace, with plain python (no
Jupyter needed), in a scratch folder; the picture it saves exists and its
bulge is warmer than the galaxy as a whole (the young arms are blue)."""
import json
import os
import sys

import numpy as np
import pytest

SOURCE = os.environ.get("ORRERY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
NOTEBOOK = os.path.join(SOURCE, "examples", "python", "stellar_ages.ipynb")


def test_stellar_ages_notebook(tmp_path, monkeypatch):
    pytest.importorskip("PIL")
    with open(NOTEBOOK) as f:
        nb = json.load(f)
    assert nb["nbformat"] == 4
    cells = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert len(cells) >= 3
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(os.path.dirname(NOTEBOOK))
    namespace = {"__name__": "__main__"}
    for i, cell in enumerate(cells):
        code = compile("".join(cell["source"]), f"{NOTEBOOK} [code cell {i}]", "exec")
        exec(code, namespace)
    assert (tmp_path / "stellar_ages.png").stat().st_size > 10_000
    image = namespace["image"]
    assert image.rgb.shape == (300, 400, 3)
    x, y, z = (image.planes[k].astype(np.float64) for k in "XYZ")
    whole = x.sum() / (x + y + z).sum()
    assert whole < 0.313 < namespace["centre"]  # bluer than D65 overall, redder in the bulge
