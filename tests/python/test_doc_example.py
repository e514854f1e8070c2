"""doc/python.md's example runs as written (the block after `<!-- python example -->`) and
draws its two pictures; its callback ran every 20 cycles."""

import os
import re

from conftest import ROOT


def example():
    text = open(os.path.join(ROOT, "doc", "python.md")).read()
    m = re.search(r"<!-- python example -->\n```python\n(.*?)```", text, re.S)
    assert m, "doc/python.md has no python example block"
    return m.group(1)


def test_doc_example_runs_and_draws(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ns = {}
    exec(compile(example(), "doc/python.md", "exec"), ns)
    for name in ("python_history.png", "python_field.png"):
        data = (tmp_path / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert len(ns["wall"]) == 6000 // 20
    s = ns["s"]
    assert s.cycles == 6001
    # The history recorded every 20 cycles; the wall was hit (a force on it at some sample).
    assert len(ns["h"]["time"]) == 6000 // 20
    assert max(abs(f) for _, f in ns["wall"]) > 0
