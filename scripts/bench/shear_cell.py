#!/usr/bin/env python3
"""The sheared-cell benchmark of doc/performance.md ("The sheared cell", issue 35).

From an S1 bed saved by bed2tru.py (bed10000.sav): settles it 20,000 steps, puts the
particles in a periodic cell 40 x 40 x (highest centre + R) mm without walls or gravity
(shear0.sav), and writes shear_run.tru (GRID 0 0 0 5 0 0, 3000 steps) and still_run.tru (the
same cell at rest), to be timed side by side with side_by_side.sh or TRUBAL_TIMING=1.

usage: shear_cell.py DIR     (DIR holds bed10000.sav; TRUBAL_BIN or target/release/trubal)
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    d = sys.argv[1]
    exe = os.environ.get("TRUBAL_BIN", os.path.join(ROOT, "target", "release", "trubal"))
    with open(os.path.join(d, "settle.tru"), "w") as fh:
        fh.write("restart bed10000.sav\ncycle 20000\nprint balls\n")
    out = subprocess.run([exe, "--json", "settle.tru"], cwd=d, capture_output=True, text=True, check=True).stdout
    balls = [json.loads(x) for x in out.splitlines() if '"balls"' in x][-1]["balls"]
    r = 1e-3
    zmax = max(b["pos"][2] for b in balls) + r
    lines = [
        f"start 0.040 0.040 {zmax:.9e} 10000 10000 0",
        "rad 1e-3 1", "density 2500 1", "ymd 1e7 1", "pra 0.3 1", "friction 0.5 1",
        "damping restitution 0.5", "fraction 0.2", "set tangential noslip", "set genoverlap 0.01",
    ]
    for b in balls:
        x, y, z = b["pos"]
        lines.append(f"cr {x % 0.04:.9e} {y % 0.04:.9e} {z:.9e} 0 0 0 0 0 0 1 1")
    lines += ["cycle 1", "save shear0.sav"]
    with open(os.path.join(d, "build_shear.tru"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    subprocess.run([exe, "build_shear.tru"], cwd=d, capture_output=True, check=True)
    with open(os.path.join(d, "shear_run.tru"), "w") as fh:
        fh.write("restart shear0.sav\ngrid 0 0 0 5 0 0\ncycle 3000\nprint info\n")
    with open(os.path.join(d, "still_run.tru"), "w") as fh:
        fh.write("restart shear0.sav\ncycle 3000\nprint info\n")


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
