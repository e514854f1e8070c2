#!/usr/bin/env python3
"""The elastic gas of tests/it/elastic_gas.rs (issue 49 item 4) with a quieter energy print.

The energy printed at an instant pairs the kinetic energy of the half-step velocities with the
strain energy of the positions, which leaves each contact in flight a term of order F v Δt
(±1.3e-3 of the energy in the dense gas). Two prints a step apart, `PRint ENergy`, `Cycle 1`,
`PRint ENergy`, give the kinetic energy of the two half steps on either side of the second
print's positions: their mean with the second print's strain energy leaves a term of order
Δt², and the scatter from one print to the next falls from 7e-4 to 1e-4 of the energy, so a
drift of 1e-4 shows in 10⁶ steps. The deck is the test's (the same lattice, xorshift draws and
walls), with the lattice's side N, the box L, the FRAction, the seed and walls or a periodic
box as options.

    TRUBAL_BIN=target/ci/trubal python3 scripts/elastic_gas_paired.py OUT.csv STEPS [FRACTION]

Writes OUT.csv (cycle, the quiet residual over the input, the printed one) with its provenance
(scripts/provenance.py) and prints the means of each tenth of the run.
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import provenance  # noqa: E402
from elastic_gas import gas  # noqa: E402

MASK = (1 << 64) - 1


def deck(steps, prints, frac, n=10, length=0.028, seed=0x9E3779B97F4A7C15, walls=True):
    s = f"start {length} {length} {length} 10 {n ** 3 + 10} 6\n"
    if walls:
        s += "set open all\n"
    s += "rad 1e-3 1\nymd 1e8 1\npra 0.3 1\ndensity 2500 1\n"
    if walls:
        s += (
            f"dwall p 1 0 0 0\ndwall p -1 0 0 -{length}\ndwall p 0 1 0 0\n"
            f"dwall p 0 -1 0 -{length}\ndwall p 0 0 1 0\ndwall p 0 0 -1 -{length}\n"
        )
    s += f"fraction {frac}\n"
    s += gas(n, length, seed)
    s += "print energy\ncycle 1\nprint energy\n"
    for _ in range(prints):
        s += f"cycle {steps // prints - 1}\nprint energy\ncycle 1\nprint energy\n"
    return s


def main():
    out, steps = sys.argv[1], int(sys.argv[2])
    frac = float(sys.argv[3]) if len(sys.argv) > 3 else 0.2
    exe = os.environ.get("TRUBAL_BIN", "target/ci/trubal")
    prints = 200
    run = subprocess.run(
        [exe, "--json", "--threads", "1", "-"],
        input=deck(steps, prints, frac),
        capture_output=True,
        text=True,
        env=dict(os.environ, RAYON_NUM_THREADS="1"),
    )
    if run.returncode != 0:
        sys.exit(run.stderr[-2000:])
    e = [json.loads(l) for l in run.stdout.splitlines() if l.startswith("{")]
    e = [x for x in e if x.get("print") == "energy"]
    inp = e[0]["input"]
    rows = []
    for a, b in zip(e[0::2], e[1::2]):
        quiet = (0.5 * (a["kinetic"] + b["kinetic"]) + b["strain"]) / inp - 1.0
        rows.append((b["cycle"], quiet, b["residual"] / inp))
    with open(out, "w") as f:
        f.write(
            f"# The elastic gas of tests/it/elastic_gas.rs at FRAction {frac}, {steps} steps: the "
            "residual over the input with the kinetic energy of the two half steps about each "
            "print (quiet) and as printed.\ncycle,quiet,printed\n"
        )
        for c, q, p in rows:
            f.write(f"{c},{q:.6e},{p:.6e}\n")
    provenance.record(out, exe)
    k = (len(rows) - 1) // 10
    tenths = [sum(r[1] for r in rows[1 + t * k : 1 + (t + 1) * k]) / k for t in range(10)]
    print("tenths:", " ".join(f"{x:+.2e}" for x in tenths))


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
