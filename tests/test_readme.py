"""The README's API tour runs as written (a reader's first copy-paste must work): the
multi-bounce scene blocks and the 3D scene block, executed in a temporary folder."""
import os
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"


def _blocks(section, n):
    text = README.read_text()
    i = text.index(section)
    j = text.index("\n### ", i + len(section))
    blocks = re.findall(r"```python\n(.*?)```", text[i:j], re.S)
    assert len(blocks) >= n, f"{section}: {len(blocks)} python blocks"
    return blocks[:n]


def _run(code, tmp_path):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        ns = {}
        exec(compile(code, str(README), "exec"), ns)
        return ns
    finally:
        os.chdir(cwd)


def test_multi_bounce_scene_runs_as_written(tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("pyarrow")
    first, recording = _blocks("### A multi-bounce scene", 2)
    ns = _run(first + recording.replace("600.0", "3.0"), tmp_path)
    assert ns["result"].status == "done"
    assert (tmp_path / "events.csv").stat().st_size > 0
    assert ns["res"].n_events == ns["result"].n_events
    assert len(ns["res"].snapshots[0]) == 301


def test_3d_scene_runs_as_written(tmp_path):
    (block,) = _blocks("### A 3D scene", 1)
    ns = _run(block, tmp_path)
    assert ns["result"].status == "done"
