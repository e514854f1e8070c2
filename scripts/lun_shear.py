#!/usr/bin/env python3
"""Simple shear of smooth inelastic spheres against Lun's kinetic theory (issue 35, item 6).

Runs scripts/lun_shear.tru at solid fractions 0.05 ... 0.55 (np = 400 spheres of 20 um,
E = 0.6 GPa, mu = 0, restitution 0.95, s = 10^4 1/s, 60 strain units: the defaults are the
run of doc/validation.md), time-averages the second half of the recorded history and writes
doc/data/lun_shear.csv (with its provenance) and doc/img/lun_shear.png next to the theory of
doc/spec/shang1998.md §3.5 with beta = -1 (smooth spheres: eta2 = 0). Options other than the
defaults print the rows and write nothing (unless --write).

usage: scripts/lun_shear.py [--strain UNITS] [--np N] [--seed K] [--write] [PHI ...]
       scripts/lun_shear.py --chart-only     (redraw from doc/data/lun_shear.csv)
"""
import csv
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import provenance  # noqa: E402
import run_table  # noqa: E402  (binary, chart)

SIGMA, RHO, E, NU, S, ECOEF = 2e-5, 2600.0, 6e8, 0.25, 1e4, 0.95
# `--seed K` discards K x SEED_STRIDE random numbers before the generation (`RGEnerate Seed`
# discards n numbers, TRUBAL's meaning): seeds a few numbers apart can give the same
# assembly (the first tries rejected), so the seeds of the drivers lie 10^7 numbers apart
# (lun_shear, shang_shear, triaxial, pasha_indent and ci_tables.py's samples: this one value).
SEED_STRIDE = 10_000_000


def g0(phi):
    """Carnahan-Starling radial distribution at contact (Shang (2.65))."""
    return (2 - phi) / (2 * (1 - phi) ** 3)


def lun(phi, e=ECOEF, eta2=0.0, kk=0.4):
    """Lun's simple-shear prediction, doc/spec/shang1998.md §3.5, Eqs. 3.6-3.8."""
    eta1 = (1 + e) / 2
    g = g0(phi)
    t3 = eta2 ** 3 / (kk - eta2) if eta2 else 0.0
    f = (1 + 1.6 * (eta1 * (3 * eta1 - 2) + eta2 / 2 * (6 * eta1 - 1 - 2 * eta2) - t3) * phi * g) * (
        1 + 0.8 * (2 * eta1 + 3 * eta2) * phi * g
    ) / (g * ((2 - eta1 - eta2) * (eta1 + eta2) + t3 / 6)) + 192 / (25 * math.pi) * (4 * eta1 + 3 * eta2) * phi ** 2 * g
    gg = phi ** 2 * g * (eta1 * (1 - eta1) + eta2 * (1 - eta2) - t3)
    rt = math.sqrt(1536 * gg / (5 * math.pi * f))
    pxy = 5 / 96 * math.sqrt(math.pi / 3) * f / rt
    pyy = phi * (1 + 4 * eta1 * phi * g) / (3 * rt ** 2)
    return {"F": f, "Rt": rt, "pxy": pxy, "pyy": pyy, "3T": 1 / rt ** 2}


def rayleigh_dt():
    g = E / (2 * (1 + NU))
    return 0.2 * math.pi * SIGMA / 2 * math.sqrt(RHO / g) / (0.1631 * NU + 0.8766)


def start(phi, npart, dt, sigma=SIGMA):
    """The starting cell: side l0 (a random gas at phi <= 0.25) and the compression to the
    side of phi, rate rc for nc cycles (0 when phi <= 0.25)."""
    l = (npart * math.pi * sigma ** 3 / (6 * phi)) ** (1 / 3)
    l0 = l * max(1.0, (phi / 0.25) ** (1 / 3))
    nc = 0 if l0 == l else 20000
    rc = 0.0 if nc == 0 else math.log(l / l0) / (nc * dt)
    return l0, rc, nc


