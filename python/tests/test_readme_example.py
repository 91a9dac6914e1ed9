"""The README's notebook example runs as written, with the tiny model in place of a trained one."""

import contextlib
import io
import os
import re

from conftest import SOURCE_DIR


def test_the_readme_example_runs(tiny_model, tiny_scene, tmp_path, monkeypatch):
    readme = open(os.path.join(SOURCE_DIR, "README.md"), encoding="utf-8").read()
    blocks = [b for b in re.findall(r"```python\n(.*?)```", readme, re.S) if "import nsf" in b]
    assert len(blocks) == 1
    code = blocks[0]
    assert len(code.strip().splitlines()) <= 10
    code = code.replace('"models/rom_tiny.nsf"', repr(tiny_model))
    code = code.replace('"scenes/examples/rom_tiny.json"', repr(tiny_scene))
    monkeypatch.chdir(tmp_path)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "README.md", "exec"), {})
    lowest_rom, lowest_truth = (float(v) for v in printed.getvalue().split())
    assert 0 < lowest_truth < 0.3 and 0 < lowest_rom < 0.4
    assert (tmp_path / "tiny.h5").is_file()
