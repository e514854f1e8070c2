#!/usr/bin/env python3
"""The elastic gas's contacts sorted by how their edges were corrected, with the energy each
kind carries: for the measurement build ca03ee3 only (reverted), whose binary prints on
standard error, at the end of a run, one `DBG kind FLAGS n N sum W abs A eon E1 eoff E2` line
per kind (a contact's life: first overlap to the step after its release correction).

`W` is the leap-frog work of the contact's force over its life, `Σ F_n·(v_{n−½} + v_{n+½})/2
Δt` (zero for an exact integration; with other contacts on the same bodies it also carries the
exchange of the scheme's O(Δt²) energy between contacts, so only the sum over all kinds is
the gas's drift), `E1`, `E2` the excess of the onset and release as `physics::hertz_edge::Edge`
works it out (applied where the edge is corrected, left in the gas where the guard skips it:
an onset's skipped excess is `−E1` of kinetic energy, a release's `+E2`). FLAGS bits: 0 first
overlap, 2 onset corrected, 3 onset `Edge::of` None, 4 onset guard (step below h/2), 5 release
kept, 6 a contact of a single step, 7 release corrected, 8 release None, 9 release guard,
10 closed again before the release correction, 12 a plane wall, 18–21 why the onset was
None (q ≤ 0, disc < 0, φ > 1, h ≤ 0).

    TRUBAL_BIN=/path/to/the/ca03ee3/build python3 scripts/elastic_gas_edge_kinds.py OUT STEPS FRACTION

The deck is scripts/elastic_gas_paired.py's (the gas of tests/it/elastic_gas.rs, walls).
Writes OUT (one line per kind, energies over the input) with its provenance.
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import provenance  # noqa: E402
from elastic_gas_paired import deck  # noqa: E402

NAMES = {0: "start", 2: "onset", 3: "onset-None", 4: "onset-guard", 5: "release-kept",
         6: "single-step", 7: "release", 8: "release-None", 9: "release-guard",
         10: "closed-again", 12: "wall", 18: "q<=0", 19: "disc<0", 20: "phi>1", 21: "h<=0"}


def main():
    out, steps, frac = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    exe = os.environ["TRUBAL_BIN"]
    run = subprocess.run([exe, "--json", "--threads", "1", "-"], input=deck(steps, 10, frac),
                         capture_output=True, text=True,
                         env=dict(os.environ, RAYON_NUM_THREADS="1"))
    if run.returncode != 0:
        sys.exit(run.stderr[-2000:])
    e = [json.loads(l) for l in run.stdout.splitlines() if l.startswith("{")]
    e = [x for x in e if x.get("print") == "energy"]
    inp = e[0]["input"]
    a, b = e[-2], e[-1]
    quiet = (0.5 * (a["kinetic"] + b["kinetic"]) + b["strain"]) / inp - 1.0
    lines = [f"# The elastic gas at FRAction {frac}, {steps} steps (walls): contacts by kind of "
             f"edge correction; energies over the input {inp:.6e} J. The quiet residual at the "
             f"end {quiet:+.3e}.",
             "kind,contacts,work,abs_work,onset_excess,release_excess"]
    for l in run.stderr.splitlines():
        t = l.split()
        if l.startswith("DBG total"):
            lines[0] += f" The sum of the contacts' work {float(t[2]) / inp:+.3e}."
        elif l.startswith("DBG kind"):
            k = int(t[2], 16)
            name = "+".join(NAMES.get(i, str(i)) for i in range(24) if k >> i & 1)
            lines.append(f"{name},{t[4]},{float(t[6]) / inp:+.3e},{float(t[8]) / inp:.3e},"
                         f"{float(t[10]) / inp:+.3e},{float(t[12]) / inp:+.3e}")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    provenance.record(out, exe)
    print("\n".join(lines))


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
