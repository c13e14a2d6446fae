"""The Python code of the README and of the guide's pages (getting started, Python, Monte Carlo, events, optimal control) runs: each page's blocks in
order, in one namespace, as a reader would paste them."""

import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [
    ROOT / "README.md",
    ROOT / "docs" / "guide" / "getting-started.md",
    ROOT / "docs" / "guide" / "python.md",
    ROOT / "docs" / "guide" / "montecarlo.md",
    ROOT / "docs" / "guide" / "events.md",
    ROOT / "docs" / "guide" / "optimal.md",
]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_the_pages_python_runs(page):
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(), re.S)
    assert blocks, f"{page} has no Python block"
    namespace = {}
    for block in blocks:
        exec(compile(block, str(page), "exec"), namespace)
