"""docs/extending.md runs as written: its Python blocks are executed in order, in one namespace.

The blocks assert their own numbers (the Iwan element against Segalman's power law, the Coulomb
limit and the library's element; the API's and the scene's peaks; the effect's decision).
"""

import re
from pathlib import Path

from hbm.scenes import EFFECTS, MODELS, unregister_effect, unregister_model

PAGE = Path(__file__).resolve().parents[1] / "docs" / "extending.md"


def python_blocks(text):
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_extending_page_runs_as_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the scenes write their outputs here
    blocks = python_blocks(PAGE.read_text())
    assert len(blocks) >= 7
    namespace = {"__name__": "docs_extending"}
    try:
        for i, block in enumerate(blocks):
            exec(compile(block, f"{PAGE.name}[block {i + 1}]", "exec"), namespace)
    finally:  # leave the registries as they were even when a block fails
        if "my-iwan" in MODELS:
            unregister_model("my-iwan")
        if any(e.name == "contact damping" for e in EFFECTS):
            unregister_effect("contact damping")
    assert (tmp_path / "my_iwan_out" / "frf.csv").is_file()
    # the page's own element and the library's agree on the peak it prints
    assert namespace["a_mine"] / namespace["a_lib"] - 1.0 < 1e-5
