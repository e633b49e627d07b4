"""docs/python.md's example runs as written."""

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
