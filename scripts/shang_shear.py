#!/usr/bin/env python3
"""Shang's cohesive simple shear (issue 35, item 6): runs scripts/shang_shear.tru (480 silica
spheres of 20 um, phi = 0.45, JKR Gamma = 0.2 N/m, Walton's law, mu = 0.4) and prints the
time-averaged P_xy/rho(sigma s)^2, P_yy/rho(sigma s)^2 and 3T/(sigma s)^2 next to Shang's
time-step table (1.2326, 2.4509, 1.3184 at s = 12000 1/s) and Lun's theory (e = 0.95,
beta = 0); with --sweep, the same at several shear rates, against the energy cohesion number
CN_e (Shang (3.17)), written to doc/data/shang_shear.csv and doc/img/shang_shear.png.

The defaults are the runs of doc/validation.md: 30 strain units, seed 0, Shang's step; the
sweep at s = 12000, 8000, 6000, 4500, 3000 1/s. --record appends each run, with its
provenance (scripts/provenance.py), to doc/data/shang_shear_runs.jsonl.

usage: scripts/shang_shear.py [--strain UNITS] [--frac F] [--seed K] [--sweep] [--record] [S ...]
       scripts/shang_shear.py --chart-only     (redraw from doc/data/shang_shear.csv)
"""
import csv
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import lun_shear  # noqa: E402
import provenance  # noqa: E402
import run_table  # noqa: E402

SIGMA, RHO, E, NU, GAMMA_SHANG = 2e-5, 2600.0, 6e10, 0.25, 0.2
E_STAR = E / (2 * (1 - NU ** 2))
FRAC = 0.8281
SEED = 0


def cn_e(phi, s, gamma=GAMMA_SHANG):
    """Shang (3.17): phi Gamma^(5/3) / (rho sigma^(11/3) s^2 E*^(2/3))."""
    return phi * gamma ** (5 / 3) / (RHO * SIGMA ** (11 / 3) * s ** 2 * E_STAR ** (2 / 3))


def run(exe, phi, npart, s, strain, work):
    g = E / (2 * (1 + NU))
    dt = FRAC * math.pi * SIGMA / 2 * math.sqrt(RHO / g) / (0.1631 * NU + 0.8766)
    l0, rc, nc = lun_shear.start(phi, npart, dt)
    n = int(strain / (s * dt))
    sets = {"l0": l0, "np": npart, "rc": rc, "nc": nc, "s": s, "n": n, "h": max(1, n // 400),
            "gamma": GAMMA_SHANG / 2, "frac": FRAC, "seed": SEED * lun_shear.SEED_STRIDE}
    objs = lun_shear.run_json(exe, "shang_shear.tru", sets, work)
    hist = next(o for o in objs if o["print"] == "history")
    cols = hist["columns"]
    rows = [r for r in hist["rows"] if r[0] > nc + n / 2]
    mean = lambda c: sum(r[cols.index(c)] for r in rows) / len(rows)
    norm = RHO * (SIGMA * s) ** 2
    return {"phi": phi, "s": s, "seed": SEED, "strain": strain, "cn_e": cn_e(phi, s), "pxy": -mean("sxy") / norm,
            "pyy": mean("syy") / norm, "3T": 3 * mean("temperature") / (SIGMA * s) ** 2,
            "dt": dt, "steps": n}


def main():
    argv = sys.argv[1:]
    if "--chart-only" in argv:
        with open(os.path.join(ROOT, "doc", "data", "shang_shear.csv")) as fh:
            draw([{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)])
        return
    strain = 30.0
    strain = lun_shear.option(argv, "--strain", strain)
    global FRAC, SEED
    SEED = lun_shear.option(argv, "--seed", SEED)
    FRAC = lun_shear.option(argv, "--frac", FRAC)
    sweep = "--sweep" in argv
    record = "--record" in argv
    argv = [a for a in argv if a not in ("--sweep", "--record")]
    lun_shear.no_other_options(argv)
    rates = [float(a) for a in argv] or ([12000, 8000, 6000, 4500, 3000] if sweep else [12000])
    exe = run_table.trubal_binary()
    work = os.path.join(ROOT, "target", "shang_shear")
    os.makedirs(work, exist_ok=True)
    kt = lun_shear.lun(0.45, e=0.95, eta2=0.4 / (2 * 1.4))
    out = []
    for s in rates:
        r = run(exe, 0.45, 480, s, strain, work)
        r.update({"kt_pxy": kt["pxy"], "kt_pyy": kt["pyy"], "kt_3T": kt["3T"]})
        out.append(r)
        print(json.dumps(r), flush=True)
        if record:
            with open(os.path.join(ROOT, "doc", "data", "shang_shear_runs.jsonl"), "a") as fh:
                fh.write(json.dumps(dict(r, **provenance.stamp(exe))) + "\n")
    if sweep:
        with open(os.path.join(ROOT, "doc", "data", "shang_shear.csv"), "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(out[0].keys()))
            w.writeheader()
            w.writerows(out)
        provenance.record(os.path.join(ROOT, "doc", "data", "shang_shear.csv"), exe, strain_units=strain, seed=SEED)
        draw(out)


def draw(rows):
    """The chart doc/img/shang_shear.png: the stresses against CN_e."""
    run_table.chart(
        os.path.join(ROOT, "doc", "img", "shang_shear.png"),
        "Shang's cohesive simple shear, φ = 0.45",
        [(lab, [(r["cn_e"], r[k]) for r in rows]) for lab, k in [("P_xy / ρ(σs)²", "pxy"), ("P_yy / ρ(σs)²", "pyy"), ("3T / (σs)²", "3T")]],
        "energy cohesion number CN_e (Shang's critical range 4–9e-3)",
        "stress / ρ(σs)²,  3T / (σs)²",
        logx=True,
    )

if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
