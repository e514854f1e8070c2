"""Every Python script under scripts/ answers `--help` with its usage and runs nothing: no
trubal process, no data file written (a user asking how to run a table must not start it)."""

import glob
import os
import stat
import subprocess
import sys

import pytest

from conftest import ROOT

SCRIPTS = sorted(
    p for p in glob.glob(os.path.join(ROOT, "scripts", "*.py")) + glob.glob(os.path.join(ROOT, "scripts", "bench", "*.py"))
    if '__name__ == "__main__"' in open(p, encoding="utf-8").read()
)


def stub_trubal(tmp_path):
    """An environment whose trubal (TRUBAL_BIN and PATH) only leaves a marker file and fails."""
    marker = tmp_path / "trubal_was_started"
    stub = tmp_path / "trubal"
    stub.write_text(f"#!/bin/sh\ntouch {marker}\nexit 1\n")
    stub.chmod(stub.stat().st_mode | stat.S_IEXEC)
    return dict(os.environ, TRUBAL_BIN=str(stub), PATH=f"{tmp_path}:{os.environ['PATH']}"), marker


def snapshot(directory):
    return {p: os.stat(p).st_mtime_ns for p in glob.glob(os.path.join(directory, "**"), recursive=True)}


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_help_prints_the_usage_and_runs_nothing(script, tmp_path):
    env, marker = stub_trubal(tmp_path)
    data = os.path.join(ROOT, "doc", "data")
    before = snapshot(data)
    out = subprocess.run([sys.executable, script, "--help"], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "usage" in out.stdout.lower() or "python3 scripts/" in out.stdout, out.stdout
    assert not marker.exists(), "--help started trubal"
    assert snapshot(data) == before, "--help wrote into doc/data"
    assert sorted(os.listdir(tmp_path)) == ["trubal"], os.listdir(tmp_path)


# The scripts that take named options: a mistyped one stops the script with its name, before
# anything runs (it used to run the defaults, silently, for up to an hour).
OPTION_SCRIPTS = ["lun_shear.py", "shang_shear.py", "triaxial.py", "pasha_indent.py",
                  "bench/indenter_cost.py", "run_table.py"]


@pytest.mark.parametrize("script", OPTION_SCRIPTS)
def test_an_unknown_option_stops_the_script_with_its_name(script, tmp_path):
    env, marker = stub_trubal(tmp_path)
    data = os.path.join(ROOT, "doc", "data")
    before = snapshot(data)
    args = ["lian6"] if script == "run_table.py" else []
    out = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", script), *args, "--stran", "3"],
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode != 0
    assert "--stran" in out.stderr, out.stderr
    assert not marker.exists(), "the mistyped option started trubal"
    assert snapshot(data) == before
