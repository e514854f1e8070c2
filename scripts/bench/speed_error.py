#!/usr/bin/env python3
"""Speed against error (issue 9, item 4): how much accuracy each saving costs.

    python3 scripts/bench/speed_error.py [--work DIR] [--out doc/data] [--skip-binary]

Three studies, each written to OUT/speed_error_*.csv and drawn to OUT/speed_error_*.png:

1. `binary`: the FRAction tables of tests/it/timestep_study.rs (Hertz binary impact: restitution,
   contact time and peak force against the closed forms; JKR sticking threshold against
   v_s = sqrt(2 W_p/m*)), run with `cargo test --release --test it timestep_study:: -- --ignored
   --nocapture`. The run time of a binary impact is proportional to 1/FRAction.
2. `impact`: scripts/bench/speed_error_impact.tru, a 274-sphere adhesive BCC agglomerate
   (JKR, gamma = 0.5 J/m^2) hitting a wall at 0.5 m/s, for 64 us of simulated time, at
   FRAction 0.05 ... 1 with the full Mindlin-Deresiewicz law (MD) and with Mindlin no-slip +
   Coulomb (NOSLIP). The break-up is chaotic (round-off decides which bonds break), so each
   setting is an ensemble of --ensemble runs (velocity changed by k x --perturb); the error is the
   ensemble mean damage ratio minus that of MD at FRAction 0.05, to be read against the
   ensemble spread; the cost is the CPU time of the Cycle (TRUBAL_TIMING, one thread).
3. `liquid`: the same agglomerate without adhesion, moist (LIQuid 0.1 0.025 0 0.01), hitting
   the wall at 3 m/s, with the three bridge shape models (FIT, TOROIDAL, LAPLACE) at FRAction
   0.05 and 0.2: bridge damage ratio and CPU time; the reference is LAPLACE (the exact
   Laplace-Young bridge) at FRAction 0.05.

Python 3 standard library only (the charts: `trubal chart`, through scripts/run_table.py).
"""

import argparse
import csv
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import run_table  # noqa: E402  (chart)

SCENE = os.path.join(HERE, "speed_error_impact.tru")
T_SIM = 64e-6  # simulated time of every impact run (s)
FRACTIONS = [0.025, 0.05, 0.1, 0.2, 0.5, 1.0]


def trubal_exe():
    exe = os.path.join(ROOT, "target", "release", "trubal")
    if not os.path.exists(exe):
        subprocess.run(["cargo", "build", "--release"], cwd=ROOT, check=True)
    return exe


def run_scene(exe, work, sets):
    """Runs the scene; returns (last bonds JSON object, dt, cycle CPU seconds) or None."""
    args = [exe, SCENE, "--json", "--threads", "1"]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    env = dict(os.environ, TRUBAL_TIMING="1")
    p = subprocess.run(args, cwd=work, capture_output=True, text=True, env=env)
    bonds, dt = None, None
    for line in p.stdout.splitlines():
        if not line.startswith("{"):
            continue
        o = json.loads(line)
        if o.get("print") == "bonds":
            bonds = o
        if o.get("print") == "info" and "dt" in o:
            dt = o["dt"]
    cpu = sum(float(m) for m in re.findall(r"cycle_cpu_s=([0-9.eE+-]+)", p.stderr))
    if p.returncode != 0 or bonds is None:
        sys.stderr.write(f"run failed ({' '.join(args)}):\n{p.stdout[-800:]}\n{p.stderr[-800:]}\n")
        return None
    return bonds, dt, cpu


def timed_run(exe, work, sets):
    """Probes dt with 0 cycles, then runs for T_SIM of simulated time."""
    probe = run_scene(exe, work, dict(sets, n=0))
    if probe is None or not probe[1]:
        return None
    n = max(1, round(T_SIM / probe[1]))
    r = run_scene(exe, work, dict(sets, n=n))
    if r is None:
        return None
    bonds, dt, cpu = r
    return {"cycles": n, "dt": dt, "cpu_s": cpu, "damage_ratio": bonds["damage_ratio"],
            "kind": bonds.get("kind", ""), "initial": bonds["initial"], "broken": bonds["broken"]}