def run_json(exe, tru, sets, work):
    """Runs scripts/TRU with the --set values; the JSON objects it printed."""
    args = [exe, "--json", os.path.join(HERE, tru)]
    for k, v in sets.items():
        args += ["--set", f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}"]
    out = subprocess.run(args, cwd=work, capture_output=True, text=True, check=True).stdout
    return [json.loads(x) for x in out.splitlines() if x.startswith("{")]


STRAIN, NPART, PHIS = 60.0, 400, [0.05, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5, 0.55]


def run(exe, phi, npart, strain, work, seed=0):
    dt = rayleigh_dt()
    l0, rc, nc = start(phi, npart, dt)
    n = int(strain / (S * dt))
    h = max(1, n // 400)
    sets = {"l0": l0, "np": npart, "rc": rc, "nc": nc, "s": S, "n": n, "h": h, "seed": seed * SEED_STRIDE}
    objs = run_json(exe, "lun_shear.tru", sets, work)
    grid = next(o for o in objs if o["print"] == "grid")
    hist = next(o for o in objs if o["print"] == "history")
    cols = hist["columns"]
    rows = [r for r in hist["rows"] if r[0] > nc + n / 2]
    mean = lambda c: sum(r[cols.index(c)] for r in rows) / len(rows)
    size = grid["size"]
    phi_act = npart * math.pi * SIGMA ** 3 / 6 / (size[0] * size[1] * size[2])
    norm = RHO * (SIGMA * S) ** 2
    return {
        "phi": phi_act,
        "pxy": -mean("sxy") / norm,
        "pyy": mean("syy") / norm,
        "3T": 3 * mean("temperature") / (SIGMA * S) ** 2,
        "records": len(rows),
        "strain": grid["strains"][3],
    }


def option(argv, name, default):
    """The value after `name` in argv (removed from it), of default's type, or default."""
    if name in argv:
        i = argv.index(name)
        v = type(default)(argv[i + 1])
        del argv[i : i + 2]
        return v
    return default


def no_other_options(argv):
    """Stops with a message naming every option left in argv once the known ones are taken
    (`option` removes them): a mistyped option must not run the defaults."""
    unknown = [a for a in argv if a.startswith("--")]
    if unknown:
        sys.exit(f"unknown option(s): {' '.join(unknown)} (--help lists the options)")


def main():
    argv = sys.argv[1:]
    strain = option(argv, "--strain", STRAIN)
    npart = option(argv, "--np", NPART)
    seed = option(argv, "--seed", 0)
    write = "--write" in argv
    argv = [x for x in argv if x != "--write"]
    if "--chart-only" in argv:
        with open(os.path.join(ROOT, "doc", "data", "lun_shear.csv")) as fh:
            draw([{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)])
        return
    no_other_options([x for x in argv if x != "--chart-only"])
    phis = [float(x) for x in argv] or PHIS
    documented = (strain, npart, seed, phis) == (STRAIN, NPART, 0, PHIS)
    exe = run_table.trubal_binary()
    work = os.path.join(ROOT, "target", "lun_shear")
    os.makedirs(work, exist_ok=True)
    rows = []
    for phi in phis:
        r = run(exe, phi, npart, strain, work, seed)
        t = lun(r["phi"])
        r.update({"lun_pxy": t["pxy"], "lun_pyy": t["pyy"], "lun_3T": t["3T"]})
        rows.append(r)
        print(json.dumps(r), flush=True)
    if not (documented or write):
        return
    data = os.path.join(ROOT, "doc", "data", "lun_shear.csv")
    with open(data, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    provenance.record(data, exe, particles=npart, strain_units=strain, seed=seed)
    draw(rows)


def draw(rows):
    """The chart: each measure over Lun's prediction, against the solid fraction."""
    run_table.chart(
        os.path.join(ROOT, "doc", "img", "lun_shear.png"),
        "Simple shear of smooth spheres, e = 0.95: trubal over Lun's theory",
        [(lab, [(r["phi"], r[k] / r["lun_" + k]) for r in rows])
         for lab, k in [("P_xy", "pxy"), ("P_yy", "pyy"), ("3T", "3T")]],
        "solid fraction φ",
        "trubal / theory",
        hlines=[1.0],
        hline_label="Lun et al. (1984): 1",
    )


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
