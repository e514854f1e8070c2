#!/usr/bin/env python3
"""The cost of a large indenter in a bed (issue 36, item 1; doc/indentation.md, "The indenter
and the contact search").

Loads the unloaded bed that scripts/pasha_indent.py saved (target/pasha_indent/unloaded<tag>.sav)
and times N cycles, one thread, in three states: without the indenter; with the indenter
pressed into the bed (to 0.3 of its radius) and held still; with it moving down at the
procedure's speed. Prints per state the CPU (and wall-clock) seconds per 1000 cycles, the rebuilds of the
candidate list, the particle-wall candidates and the indenter's contacts.

usage: scripts/bench/indenter_cost.py [--tag T] [--n N] [--d MM] [--v M/S]
"""
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
import run_table  # noqa: E402
from lun_shear import no_other_options, option as arg  # noqa: E402


def session(work):
    p = subprocess.Popen([run_table.trubal_binary(), "--json", "--threads", "1", "-"], cwd=work,
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                         text=True, bufsize=1)

    def ask(cmd, item=None):
        p.stdin.write(cmd + "\n")
        p.stdin.flush()
        if item is None:
            return None
        while True:
            line = p.stdout.readline()
            if not line:
                raise RuntimeError(f"trubal ended at `{cmd}`")
            if line.startswith("{"):
                o = json.loads(line)
                if o.get("print") == item:
                    return o

    def cpu():
        """The process's CPU seconds (user + system; robust to other jobs on the machine)."""
        with open(f"/proc/{p.pid}/stat") as fh:
            f = fh.read().rsplit(")", 1)[1].split()
        return (int(f[11]) + int(f[12])) / os.sysconf("SC_CLK_TCK")

    return p, ask, cpu


def main():
    argv = sys.argv[1:]
    tag = arg(argv, "--tag", "_fine")
    n = arg(argv, "--n", 4000)
    d = arg(argv, "--d", 16.0) * 1e-3
    v = arg(argv, "--v", 0.15)
    no_other_options(argv)
    work = os.path.join(ROOT, "target", "pasha_indent")
    out = {}
    for state in ["none", "held", "moving"]:
        p, ask, cpu = session(work)
        ask(f"restart unloaded{tag}.sav")
        info = ask("print info", "info")
        balls = ask("print balls", "balls")["balls"]
        walls = ask("print walls", "walls")["walls"]
        die = walls[0]["geometry"]["Cylinder"]
        c = die["point"]
        under = [b["pos"][2] + b["radius"] for b in balls
                 if math.hypot(b["pos"][0] - c[0], b["pos"][1] - c[1]) < d / 2]
        if state != "none":
            z0 = max(under) + d / 2 + 1e-4
            ask(f"dwall ob {c[0]!r} {c[1]!r} {z0!r} {d / 2!r} v 0 0 {-v!r} m 3")
            ask("cycle 1")
            dt = ask("print info", "info")["dt"]
            ask(f"cycle {int(0.3 * d / 2 / v / dt)}")
            if state == "held":
                ask("awall 4 v 0 0 0")
        e0 = ask("print entries", "entries")
        t, c0 = time.time(), cpu()
        ask(f"cycle {n}")
        e1 = ask("print entries", "entries")
        sec, csec = time.time() - t, cpu() - c0
        w = ask("print info", "info")
        out[state] = {
            "particles": info["balls"], "cpu_seconds_per_1000": csec / n * 1000, "wall_seconds_per_1000": sec / n * 1000,
            "rebuilds": e1["rebuilds"] - e0["rebuilds"],
            "wall_contacts": w["wall_contacts"],
        }
        ask("stop")
        p.stdin.close()
        p.wait()
        print(state, json.dumps(out[state]), flush=True)


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
