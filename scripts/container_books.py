#!/usr/bin/env python3
"""The books of a shrinking container (issue 49 item 6) through the binary: the 27-sphere
lattice of tests/it/hard_cases.rs in a sphere container and in a cylindrical die shrinking at
10 m/s (the scene of `a_shrinking_container_books_its_work_to_second_order`), at FRAction 0.2,
0.1, 0.05 and 0.025: the printed residual over the input, and the same less the work in
flight at the print (1/2 dt (sum F.v + F_r v_r), from the printed forces and velocities);
then the sphere's squeeze for 9 microseconds and 1 more, in one Cycle and in two with a
command between them that changes nothing (`AWAll 1 V 0 0 0 -10`, the velocity it has): the
residual over the input of each, and their difference (the test
`a_command_that_changes_nothing_leaves_the_books_as_one_cycle`). Usage:

    python3 scripts/container_books.py OUT.csv [TRUBAL_BIN]
"""
import hashlib
import json
import math
import subprocess
import sys
import time
import os

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from heavy_dashpot import prints  # noqa: E402

GLASS = "rad 30e-6 1\nymd 70e9 1\npra 0.3 1\ndensity 2650 1\n"
DT_R = math.pi * 30e-6 * math.sqrt(2650 * 2.6 / 70e9) / (0.1631 * 0.3 + 0.8766)
WALLS = {"sphere": ("sp 5e-4 5e-4 5e-4 2.2e-4", 9.5e-6),
         "cylinder": ("cylinder 5e-4 5e-4 5e-4 0 0 1 2.2e-4", 11.5e-6)}


def run(binary, deck):
    return prints(binary, deck)


def squeeze(binary, kind, fraction):
    wall, t_end = WALLS[kind]
    n = round(t_end / (fraction * DT_R))
    deck = (f"start 1e-3 1e-3 1e-3 10 100 2\nset open all\n{GLASS}fraction {fraction}\n"
            f"aggl 1 5e-4 5e-4 5e-4 1.4e-4\nage 1 1 1 4.4e-4 4.4e-4 4.4e-4 6e-5 6e-5 6e-5\n"
            f"dwall {wall} v 0 0 0 -10\ncycle {n}\nprint energy balls walls info\n")
    out, err = run(binary, deck)
    if "energy" not in out:
        sys.exit(err)
    en, info = out["energy"], out["info"]
    w = out["walls"]["walls"][0]
    fv = sum(sum(f * v for f, v in zip(b["force"], b["vel"])) for b in out["balls"]["balls"])
    flight = 0.5 * info["dt"] * (fv + w["normal_force"] * w["radial_velocity"])
    return f"{en['residual'] / en['input']:+.5e},{(en['residual'] - flight) / en['input']:+.5e}"


def split(binary, fraction, command):
    n = round(9.0e-6 / (fraction * DT_R))
    more = round(1.0e-6 / (fraction * DT_R))
    mid = "awall 1 v 0 0 0 -10\n" if command else ""
    deck = (f"start 1e-3 1e-3 1e-3 10 100 2\nset open all\n{GLASS}fraction {fraction}\n"
            f"aggl 1 5e-4 5e-4 5e-4 1.4e-4\nage 1 1 1 4.4e-4 4.4e-4 4.4e-4 6e-5 6e-5 6e-5\n"
            f"dwall {WALLS['sphere'][0]} v 0 0 0 -10\ncycle {n}\n{mid}cycle {more}\nprint energy\n")
    out, err = run(binary, deck)
    if "energy" not in out:
        sys.exit(err)
    return out["energy"]["residual"] / out["energy"]["input"]


def main():
    out = sys.argv[1]
    binary = sys.argv[2] if len(sys.argv) > 2 else "target/ci/trubal"
    sha = hashlib.sha256(open(binary, "rb").read()).hexdigest()[:16]
    here = __file__.rsplit("/", 2)[0] if "/" in __file__ else "."
    git = subprocess.run(["git", "-C", here or ".", "describe", "--always", "--dirty"],
                         capture_output=True, text=True).stdout.strip()
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows = []
    for kind in WALLS:
        for fraction in [0.2, 0.1, 0.05, 0.025]:
            rows.append(f"squeeze,{kind},{fraction},{squeeze(binary, kind, fraction)}")
    for fraction in [0.2, 0.1, 0.05]:
        one, two = split(binary, fraction, False), split(binary, fraction, True)
        rows.append(f"one Cycle,sphere,{fraction},{one:+.6e},")
        rows.append(f"two Cycles and a command,sphere,{fraction},{two:+.6e},")
        rows.append(f"difference,sphere,{fraction},{two - one:+.3e},")
    with open(out, "w") as f:
        f.write("# Shrinking containers at 10 m/s (issue 49 item 6): residual over input.\n")
        f.write(f"# Made by: python3 scripts/container_books.py {out} {binary}\n")
        f.write(f"# Build: worktree {git}, binary sha256 {sha}..., {started}\n")
        f.write("run,wall,fraction,residual_over_input,less_in_flight\n")
        f.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
