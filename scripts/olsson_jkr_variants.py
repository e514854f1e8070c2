#!/usr/bin/env python3
"""Olsson's dry law, measured on a small case (issue 53 items 2-3): the reduced dry agglomerate
of scripts/ci_tables.py (Olsson's size distribution, 400 particles, random seeds 0..N-1, each
prepared once) hits the wall at V m/s (default 2 and 3) with each variant of the contact law:

  trubal           trubal's JKR (snap-in at contact, neck to alpha_s, pairs and walls), its dashpot
  trubal+liggghts  the same with LIGGGHTS' dashpot (SET DASHpot LIGGGHTS): the normal law of
                   the Rasmuson group's LIGGGHTS JKR (eidevag/LIGGGHTS-PUBLIC-JKR)
  nguyen           SET NORmal NGUYEN (one curve from alpha_s, no hysteresis, wall on/off at 0)
  nguyen+liggghts  NGUYEN with LIGGGHTS' dashpot

and writes the fragmentation, capture ratio and damage ratio of every run, with the mean and
standard deviation over the seeds per variant, to doc/data/olsson_jkr_variants.csv (with its
provenance, scripts/provenance.py).

usage: scripts/olsson_jkr_variants.py [--seeds N] [--v 2,3]     (TRUBAL_BIN selects the binary)
"""
import csv
import os
import shutil
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import ci_tables  # noqa: E402
import provenance  # noqa: E402
import run_table  # noqa: E402

VARIANTS = {
    "trubal": ("trubal", ""),
    "trubal+liggghts": ("liggghts", ""),
    "nguyen": ("trubal", "set normal nguyen"),
    "nguyen+liggghts": ("liggghts", "set normal nguyen"),
}


def main():
    argv = sys.argv[1:]
    seeds = int(argv[argv.index("--seeds") + 1]) if "--seeds" in argv else 6
    vs = argv[argv.index("--v") + 1].split(",") if "--v" in argv else ["2", "3"]
    exe = run_table.trubal_binary()
    rows = []
    for k in range(seeds):
        work = tempfile.mkdtemp(prefix=f"olsson_jkr_{k}_")
        try:
            ci_tables.olsson_prepare(exe, work, k)
            for v in vs:
                for name, (dashpot, law) in VARIANTS.items():
                    m = ci_tables.olsson_impact(exe, work, v, dashpot, law)
                    row = {"variant": name, "v": v, "seed": k, **m}
                    print(row, flush=True)
                    rows.append(row)
        finally:
            shutil.rmtree(work, ignore_errors=True)
    summary = []
    for v in vs:
        for name in VARIANTS:
            sel = [r for r in rows if r["variant"] == name and r["v"] == v]
            s = {"variant": name, "v": v, "seed": "mean"}
            d = {"variant": name, "v": v, "seed": "sd"}
            for key in ("fragmentation_pct", "capture_ratio", "damage_ratio"):
                xs = [r[key] for r in sel]
                s[key] = statistics.mean(xs)
                d[key] = statistics.stdev(xs) if len(xs) > 1 else 0.0
            summary += [s, d]
            print(f"v {v} {name}: fragmentation {s['fragmentation_pct']:.2f} ± {d['fragmentation_pct']:.2f} %, "
                  f"capture {s['capture_ratio']:.3f} ± {d['capture_ratio']:.3f}, "
                  f"damage {s['damage_ratio']:.3f} ± {d['damage_ratio']:.3f}", flush=True)
    out = os.path.join(ROOT, "doc", "data", "olsson_jkr_variants.csv")
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, ["variant", "v", "seed", "fragmentation_pct", "capture_ratio", "damage_ratio"])
        w.writeheader()
        for r in rows + summary:
            w.writerow({k: (f"{x:.6g}" if isinstance(x, float) else x) for k, x in r.items()})
    provenance.record(out, exe, seeds=seeds, velocities=vs)


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
