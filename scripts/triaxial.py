#!/usr/bin/env python3
"""Isotropic compression and a constant-mean-stress triaxial test in the periodic cell
(issue 35, item 3): runs scripts/triaxial.tru, writes doc/data/triaxial.csv (axial strain,
deviator q/p, volumetric strain, mobilised friction angle) and doc/img/triaxial.png, and
prints the peak and critical-state friction angles and the servo's error.

usage: scripts/triaxial.py [--chart-only] [--np N] [--p PA] [--rate 1/S] [--strain AXIAL] [--mu0 MU] [--seed K] [--tag T] [--gain G]
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
from lun_shear import option as arg  # noqa: E402

R_MEAN = 1.1e-4
E, NU, RHO = 1e9, 0.3, 2600.0


def dt():
    g = E / (2 * (1 + NU))
    return 0.2 * math.pi * 1e-4 * math.sqrt(RHO / g) / (0.1631 * NU + 0.8766)


def main():
    argv = sys.argv[1:]
    if "--chart-only" in argv:
        # Draw the chart again from doc/data/triaxial<tag>.csv (no run).
        draw(arg([a for a in argv if a != "--chart-only"], "--tag", ""))
        return
    npart = arg(argv, "--np", 600)
    p = arg(argv, "--p", 1e5)
    rate = arg(argv, "--rate", 5.0)
    axial = arg(argv, "--strain", 0.25)
    mu0 = arg(argv, "--mu0", 0.5)
    seed = arg(argv, "--seed", 0)
    tag = arg(argv, "--tag", "")
    gain = arg(argv, "--gain", 5e-3)
    n = int(axial / (rate * dt()))
    vols = sum(math.pi * 4 / 3 * rr ** 3 for rr in [1e-4] * (npart // 2) + [1.2e-4] * (npart // 2))
    sets = {"l": (vols / 0.2) ** (1 / 3), "np": npart, "half": npart // 2, "p": p, "rate": rate, "n": n, "niso": 80000, "h": max(1, n // 300), "mu0": mu0,
            "seed": seed, "g": gain}
    exe = run_table.trubal_binary()
    work = os.path.join(ROOT, "target", "triaxial")
    os.makedirs(work, exist_ok=True)
    args = [exe, "--json", os.path.join(HERE, "triaxial.tru")]
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
    with open(os.path.join(ROOT, "doc", "data", f"triaxial{tag}.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    provenance.record(os.path.join(ROOT, "doc", "data", f"triaxial{tag}.csv"), run_table.trubal_binary())
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
        "largest_mean_stress_error": err, "steps": n, "gain": gain, "mu0": mu0,
        "particles": npart, "p": p,
    }
    print(json.dumps(summary, indent=1))
    with open(os.path.join(ROOT, "doc", "data", f"triaxial{tag}_summary.json"), "w") as fh:
        json.dump(summary, fh, indent=1)
    provenance.record(os.path.join(ROOT, "doc", "data", f"triaxial{tag}_summary.json"), run_table.trubal_binary())
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
    main()
