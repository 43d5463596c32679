"""The Python examples of README.md and docs/python.md run as written."""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def python_blocks(path):
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


@pytest.mark.parametrize("doc", ["README.md", "docs/python.md"])
def test_doc_examples_run(doc, tmp_path, monkeypatch):
    blocks = [b for b in python_blocks(ROOT / doc) if "# not run" not in b]
    assert blocks, f"{doc} has no python example"
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    namespace = {}
    for block in blocks:  # one namespace: later blocks use earlier ones' names
        exec(compile(block, f"{doc} example", "exec"), namespace)
