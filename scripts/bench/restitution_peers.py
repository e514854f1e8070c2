#!/usr/bin/env python3
"""Restitution at the time step: trubal against LIGGGHTS on the same binary impact.

The scene is the peers' S3 (../shared/peers/s3_hertz_binary: Chung & Ooi test 1, two glass
spheres R = 10 mm, E = 48 GPa, nu = 0.2, rho = 2800, +-10 m/s, touching at t = 0) with a
restitution coefficient e set, at FRAction (fraction of the Rayleigh step, the same
definition in both codes) 0.05 ... 1. Prints a markdown table of the rebound's relative
error (e_measured / e - 1) of both codes; writes doc/data/restitution_peers.csv.

    python3 scripts/bench/restitution_peers.py [--trubal target/release/trubal]

LIGGGHTS 3.8 (Debian package `liggghts`) must be on the PATH.
"""
import argparse, csv, math, os, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
FRACTIONS = [0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0]
ES = [0.1, 0.3, 0.5, 0.7, 0.9]
# Elastic contact duration of the scene (Hertz), in Rayleigh steps (for the table).
M = 2800 * 4 / 3 * math.pi * 0.01 ** 3
E_STAR = 48e9 / (2 * (1 - 0.2 ** 2))
TC = 2.868 * ((M / 2) ** 2 / (0.005 * E_STAR ** 2 * 20.0)) ** 0.2
DT_R = math.pi * 0.01 * math.sqrt(2800 / (48e9 / 2.4)) / (0.1631 * 0.2 + 0.8766)


# The impact (two spheres at +-10 m/s) as equal_error.py runs it at any speed.
from equal_error import liggghts_e, trubal_e

sys.path.insert(0, os.path.dirname(HERE))
import provenance  # noqa: E402


def liggghts(frac, e, tmp):
    return liggghts_e(frac, e, 20.0, tmp)


def trubal(exe, frac, e, tmp):
    return trubal_e(exe, frac, e, 20.0, tmp)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trubal", default=os.path.join(ROOT, "target", "release", "trubal"))
    ap.add_argument("--csv", default=os.path.join(ROOT, "doc", "data", "restitution_peers.csv"))
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for f in FRACTIONS:
            for e in ES:
                rows.append((f, e, trubal(a.trubal, f, e, tmp), liggghts(f, e, tmp)))
    with open(a.csv, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["fraction", "steps_per_contact", "e_set", "e_trubal", "e_liggghts"])
        for f, e, t, l in rows:
            w.writerow([f, f"{TC / (f * DT_R):.2f}", e, f"{t:.6f}", f"{l:.6f}"])
    provenance.record(a.csv, a.trubal)
    head = "| FRAction | steps per contact | " + " | ".join(f"e = {e}: trubal / LIGGGHTS" for e in ES) + " |"
    print(head)
    print("|" + "---|" * (2 + len(ES)))
    for f in FRACTIONS:
        cells = []
        for e in ES:
            t, l = next((t, l) for ff, ee, t, l in rows if ff == f and ee == e)
            cells.append(f"{100 * (t / e - 1):+.2f} % / {100 * (l / e - 1):+.2f} %")
        print(f"| {f} | {TC / (f * DT_R):.1f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
