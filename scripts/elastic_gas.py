#!/usr/bin/env python3
"""The elastic gas of tests/it/elastic_gas.rs (issue 49 item 4) through the binary, with its
prints written to a data file of doc/data with their provenance.

The command file is the test's `deck(steps, 100)` to the byte: the same lattice, the same
xorshift generator and Box-Muller draws, numbers written as Rust's `{:e}` writes them (the
shortest digits that read back to the same double). Usage:

    python3 scripts/elastic_gas.py STEPS OUT.csv [TRUBAL_BIN]

e.g. `python3 scripts/elastic_gas.py 10000000 doc/data/elastic_gas_1e7.csv target/ci/trubal`.
"""
import hashlib
import json
import math
import os
import subprocess
import sys
import time
from decimal import Decimal

MASK = (1 << 64) - 1


def rust_e(x):
    """Rust's `{:e}` of an f64: shortest round-trip digits, `d.ddde-N`, no `+`."""
    if x == 0.0:
        return "-0e0" if math.copysign(1.0, x) < 0 else "0e0"
    sign, digits, exp = Decimal(repr(x)).as_tuple()
    digits = "".join(map(str, digits)).rstrip("0") or "0"
    # repr may carry trailing zeros in the exponent form; the value is digits × 10^(exp + k).
    n_stripped = len("".join(map(str, Decimal(repr(x)).as_tuple()[1]))) - len(digits)
    e10 = exp + n_stripped + len(digits) - 1
    mant = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    return ("-" if sign else "") + f"{mant}e{e10}"


def gas(n, length, seed):
    """The `create` lines of n³ spheres on a lattice of pitch length/n, each velocity component
    normal with 0.5 m/s (xorshift64 from `seed`, Box-Muller): the gas of tests/it/elastic_gas.rs."""
    state = [seed]

    def uniform():
        x = state[0]
        x ^= (x << 13) & MASK
        x ^= x >> 7
        x ^= (x << 17) & MASK
        state[0] = x
        return ((x >> 11) + 0.5) / float(1 << 53)

    def normal():
        u1, u2 = uniform(), uniform()
        return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)

    a = length / n
    s = ""
    for i in range(n):
        for j in range(n):
            for k in range(n):
                p = lambda q: (q + 0.5) * a
                v = [0.5 * normal(), 0.5 * normal(), 0.5 * normal()]
                s += "create {} {} {} {} {} {} 0 0 0 1 1\n".format(
                    rust_f(p(i)), rust_f(p(j)), rust_f(p(k)), rust_e(v[0]), rust_e(v[1]), rust_e(v[2])
                )
    return s


def deck(steps, prints):
    length = 0.028
    s = (
        f"start {length} {length} {length} 10 1010 6\nset open all\nrad 1e-3 1\nymd 1e8 1\n"
        f"pra 0.3 1\ndensity 2500 1\n"
        f"dwall p 1 0 0 0\ndwall p -1 0 0 -{length}\ndwall p 0 1 0 0\n"
        f"dwall p 0 -1 0 -{length}\ndwall p 0 0 1 0\ndwall p 0 0 -1 -{length}\n"
    )
    s += gas(10, length, 0x9E3779B97F4A7C15)
    s += "print energy\n"
    for _ in range(prints):
        s += f"cycle {steps // prints}\nprint energy\n"
    return s


def rust_f(x):
    """Rust's `{}` of an f64 (shortest round-trip digits, no exponent)."""
    r = repr(x)
    if "e" in r or "E" in r:
        r = format(Decimal(r), "f")
    if r.endswith(".0"):
        r = r[:-2]
    return r


def main():
    steps, out = int(sys.argv[1]), sys.argv[2]
    binary = sys.argv[3] if len(sys.argv) > 3 else "target/ci/trubal"
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    describe = subprocess.run(
        ["git", "describe", "--always", "--dirty"], cwd=root, capture_output=True, text=True
    ).stdout.strip()
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    with open(binary, "rb") as f:
        sha = hashlib.sha256(f.read()).hexdigest()[:16]
    t0 = time.time()
    run = subprocess.run(
        [binary, "--json", "--threads", "1", "-"],
        input=deck(steps, 100),
        capture_output=True,
        text=True,
        env=dict(os.environ, RAYON_NUM_THREADS="1"),
    )
    # 130: stopped by Ctrl-C (SIGINT to the binary); the prints so far are complete.
    if run.returncode not in (0, 130):
        sys.exit(run.stderr)
    prints = [json.loads(l) for l in run.stdout.splitlines() if l.startswith("{")]
    energy = [p for p in prints if p.get("print") == "energy"]
    rows = [e["residual"] / e["input"] for e in energy]
    done = (len(rows) - 1) * (steps // 100)
    note = "" if run.returncode == 0 else f" (interrupted after {done} steps)"
    with open(out, "w") as f:
        f.write(
            f"# The elastic gas of tests/it/elastic_gas.rs (1000 spheres, the default step: FRAction 0.1 since 7655d24, 0.2 before), {steps} steps: "
            "energy residual over the input at each print.\n"
            f"# Made by: python3 scripts/elastic_gas.py {steps} {out} {binary}\n"
            f"# Build: worktree {describe}, binary sha256 {sha}..., started {started}, "
            f"{time.time() - t0:.0f} s wall{note}\n"
            "cycle,residual_over_input\n"
        )
        for k, r in enumerate(rows):
            f.write(f"{k * (steps // 100)},{r:.6e}\n")
    for t in range(10):
        w = rows[1 + 10 * t : 11 + 10 * t]
        if w:
            print(f"{(t + 1) * steps // 10:>9} steps: mean {sum(w) / len(w):+.3e}")
    print(f"largest |print| {max(abs(r) for r in rows):.3e}")


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
