#!/usr/bin/env python3
"""The stability bounds of doc/limits.md: hard scenes run through the binary, each either
running (with its energy books) or stopping with a diagnosis.

    python3 scripts/limits.py [--trubal target/release/trubal] [--only NAME ...] [--list]

Every case is a command file written here (ending with PRint ENErgy and PRint INFo), run as
`trubal --json --threads 1 -` under /usr/bin/time -v; the table gives whether it ran, its
wall time, peak memory, the energy residual against the input, the step, and the first
warning or the error. Results: doc/data/limits.csv and the markdown table on stdout.
Python 3 standard library only.
"""
import argparse, csv, json, os, re, subprocess, sys, tempfile, time

import provenance

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

GLASS30 = "rad 30e-6 1\nymd 70e9 1\npra 0.3 1\ndensity 2650 1\n"


def box(extra=""):
    """A closed box of 1 mm with six walls."""
    return ("start 1e-3 1e-3 1e-3 100 {n} 6\n" + extra +
            "dwall p 0 0 1 0\ndwall p 0 0 -1 -1e-3\ndwall p 1 0 0 0\ndwall p -1 0 0 -1e-3\n"
            "dwall p 0 1 0 0\ndwall p 0 -1 0 -1e-3\n")


def bridge(eta):
    # Two 100 um glass spheres with a bridge (0.1 % liquid, 0.025 N/m, eta) pulled apart at
    # 1 m/s and pushed together at 1 m/s: the viscous force at S_min = R*/100 is the stiffest
    # dashpot of a wet scene.
    return ("start 1e-3 1e-3 1e-3 10 10 2\nset open all\nrad 100e-6 1\nymd 70e9 1\npra 0.3 1\n"
            f"density 2650 1\nliquid 0.1 0.025 0 {eta}\n"
            "create 4e-4 5e-4 5e-4 0.5 0 0 0 0 0 1 1\ncreate 6e-4 5e-4 5e-4 -0.5 0 0 0 0 0 1 1\n"
            "cycle 40000\n")


def size_ratio(k):
    # A bed of 40 spheres of 300 um and 400 (k = 10) or 800 (k = 20) of 300/k um, generated
    # at random in a 3 mm x 3 mm x 6 mm box with walls, falling and settling under gravity
    # for 40 ms.
    small = 400 if k <= 10 else 800
    cycles = 250_000 if k <= 10 else 500_000
    return ("start 3e-3 3e-3 6e-3 400 2000 5\nset open all\n"
            f"rad 300e-6 1\nrad {300e-6 / k} 2\nymd 1e8 1\npra 0.3 1\ndensity 2500 1\nfriction 0.3 1\n"
            "damping restitution 0.5\ngravity 0 0 -9.81\n"
            "dwall p 0 0 1 0\ndwall p 1 0 0 0\ndwall p -1 0 0 -3e-3\ndwall p 0 1 0 0\ndwall p 0 -1 0 -3e-3\n"
            f"rge 40 1 1 0\nrge {small} 2 1 0\ncycle {cycles}\n")


def impact(v, wall):
    # A 30 um glass sphere (E = 70 GPa) at v against a wall or a like sphere at rest.
    if wall:
        return ("start 1e-3 1e-3 1e-3 10 10 2\nset open all\n" + GLASS30 +
                "damping restitution 0.5\ndwall p 0 0 1 1e-4\n"
                f"create 5e-4 5e-4 2e-4 0 0 -{v} 0 0 0 1 1\ncycle 2000\n")
    return ("start 1e-3 1e-3 1e-3 10 10 2\nset open all\n" + GLASS30 +
            f"damping restitution 0.5\ncreate 4e-4 5e-4 5e-4 {v} 0 0 0 0 0 1 1\n"
            "create 5e-4 5e-4 5e-4 0 0 0 0 0 0 1 1\ncycle 2000\n")


def overlap(f):
    # Two 1 mm spheres overlapping by a fraction f of the radius (grown from touching), in a
    # closed 10 mm box.
    r = 1e-3
    return ("start 0.01 0.01 0.01 10 10 6\n" + "rad 1e-3 1 \nymd 1e8 1\npra 0.3 1\ndensity 2500 1\n"
            "dwall p 0 0 1 0\ndwall p 0 0 -1 -0.01\ndwall p 1 0 0 0\ndwall p -1 0 0 -0.01\n"
            "dwall p 0 1 0 0\ndwall p 0 -1 0 -0.01\n"
            f"create 0.005 0.005 0.005 0 0 0 0 0 0 1 1\ncreate {0.005 + 2 * r} 0.005 0.005 0 0 0 0 0 0 1 1\n"
            f"rad {r / (1 - f / 2)} 1\ncycle 20000\n")


