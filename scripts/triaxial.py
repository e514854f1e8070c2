#!/usr/bin/env python3
"""Isotropic compression and a constant-mean-stress triaxial test in the periodic cell
(issue 35, item 3): runs scripts/triaxial.tru, writes doc/data/triaxial.csv (axial strain,
deviator q/p, volumetric strain, mobilised friction angle) and doc/img/triaxial.png, and
prints the peak and critical-state friction angles and the servo's error.

usage: scripts/triaxial.py [--chart-only] [--np N] [--p PA] [--rate 1/S] [--strain AXIAL] [--mu0 MU] [--seed K] [--tag T] [--gain G]
                           [--niso CYCLES]

The defaults are the loose sample of doc/validation.md (600 spheres, --mu0 0.5, --gain 1.5e-2);
the dense one is `--np 1000 --mu0 0 --gain 5e-3 --tag _dense`.
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
import run_table  # noqa: E402
from lun_shear import SEED_STRIDE, no_other_options, option as arg  # noqa: E402

R_MEAN = 1.1e-4
E, NU, RHO = 1e9, 0.3, 2600.0


def dt():
    g = E / (2 * (1 + NU))
    return 0.2 * math.pi * 1e-4 * math.sqrt(RHO / g) / (0.1631 * NU + 0.8766)


OPTIONS = {"np": 600, "p": 1e5, "rate": 5.0, "strain": 0.25, "mu0": 0.5, "seed": 0, "gain": 1.5e-2, "niso": 80000}


def run(exe, opts, work, deck=None):
    """Runs the command file `deck` (scripts/triaxial.tru) in `work` with OPTIONS updated by
    opts; returns the rows (axial strain, q/p, volumetric strain, mobilised friction angle,
    mean stress, one per history record of the triaxial stage) and the summary."""
    o = dict(OPTIONS, **opts)
    npart, p, rate, gain = int(o["np"]), o["p"], o["rate"], o["gain"]
    n = int(o["strain"] / (rate * dt()))
    vols = sum(math.pi * 4 / 3 * rr ** 3 for rr in [1e-4] * (npart // 2) + [1.2e-4] * (npart // 2))
    sets = {"l": (vols / 0.2) ** (1 / 3), "np": npart, "half": npart // 2, "p": p, "rate": rate, "n": n,
            "niso": int(o["niso"]), "h": max(1, n // 300), "mu0": o["mu0"], "seed": int(o["seed"]) * SEED_STRIDE, "g": gain}
    args = [exe, "--json", deck or os.path.join(HERE, "triaxial.tru")]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    out = subprocess.run(args, cwd=work, capture_output=True, text=True, check=True).stdout
    objs = [json.loads(x) for x in out.splitlines() if x.startswith("{")]
    stresses = [o for o in objs if o["print"] == "stress"]
    grids = [o for o in objs if o["print"] == "grid"]
    hist = next(o for o in objs if o["print"] == "history")
    cols = hist["columns"]
    c = lambda name: cols.index(name)
    e0 = grids[1]["strains"]
    rows = []
    for r in hist["rows"]:
        s1 = r[c("szz")]
        s3 = (r[c("sxx")] + r[c("syy")]) / 2
        ea = -(r[c("e33")] - e0[2])
        ev = -sum(r[c(k)] - e0[i] for i, k in enumerate(["e11", "e22", "e33"]))
        mean = (r[c("sxx")] + r[c("syy")] + r[c("szz")]) / 3
        sphi = (s1 - s3) / (s1 + s3)
        rows.append({
            "axial_strain": ea, "q_over_p": (s1 - s3) / mean, "volumetric_strain": ev,
            "phi_mobilised_deg": math.degrees(math.asin(max(-1.0, min(1.0, sphi)))),
            "mean_stress": mean,
        })
    peak = max(rows, key=lambda r: r["phi_mobilised_deg"])
    tail = rows[-len(rows) // 5 :]
    crit = sum(r["phi_mobilised_deg"] for r in tail) / len(tail)
    err = max(abs(r["mean_stress"] / p - 1) for r in rows[len(rows) // 10 :])
    iso = stresses[0]["mean"], stresses[1]["mean"]
    size = grids[1]["size"]
    summary = {
        "isotropic_mean_after_compression": iso[0], "isotropic_mean_after_relaxation": iso[1],
        "solid_fraction_at_p": vols / (size[0] * size[1] * size[2]),
        "peak_phi_deg": peak["phi_mobilised_deg"], "peak_axial_strain": peak["axial_strain"],
        "critical_phi_deg": crit, "final_volumetric_strain": rows[-1]["volumetric_strain"],
        "largest_mean_stress_error": err, "steps": n, "gain": gain, "mu0": o["mu0"],
        "particles": npart, "p": p,
    }
    return rows, summary


def main():
    argv = sys.argv[1:]
    if "--chart-only" in argv:
        # Draw the chart again from doc/data/triaxial<tag>.csv (no run).
        draw(arg([a for a in argv if a != "--chart-only"], "--tag", ""))
        return
    opts = {k: arg(argv, "--" + k, v) for k, v in OPTIONS.items()}
    tag = arg(argv, "--tag", "")
    no_other_options(argv)
    exe = run_table.trubal_binary()
    work = os.path.join(ROOT, "target", "triaxial")
    os.makedirs(work, exist_ok=True)
    rows, summary = run(exe, opts, work)
    with open(os.path.join(ROOT, "doc", "data", f"triaxial{tag}.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    provenance.record(os.path.join(ROOT, "doc", "data", f"triaxial{tag}.csv"), exe)
    print(json.dumps(summary, indent=1))
    with open(os.path.join(ROOT, "doc", "data", f"triaxial{tag}_summary.json"), "w") as fh:
        json.dump(summary, fh, indent=1)
    provenance.record(os.path.join(ROOT, "doc", "data", f"triaxial{tag}_summary.json"), exe)
    draw(tag)


def draw(tag):
    """The chart doc/img/triaxial<tag>.png from doc/data/triaxial<tag>.csv and _summary.json."""
    with open(os.path.join(ROOT, "doc", "data", f"triaxial{tag}.csv")) as fh:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)]
    with open(os.path.join(ROOT, "doc", "data", f"triaxial{tag}_summary.json")) as fh:
        o = json.load(fh)
    run_table.chart(
        os.path.join(ROOT, "doc", "img", f"triaxial{tag}.png"),
        f"Triaxial test at constant mean stress {o['p'] / 1e3:g} kPa: {o['particles']} spheres, μ = 0.5"
        f" (prepared with μ = {o['mu0']:g})",
        [("q/p", [(100 * r["axial_strain"], r["q_over_p"]) for r in rows]),
         ("10 × volumetric strain (dilation < 0)", [(100 * r["axial_strain"], 10 * r["volumetric_strain"]) for r in rows])],
        "axial strain [%]",
        "q/p,  10 × volumetric strain",
    )

if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