def read_csv(path):
    """Rows of a CSV written by write_csv, numbers as floats ("" and text kept)."""
    if not os.path.exists(path):
        return []
    out = []
    with open(path) as f:
        for r in csv.DictReader(f):
            row = {}
            for k, v in r.items():
                try:
                    row[k] = float(v)
                except ValueError:
                    row[k] = v
            out.append(row)
    return out


def write_csv(path, rows):
    keys = list(rows[0].keys())
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    print("wrote", path)


def binary_study(out):
    p = subprocess.run(["cargo", "test", "--release", "--test", "timestep_study", "--",
                        "--ignored", "--nocapture"], cwd=ROOT, capture_output=True, text=True)
    rows = []
    for line in p.stdout.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and re.match(r"^[0-9.]+$", cells[0]):
            rows.append({"test": "hertz", "fraction": float(cells[0]), "steps_per_contact": float(cells[1]),
                         "restitution_err_pct": 100 * float(cells[2]),
                         "contact_time_err_pct": float(cells[3].rstrip(" %")),
                         "peak_force_err_pct": float(cells[4].rstrip(" %")), "jkr_threshold_err_pct": ""})
        elif len(cells) == 2 and re.match(r"^[0-9.]+$", cells[0]):
            rows.append({"test": "jkr", "fraction": float(cells[0]), "steps_per_contact": "",
                         "restitution_err_pct": "", "contact_time_err_pct": "", "peak_force_err_pct": "",
                         "jkr_threshold_err_pct": float(cells[1].rstrip(" %"))})
    if not rows:
        sys.exit("no tables in the output of timestep_study:\n" + p.stdout[-2000:] + p.stderr[-2000:])
    write_csv(os.path.join(out, "speed_error_binary.csv"), rows)
    return rows


def charts(a, binary, agg, wet):
    # ---- charts --------------------------------------------------------------------------
    series = []
    if binary:
        h = [r for r in binary if r["test"] == "hertz"]
        series += [
            ("restitution", [(0.2 / r["fraction"], abs(r["restitution_err_pct"])) for r in h]),
            ("contact time", [(0.2 / r["fraction"], abs(r["contact_time_err_pct"])) for r in h]),
            ("peak force", [(0.2 / r["fraction"], abs(r["peak_force_err_pct"])) for r in h]),
            ("JKR sticking velocity", [(0.2 / r["fraction"], abs(r["jkr_threshold_err_pct"]))
                                for r in binary if r["test"] == "jkr"]),
        ]
    md = [r for r in agg if r["tangential"] == "md"]
    ref = min(md, key=lambda r: r["fraction"]) if md else None
    base = next((r["cpu_s"] for r in md if r["fraction"] == 0.2), None)
    if base:
        series.append(("agglomerate: damage ratio, mean", [(r["cpu_s"] / base, 100 * abs(r["damage_err"]))
                                                   for r in md if r is not ref]))
        series.append(("agglomerate: damage ratio, ensemble SD", [(r["cpu_s"] / base, 100 * r["damage_sd"]) for r in md]))
    run_table.chart(os.path.join(a.out, "speed_error_fraction.png"),
                    "Error against run time: FRAction 1 … 0.05", series,
                    "run time / run time at FRAction 0.2", "|error| [%]", logx=True)
    run_table.chart(os.path.join(a.out, "speed_error_tangential.png"),
                    "Agglomerate impact: mean damage ratio against CPU time",
                    [(lab.upper(), [(r["cpu_s"], r["damage_mean"]) for r in agg if r["tangential"] == lab])
                     for lab in ("md", "noslip")],
                    "Cycle CPU time per run [s]", "damage ratio (mean of %d)" % a.ensemble, logx=True)
    if wet:
        run_table.chart(os.path.join(a.out, "speed_error_liquid.png"),
                        "Moist impact: bridge damage ratio against CPU time",
                        [(m.upper(), [(r["cpu_s"], r["damage_ratio"]) for r in wet if r["bridge"] == m])
                         for m in ("fit", "toroidal", "laplace")],
                        "Cycle CPU time [s]", "bridge damage ratio", logx=True)



