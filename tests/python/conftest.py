"""Shared decks and helpers of the Python module's tests (`.ci/run` runs them with pytest)."""

import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# An adhesive agglomerate of 150-odd spheres falling onto a wall (the README's prepare.tru
# without its SAve): contacts, JKR bonds, a wall, every part of a step.
IMPACT = """start 1e-3 1e-3 1e-3 1000 200 2
set open all
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
cohesion 0.5 1
agglomerate 1 5.1961524227066318e-4 5.1961524227066318e-4 5.1961524227066318e-4 150e-6
agen 1 1 1 0 0 0 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
agen 1 1 1 34.641016151377545e-6 34.641016151377545e-6 34.641016151377545e-6 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
rad 30.0021e-6 1
cycle 1
velocity 0 0 -0.2 0
dwall p 0 0 1 0.384e-3
"""

# The same agglomerate without the wall and without adhesion: every force on a particle is a
# contact's (no gravity, no wall, no mass damping).
FREE = """start 1e-3 1e-3 1e-3 1000 200 2
set open all
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
agglomerate 1 5.1961524227066318e-4 5.1961524227066318e-4 5.1961524227066318e-4 150e-6
agen 1 1 1 0 0 0 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
agen 1 1 1 34.641016151377545e-6 34.641016151377545e-6 34.641016151377545e-6 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
rad 30.5e-6 1
"""


def trubal_binary():
    """The binary the comparisons run: TRUBAL_BIN, or the test profile's, or release's."""
    env = os.environ.get("TRUBAL_BIN")
    if env:
        return env
    for p in ("target/ci/trubal", "target/release/trubal"):
        path = os.path.join(ROOT, p)
        if os.path.exists(path):
            return path
    found = shutil.which("trubal")
    if found:
        return found
    pytest.skip("no trubal binary (build it: cargo build --profile ci)")


def run_binary(deck, cwd, threads=1, json=False):
    """Runs a deck through the binary in cwd; returns its standard output."""
    args = [trubal_binary(), "-", "--threads", str(threads)] + (["--json"] if json else [])
    r = subprocess.run(args, input=deck, text=True, capture_output=True, cwd=cwd)
    assert r.returncode == 0, r.stderr
    return r.stdout
