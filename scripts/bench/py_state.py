#!/usr/bin/env python3
"""Reading a 10^5-particle state into numpy: the Python module (`Session.particles()`, copies
from the scene's arrays) against the JSON path the drivers used before it (`trubal - --json`
on a pipe, `PRint Balls`, json.loads, numpy arrays built from the objects), and the module's
own JSON (`Session(json=True).run("print balls")`, no pipe) to tell parsing from the pipe.

Every timing is in-process (time.perf_counter around the read alone, the scene built once),
repeated; the medians are written, with all repetitions, to doc/data/bench/py_state_100k.txt
(or the file given). The machine is shared: the ratio of medians measured in one run is the
figure to quote, not the absolute times.

    python3 scripts/bench/py_state.py [--reps 7] [--out FILE]
"""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

import trubal

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
N_SIDE = 47  # 47^3 = 103 823 particles
L = 0.1
DX = L / N_SIDE
DECK = f"""start {L} {L} {L} 10 110000 2
rad {0.4 * DX!r} 1
density 2650 1
ymd 70e9 1
pra 0.3 1
agen 1 1 1 {DX / 2!r} {DX / 2!r} {DX / 2!r} {DX!r} {DX!r} {DX!r}
velocity 0 0 -0.1 0
cycle 2
"""


def binary():
    """TRUBAL_BIN, or the binary of the profile the module was built in (pip install . builds
    release; .ci/run builds the `ci` profile)."""
    if os.environ.get("TRUBAL_BIN"):
        return os.environ["TRUBAL_BIN"]
    for p in ("target/release/trubal", "target/ci/trubal"):
        path = os.path.join(ROOT, p)
        if os.path.exists(path):
            return path
    sys.exit("no trubal binary: cargo build --release")


def arrays_from_json(balls):
    """The arrays a driver builds from PRint Balls' objects."""
    return {
        "id": np.array([b["id"] for b in balls], dtype=np.uint32),
        "position": np.array([b["pos"] for b in balls]),
        "velocity": np.array([b["vel"] for b in balls]),
        "spin": np.array([b["spin"] for b in balls]),
        "force": np.array([b["force"] for b in balls]),
        "radius": np.array([b["radius"] for b in balls]),
        "material": np.array([b["material"] for b in balls], dtype=np.uint16),
    }


def timed(f, reps):
    out = []
    for _ in range(reps):
        t0 = time.perf_counter()
        r = f()
        out.append(time.perf_counter() - t0)
    return out, r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--out", default=os.path.join(ROOT, "doc", "data", "bench", "py_state_100k.txt"))
    a = ap.parse_args()

    s = trubal.Session(threads=1)
    s.run(DECK)
    n = len(s.particles()["id"])
    t_mod, p = timed(s.particles, a.reps)

    sj = trubal.Session(threads=1, json=True)
    sj.run(DECK)
    t_modjson, q = timed(lambda: arrays_from_json(json.loads(sj.run("print balls"))["balls"]), a.reps)

    pipe = subprocess.Popen([binary(), "-", "--json", "--threads", "1"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True, bufsize=1)
    pipe.stdin.write(DECK)

    def via_pipe():
        pipe.stdin.write("print balls\n")
        pipe.stdin.flush()
        while True:
            line = pipe.stdout.readline()
            if line.startswith('{"balls"') or '"print":"balls"' in line:
                return arrays_from_json(json.loads(line)["balls"])

    t_pipe, r = timed(via_pipe, a.reps)
    pipe.stdin.write("stop\n")
    pipe.stdin.close()
    pipe.wait()
    # The three paths read the same state, bit for bit.
    for k in r:
        assert np.array_equal(p[k], r[k]) and np.array_equal(p[k], q[k]), k

    med = {k: statistics.median(v) for k, v in
           (("module", t_mod), ("module_json", t_modjson), ("pipe_json", t_pipe))}
    head = (f"# reading the particle arrays of a {n}-particle scene into numpy "
            f"(scripts/bench/py_state.py; {a.reps} repetitions each, in-process "
            f"time.perf_counter; medians; shared, loaded machine: the ratio is the figure)\n"
            f"# python {platform.python_version()}, numpy {np.__version__}, trubal module "
            f"{trubal.__version__}, binary {binary()}\n")
    lines = [head, "path\tmedian_s\tratio_to_module\trepetitions_s\n"]
    for k, v in (("module", t_mod), ("module_json", t_modjson), ("pipe_json", t_pipe)):
        lines.append(f"{k}\t{med[k]:.6f}\t{med[k] / med['module']:.1f}\t"
                     + ",".join(f"{x:.6f}" for x in v) + "\n")
    text = "".join(lines)
    sys.stdout.write(text)
    with open(a.out, "w") as fh:
        fh.write(text)


if __name__ == "__main__":
    main()
