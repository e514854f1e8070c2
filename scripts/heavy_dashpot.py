#!/usr/bin/env python3
"""The heavy dashpot of issue 49 item 8 through the binary: the rebound of the sphere of
tests/it/restitution.rs (R = 10 mm, E = 1e8 Pa, nu = 0.3, rho = 2500) against a wall and
against a like sphere, `DAmping REStitution 0.05`, at 1, 10 and 30 m/s, first touch at six
places within a step, at the default step (which a pair with e < 0.1 shortens,
`physics::dashpot::heavy_step_share`) and at FRAction 0.2 given. Writes the relative error
of each rebound against the set e, with its provenance. Usage:

    python3 scripts/heavy_dashpot.py OUT.csv [TRUBAL_BIN]
"""
import hashlib
import json
import math
import subprocess
import sys
import time

MATERIAL = "rad 0.01 1\nymd 1e8 1\npra 0.3 1\ndensity 2500 1\n"
G = 1e8 / 2.6
DT_R = math.pi * 0.01 * math.sqrt(2500 / G) / (0.1631 * 0.3 + 0.8766)


def prints(binary, deck):
    """Runs `deck` through `binary --json`: its JSON prints by kind, and its stderr."""
    p = subprocess.run([binary, "--json", "-"], input=deck, capture_output=True, text=True)
    out = {}
    for line in p.stdout.splitlines():
        try:
            j = json.loads(line)
        except ValueError:
            continue
        out[j.get("print")] = j
    return out, p.stderr


def run(binary, deck):
    out, err = prints(binary, deck)
    if "balls" not in out:
        sys.exit(err)
    return out


def rebound(binary, wall, e, v, phase, fraction):
    """The rebound's e over the set e, less 1, and the step in use."""
    fr = "" if fraction is None else f"fraction {fraction}\n"
    probe = run(binary, f"start 0.1 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{fr}"
                f"damping restitution {e}\ncreate 0.05 0.05 0.05 0 0 0 0 0 0 1 1\n"
                f"print info balls\n")
    dt = probe["info"]["dt"]
    gap = 1e-3 + phase * v * dt
    cycles = int(gap / (v * dt)) + 400
    if wall:
        deck = (f"start 0.1 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{fr}damping restitution {e}\n"
                f"dwall p 0 0 1 0.02\ncreate 0.05 0.05 {0.03 + gap} 0 0 -{v} 0 0 0 1 1\n"
                f"cycle {cycles}\nprint balls\n")
    else:
        deck = (f"start 0.2 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{fr}damping restitution {e}\n"
                f"create 0.07 0.05 0.05 {v / 2} 0 0 0 0 0 1 1\n"
                f"create {0.09 + gap} 0.05 0.05 -{v / 2} 0 0 0 0 0 1 1\n"
                f"cycle {cycles}\nprint balls\n")
    b = run(binary, deck)["balls"]["balls"]
    got = b[0]["vel"][2] / v if wall else (b[1]["vel"][0] - b[0]["vel"][0]) / v
    return got / e - 1.0, dt


def main():
    out = sys.argv[1]
    binary = sys.argv[2] if len(sys.argv) > 2 else "target/ci/trubal"
    sha = hashlib.sha256(open(binary, "rb").read()).hexdigest()[:16]
    here = __file__.rsplit("/", 2)[0] if "/" in __file__ else "."
    git = subprocess.run(["git", "-C", here or ".", "describe", "--always", "--dirty"],
                         capture_output=True, text=True).stdout.strip()
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows = []
    for label, fraction in [("default", None), ("0.2", 0.2)]:
        for wall in [True, False]:
            for v in [1.0, 10.0, 30.0]:
                for phase in [0.0, 0.2, 0.37, 0.5, 0.71, 0.9]:
                    err, dt = rebound(binary, wall, 0.05, v, phase, fraction)
                    rows.append(f"{label},{'wall' if wall else 'sphere'},{v},{phase},"
                                f"{dt / DT_R:.6f},{err:+.5f}")
    with open(out, "w") as f:
        f.write("# Restitution e = 0.05 through the binary (issue 49 item 8): rebound / e - 1.\n")
        f.write(f"# Made by: python3 scripts/heavy_dashpot.py {out} {binary}\n")
        f.write(f"# Build: worktree {git}, binary sha256 {sha}..., {started}\n")
        f.write("step,target,speed_m_s,phase,fraction_in_use,relative_error\n")
        f.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