def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", default=os.path.join(ROOT, "target", "speed_error"))
    ap.add_argument("--out", default=os.path.join(ROOT, "doc", "data"))
    ap.add_argument("--skip-binary", action="store_true")
    ap.add_argument("--skip-liquid", action="store_true")
    ap.add_argument("--ensemble", type=int, default=5)
    ap.add_argument("--perturb", type=float, default=2e-3,
                    help="relative change of the impact velocity between ensemble members")
    ap.add_argument("--charts-only", action="store_true", help="redraw the PNGs from the CSVs")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    exe = trubal_exe()

    if a.skip_binary or a.charts_only:
        binary = read_csv(os.path.join(a.out, "speed_error_binary.csv"))
    else:
        binary = binary_study(a.out)
    if a.charts_only:
        agg = read_csv(os.path.join(a.out, "speed_error_impact.csv"))
        wet = read_csv(os.path.join(a.out, "speed_error_liquid.csv"))
        charts(a, binary, agg, wet)
        return

    # ---- dry adhesive impact: FRAction x tangential law, ensembles -------------------------
    # The break-up of a perfect lattice is chaotic: round-off (a different step, a different
    # law) changes which bonds break. So every setting is run ENSEMBLE times with the impact
    # velocity changed by k x --perturb (relative; 2e-3: the damage ratio changes by ~0.001
    # per 0.2 % of velocity, Lian's D = log10(v/v0)), and means are compared.
    dry = []
    for tang in ("md", "noslip"):
        for f in FRACTIONS[1:]:
            for k in range(a.ensemble):
                r = timed_run(exe, a.work, {"frac": f, "tang": tang, "gamma": 0.5, "liquid": ";",
                                            "bridge": "toroidal", "v": 0.5 * (1 + a.perturb * k)})
                if r is None:
                    continue
                dry.append(dict({"tangential": tang, "fraction": f, "member": k}, **r))
                print("impact", tang, f, k, r["damage_ratio"], r["cpu_s"])
    write_csv(os.path.join(a.out, "speed_error_impact_runs.csv"), dry)
    agg = []
    for tang in ("md", "noslip"):
        for f in FRACTIONS[1:]:
            v = [r for r in dry if r["tangential"] == tang and r["fraction"] == f]
            if not v:
                continue
            d = [r["damage_ratio"] for r in v]
            m = sum(d) / len(d)
            sd = (sum((x - m) ** 2 for x in d) / max(1, len(d) - 1)) ** 0.5
            agg.append({"tangential": tang, "fraction": f, "runs": len(v), "damage_mean": m, "damage_sd": sd,
                        "damage_se": sd / len(d) ** 0.5, "cpu_s": sorted(r["cpu_s"] for r in v)[len(v) // 2]})
    ref = next(r for r in agg if r["tangential"] == "md" and r["fraction"] == FRACTIONS[1])
    for r in agg:
        r["damage_err"] = r["damage_mean"] - ref["damage_mean"]
        r["cost_rel"] = r["cpu_s"] / ref["cpu_s"]
    write_csv(os.path.join(a.out, "speed_error_impact.csv"), agg)

    # ---- moist impact: bridge model x FRAction -----------------------------------------
    wet = []
    for model in (() if a.skip_liquid else ("fit", "toroidal", "laplace")):
        for f in (0.05, 0.2):
            r = timed_run(exe, a.work, {"frac": f, "tang": "md", "gamma": 0, "liquid": "liquid 0.1 0.025 0 0.01",
                                        "bridge": model, "v": 3})
            if r is None:
                continue
            wet.append(dict({"bridge": model, "fraction": f}, **r))
            print("liquid", model, f, r)
    if wet:
        wref = next(r for r in wet if r["bridge"] == "laplace" and r["fraction"] == 0.05)
        for r in wet:
            r["damage_err"] = r["damage_ratio"] - wref["damage_ratio"]
            r["cost_rel"] = r["cpu_s"] / wref["cpu_s"]
        write_csv(os.path.join(a.out, "speed_error_liquid.csv"), wet)

    charts(a, binary, agg, wet)


if __name__ == "__main__":
    main()