def million():
    # 10^6 spheres of 0.1 mm generated in a periodic 2 cm box (no walls; 6.5 % solids), 20
    # cycles.
    return ("start 0.02 0.02 0.02 100 1000000 0\nrad 50e-6 1\nymd 1e8 1\npra 0.3 1\ndensity 2500 1\n"
            "friction 0.3 1\ndamping restitution 0.5\nrge 1000000 1 1 0\ncycle 20\n")


def elastic(steps):
    # 27 elastic frictionless spheres in a closed box, no damping: the energy drift over
    # `steps` cycles.
    return ("start 0.01 0.01 0.01 100 100 6\nrad 1e-3 1\nymd 1e8 1\npra 0.3 1\ndensity 2500 1\n"
            "dwall p 0 0 1 0\ndwall p 0 0 -1 -0.01\ndwall p 1 0 0 0\ndwall p -1 0 0 -0.01\n"
            "dwall p 0 1 0 0\ndwall p 0 -1 0 -0.01\n"
            "aggl 1 0.005 0.005 0.005 0.0045\nage 1 1 1 0.002 0.002 0.002 0.003 0.003 0.003\n"
            "velocity 0.3 0.2 -0.1 0\n"
            f"cycle {steps}\n")


CASES = [
    ("bridge eta 0.1 Pa s at S_min", bridge(0.1)),
    ("bridge eta 1 Pa s at S_min", bridge(1.0)),
    ("size ratio 10 bed", size_ratio(10)),
    ("size ratio 20 bed", size_ratio(20)),
    ("E 70 GPa, 20 m/s on a wall", impact(20, True)),
    ("E 70 GPa, 100 m/s on a wall", impact(100, True)),
    ("E 70 GPa, 100 m/s on a sphere", impact(100, False)),
    ("E 70 GPa, 1000 m/s on a wall", impact(1000, True)),
    ("initial overlap 10 %", overlap(0.1)),
    ("initial overlap 50 %", overlap(0.5)),
    ("initial overlap 90 %", overlap(0.9)),
    ("10^6 particles, 20 cycles", million()),
    ("elastic, 10^7 cycles", elastic(10_000_000)),
]


def run(exe, name, deck, tmp):
    deck = deck.replace("{n}", "100") + "print energy info\n"
    t0 = time.time()
    p = subprocess.run(["/usr/bin/time", "-v", exe, "--json", "--threads", "1", "-"],
                       input=deck, text=True, capture_output=True, cwd=tmp)
    wall = time.time() - t0
    mem = re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr)
    mem_mb = int(mem.group(1)) / 1024 if mem else float("nan")
    objs = [json.loads(l) for l in p.stdout.splitlines() if l.startswith("{")]
    energy = [o for o in objs if o.get("print") == "energy"]
    info = [o for o in objs if o.get("print") == "info"]
    msgs = [l for l in p.stderr.splitlines()
            if ("error" in l or "warning" in l) and "Command being timed" not in l]
    if energy:
        e = energy[-1]
        scale = max(abs(e["input"]), 1e-300)
        resid = e["residual"] / scale
    else:
        resid = float("nan")
    dt = info[-1]["dt"] if info else None
    return {
        "case": name,
        "outcome": "ran" if p.returncode == 0 else "stopped",
        "wall_s": round(wall, 2),
        "peak_MB": round(mem_mb, 1),
        "residual_over_input": resid,
        "dt": dt,
        "message": (msgs[0] if msgs else "")[:400],
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trubal", default=os.path.join(ROOT, "target", "release", "trubal"))
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--csv", default=os.path.join(ROOT, "doc", "data", "limits.csv"))
    a = ap.parse_args()
    if a.list:
        for n, _ in CASES:
            print(n)
        return
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, deck in CASES:
            if a.only and not any(o in name for o in a.only):
                continue
            r = run(a.trubal, name, deck, tmp)
            rows.append(r)
            print(f"| {r['case']} | {r['outcome']} | {r['wall_s']} s | {r['peak_MB']} MB | "
                  f"{r['residual_over_input']:.2e} | {r['dt']} | {r['message']} |", flush=True)
    if not a.only:
        with open(a.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)
        provenance.record(a.csv, a.trubal)


if __name__ == "__main__":
    main()
