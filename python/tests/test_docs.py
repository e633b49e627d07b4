"""The examples of docs/python.md and docs/batch.md run as written."""

import os
import re

from conftest import SOURCE_DIR


def test_python_md_example(tmp_path, capsys):
    text = (SOURCE_DIR / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks, "docs/python.md has no python block"
    os.environ.setdefault("ROVE_SOURCE_DIR", str(SOURCE_DIR))
    for code in blocks:
        exec(compile(code, "docs/python.md", "exec"), {"__name__": "__docs__"})
    assert "Converged" in capsys.readouterr().out


def test_batch_md_example(tmp_path, capsys):
    """docs/batch.md's Python block: a 2-worker local cluster and a library job."""
    if not os.environ.get("ROVE_CLI"):
        import pytest
        pytest.skip("the rove command line was not built (ROVE_BUILD_APPS=OFF)")
    text = (SOURCE_DIR / "docs" / "batch.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1, "docs/batch.md should have one python block"
    os.environ.setdefault("ROVE_SOURCE_DIR", str(SOURCE_DIR))
    exec(compile(blocks[0], "docs/batch.md", "exec"), {"__name__": "__main__"})
    out = capsys.readouterr().out
    assert out.count("finished ") == 4 and "4 runs: 4 ok" in out
    assert "library run: same keyframes as the command" in out
