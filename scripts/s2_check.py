#!/usr/bin/env python3
"""The cross-code check of doc/validation.md: the dry S2 agglomerate
(scripts/dry_agglomerate_impact.tru, 1 m/s, 4000 steps of 6.39 ns = 25.6 us) against LAMMPS'
damage ratio 0.4211 after the same 4000 steps (../shared/peers/results/
s2_damage_vs_time_explore.txt). Writes doc/data/s2_check.json (damage ratio, bonds broken,
the ledger's residual, wall-clock seconds) with its provenance (scripts/provenance.py).

usage: scripts/s2_check.py        (TRUBAL_BIN selects the binary)
"""
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import provenance  # noqa: E402
import run_table  # noqa: E402

LAMMPS = 0.4211


def main():
    exe = run_table.trubal_binary()
    t0 = time.time()
    out = subprocess.run([exe, os.path.join(HERE, "dry_agglomerate_impact.tru"), "--json", "--threads", "1",
                          "--set", "v=1", "--set", "n=4000"], capture_output=True, text=True, check=True).stdout
    objs = [json.loads(x) for x in out.splitlines() if x.startswith("{")]
    bonds = [o for o in objs if o.get("print") == "bonds"][-1]
    energy = [o for o in objs if o.get("print") == "energy"][-1]
    r = {"damage_ratio": bonds["damage_ratio"], "broken": bonds["broken"], "initial": bonds["initial"],
         "time_us": 1e6 * energy["time"], "residual_over_input": energy["residual"] / energy["input"],
         "lammps_damage_ratio": LAMMPS, "wall_s": round(time.time() - t0, 1)}
    print(json.dumps(r, indent=1))
    path = os.path.join(ROOT, "doc", "data", "s2_check.json")
    with open(path, "w") as fh:
        json.dump(r, fh, indent=1)
        fh.write("\n")
    provenance.record(path, exe)


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
