"""docs/PYTHON.md's walkthrough is examples/python/walkthrough.py, run: it cannot rot."""
import importlib.util
import os
import re

import pytest


def load_renderer(source_dir):
    path = os.path.join(source_dir, "examples", "python", "render_markdown.py")
    spec = importlib.util.spec_from_file_location("render_markdown", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def numbers_masked(text):
    """The text with every number replaced by '#': the shape of an output, not its figures."""
    return re.sub(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", "#", text)


def test_walkthrough_runs_and_docs_show_its_cells(source_dir):
    renderer = load_renderer(source_dir)
    script = os.path.join(source_dir, "examples", "python", "walkthrough.py")
    # WHEN the walkthrough runs (any exception fails the test)
    fresh = renderer.render(script)
    # THEN docs/PYTHON.md holds exactly its cells, and outputs of the same shape
    doc = renderer.section(open(os.path.join(source_dir, "docs", "PYTHON.md")).read())
    code = lambda md: re.findall(r"```python\n(.*?)```", md, re.S)
    assert code(doc) == code(fresh), "docs/PYTHON.md is stale: rerun the command given there"
    assert len(code(fresh)) >= 6
    fix = "docs/PYTHON.md's outputs changed shape: rerun the command given there"
    assert numbers_masked(doc.strip()) == numbers_masked(fresh.strip()), fix
