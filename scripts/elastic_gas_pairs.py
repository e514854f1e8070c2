#!/usr/bin/env python3
"""Binary collisions of the elastic gas's spheres (issue 49 item 4) at spread phases, through the
binary: 400 pairs (or spheres at a plane wall) side by side, each touching at another phase of
the step, R = 1 mm, E = 1e8 Pa, ν = 0.3, ρ = 2500 kg/m³, frictionless, no damping, relative
speed U, offset b of the radii's sum (b = 0 head-on), FRAction F. Every pair has the same energy,
so the residual over the input once all have parted is the mean error per collision over the
phase of first touch.

    TRUBAL_BIN=target/ci/trubal python3 scripts/elastic_gas_pairs.py OUT.csv [F]

Writes OUT.csv (case, U, b, mean error per collision) with its provenance (scripts/provenance.py).
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import provenance  # noqa: E402


def deck(u, frac, b, wall, n=20):
    dt = 2.73663e-5 * frac  # the Rayleigh step of these spheres times FRAction
    side = 0.006 * n + 0.006
    out = [
        f"start 0.03 {side} {side} 10 {2 * n * n + 10} 6",
        "set open all",
        "rad 1e-3 1",
        "ymd 1e8 1",
        "pra 0.3 1",
        "density 2500 1",
        f"fraction {frac}",
    ]
    if wall:
        out.append("dwall p 1 0 0 0")
    for k in range(n * n):
        ph = (k + 0.5) / (n * n)
        y, z = 0.006 + 0.006 * (k // n), 0.006 + 0.006 * (k % n)
        if wall:
            gap = 0.001 + ph * u * dt
            out.append(f"create {1e-3 + gap} {y} {z} {-u} {u * b} 0 0 0 0 1 1")
        else:
            gap = 0.002 + ph * u * dt
            dx = (4e-6 * (1.0 - b * b)) ** 0.5
            out.append(f"create {0.015 - dx / 2 - gap / 2} {y} {z} {u / 2} 0 0 0 0 0 1 1")
            out.append(f"create {0.015 + dx / 2 + gap / 2} {y + 2e-3 * b} {z} {-u / 2} 0 0 0 0 0 1 1")
    out += ["print energy", f"cycle {int(0.004 / u / dt) + 300}", "print energy"]
    return "\n".join(out) + "\n"


def main():
    out = sys.argv[1]
    frac = float(sys.argv[2]) if len(sys.argv) > 2 else 0.2
    exe = os.environ.get("TRUBAL_BIN", "target/ci/trubal")
    cases = [("pair", u, b) for u in (1.0, 2.0) for b in (0.0, 0.3, 0.5, 0.7, 0.85, 0.95)]
    cases += [("wall", 1.0, 0.0), ("wall", 1.0, 0.5)]
    rows = []
    for case, u, b in cases:
        run = subprocess.run(
            [exe, "--json", "--threads", "1", "-"],
            input=deck(u, frac, b, case == "wall"),
            capture_output=True,
            text=True,
            check=True,
        )
        e = [json.loads(l) for l in run.stdout.splitlines() if '"print":"energy"' in l][-1]
        rows.append((case, u, b, e["residual"] / e["input"]))
        print(case, u, b, f"{rows[-1][3]:+.3e}", flush=True)
    with open(out, "w") as f:
        f.write(
            f"# Binary collisions of the elastic gas's spheres at FRAction {frac}, 400 phases of "
            "first touch: mean error per collision (residual over the input after parting).\n"
            "case,speed,offset,mean_error\n"
        )
        for case, u, b, r in rows:
            f.write(f"{case},{u},{b},{r:.4e}\n")
    provenance.record(out, exe)


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
