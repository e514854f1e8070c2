#!/usr/bin/env python3
"""Reduced versions of the validation tables, checked in CI against reference figures
(issue 53 item 1; tests/it/tables.rs runs `--check CASE` for every case).

Each case runs the same command file (scripts/*.tru) and the same measures (run_table.py,
lun_shear.py, shang_shear.py, pasha_single.py) as its table, made small: fewer particles,
shorter runs. The reference figures are in doc/data/ci_tables.json, next to the tables' data:
for each measure the value of the reference sample (seed 0), the values of SAMPLES other
samples (other random seeds, or for the lattice and single-particle cases the impact speed
perturbed by k x 1e-6 relative) and the tolerance: 3 x their standard deviation (the measured
run-to-run scatter), and at least the case's floor. A change of the program that moves a
validated result by more than that scatter fails CI until the tables are run again and the
reference regenerated:

    python3 scripts/ci_tables.py --regenerate [--jobs N] [CASE ...]   (writes doc/data/ci_tables.json)
    python3 scripts/ci_tables.py --check [CASE ...]        (exit 1 if a measure is outside)
    python3 scripts/ci_tables.py --list

TRUBAL_BIN selects the binary (the CI test passes its own build).
Python 3 standard library only.
"""
import concurrent.futures
import json
import math
import os
import re
import shutil
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import lun_shear  # noqa: E402
import pasha_indent  # noqa: E402
import pasha_single  # noqa: E402
import provenance  # noqa: E402
import run_table  # noqa: E402
import shang_shear  # noqa: E402
import triaxial  # noqa: E402

REFERENCE = os.path.join(ROOT, "doc", "data", "ci_tables.json")
SAMPLES = 5


def reduce_deck(name, subs, work):
    """scripts/NAME with each (old, new) replaced; every `old` must occur exactly once, so
    that an edit of the table's command file shows here instead of silently not applying."""
    with open(os.path.join(HERE, name)) as fh:
        text = fh.read()
    for old, new in subs:
        n = len(re.findall(re.escape(old), text))
        if n != 1:
            raise SystemExit(f"{name}: `{old}` occurs {n} times (the reduction expects 1)")
        text = text.replace(old, new)
    path = os.path.join(work, "reduced_" + name)
    with open(path, "w") as fh:
        fh.write(text)
    return path


def run_deck(exe, deck, sets, work):
    """The JSON objects of a run of the command file `deck` with the --set values."""
    log = os.path.join(work, os.path.basename(deck) + ".log")
    args = {k: str(v) for k, v in sets.items()}
    rc, _ = run_table.trubal(exe, deck, args, work, log)
    if rc != 0:
        with open(log) as fh:
            raise SystemExit(f"{deck} failed (exit {rc}):\n{fh.read()[-3000:]}")
    return run_table.json_lines(log)


def table_measures(objs, run, keys):
    m = run_table.measures(objs, run)
    if m is None:
        raise SystemExit("no measures in the run's output")
    return {k: float(m[k]) for k in keys}


def lian6(exe, work, k):
    """Table 6.1 reduced: a BCC agglomerate of R_a = 300 um instead of 575 um, prepared by
    scripts/lian_ch6_prepare.tru, on the wall at 1 m/s, eta = 0.01 Pa s, 4 x 4000 cycles
    instead of 4 x 12500."""
    state = "lian6_r300.sav"
    if not os.path.exists(os.path.join(work, state)):
        run_deck(exe, os.path.join(HERE, "lian_ch6_prepare.tru"),
                 {"box": "1.6e-3", "nbox": "8000", "centre": "0.8e-3", "ra": "300e-6", "state": state}, work)
    wall = run_table.wall_height(exe, work, state)
    v = 1.0 * (1 + 1e-6 * k)
    objs = run_deck(exe, os.path.join(HERE, "lian_ch6_impact.tru"),
                    {"state": state, "wall": f"{wall:.8e}", "v": repr(v), "eta": "0.01", "frac": "0.4", "n": "4000"},
                    work)
    return table_measures(objs, {"v": v}, ["damage_ratio", "new_ratio", "e_viscous", "e_friction"])


def seed(k):
    """The `RGenerate SEed` of sample k: disjoint stretches of the one random stream, k x
    lun_shear.SEED_STRIDE numbers on (seeds a few numbers apart give the same assembly,
    shifted by a particle: each placement takes 3 numbers). The drivers' `--seed k` (lun_shear,
    shang_shear, pasha_indent, triaxial) discard the same seed(k) numbers themselves."""
    return lun_shear.SEED_STRIDE * k


def lian7(exe, work, k):
    """Table 7.1 reduced: two random agglomerates of 120 spheres (R_a 245 um) instead of 1000
    (500 um), prepared by scripts/lian_ch7_prepare.tru with random seed seed(k), colliding head-on
    at 2 m/s, eta = 0.01, Gamma = 0.025, 4 x 3000 cycles."""
    state = "lian_ch7.sav"
    deck = reduce_deck("lian_ch7_prepare.tru", [
        ("agglomerate 1 1.3e-3 2e-3 2e-3 500e-6", "agglomerate 1 1.7e-3 2e-3 2e-3 245e-6"),
        ("agglomerate 2 2.7e-3 2e-3 2e-3 500e-6", "agglomerate 2 2.3e-3 2e-3 2e-3 245e-6"),
        ("rgenerate 1000 1 1 1", f"rgenerate seed {seed(k)}\nrgenerate 120 1 1 1"),
        ("rgenerate 1000 1 1 2", "rgenerate 120 1 1 2"),
    ], work)
    run_deck(exe, deck, {"state": state}, work)
    run = {"v": "2", "theta": "0", "eta": "0.01", "gamma": "0.025", "n": "3000"}
    sets = run_table.derive("approach", exe, work, run, {})
    sets = {k2: sets[k2] for k2 in ("state", "dx", "v1x", "v1y", "v2x", "v2y", "n", "smin", "eta", "gamma", "v")}
    objs = run_deck(exe, os.path.join(HERE, "lian_ch7_collision.tru"), sets, work)
    return table_measures(objs, run, ["damage_ratio", "new_ratio", "e_viscous", "e_friction", "largest_pct"])


def olsson_prepare(exe, work, k, state="olsson_dry.sav"):
    """The reduced dry agglomerate of `olsson` (random seed k) saved as `state` in work."""
    deck = reduce_deck("olsson_prepare_dry.tru", [
        ("agglomerate 1 2.5e-3 2.5e-3 2.5e-3 520e-6", "agglomerate 1 2.5e-3 2.5e-3 2.5e-3 241e-6"),
        ("rgenerate 53 5 1 1", f"rgenerate seed {seed(k)}\nrgenerate 5 5 1 1"),
        ("rgenerate 82 4 1 1", "rgenerate 8 4 1 1"),
        ("rgenerate 346 3 1 1", "rgenerate 35 3 1 1"),
        ("rgenerate 953 2 1 1", "rgenerate 95 2 1 1"),
        ("rgenerate 2566 1 1 1", "rgenerate 257 1 1 1"),
        ("cycle 20000", "cycle 8000"),
        ("cycle 10000\nprint info", "cycle 4000\nprint info"),
        ("cgravity 1 0\ncycle 10000", "cgravity 1 0\ncycle 4000"),
    ], work)
    run_deck(exe, deck, {"state": state}, work)


def olsson_impact(exe, work, v="2", dashpot="trubal", law=""):
    """The impact of scripts/olsson_impact.tru on the prepared olsson_dry.sav (4 x 1500
    cycles); `law`: a `SET NORmal` line put after the restart (e.g. "set normal nguyen")."""
    sets = run_table.derive("olsson", exe, work, {"liquid": "dry", "v": v, "n": "1500", "dashpot": dashpot}, {})
    deck = os.path.join(HERE, "olsson_impact.tru")
    if law:
        deck = reduce_deck("olsson_impact.tru", [("set fragment 70e-6", "set fragment 70e-6\n" + law)], work)
    objs = run_deck(exe, deck, sets, work)
    return table_measures(objs, {"v": v}, ["fragmentation_pct", "capture_ratio", "damage_ratio"])


def olsson(exe, work, k):
    """Tables 4:1-4:2 reduced, dry: Olsson's size distribution, 400 particles (a tenth of each
    class) in R_a = 241 um instead of 4000 in 520 um, prepared by
    scripts/olsson_prepare_dry.tru with random seed seed(k), on the wall at 2 m/s for 4 x 1500
    cycles (scripts/olsson_impact.tru)."""
    olsson_prepare(exe, work, k)
    return olsson_impact(exe, work)


def lun(exe, work, k):
    """The Lun simple shear reduced: phi = 0.3, 250 smooth spheres, 40 strain units (the table:
    400 spheres, 60 units), random seed k (`--seed k`: seed(k) numbers discarded); the measures over Lun's theory."""
    r = lun_shear.run(exe, 0.3, 250, 40.0, work, seed=k)
    t = lun_shear.lun(r["phi"])
    return {f"{m}_over_lun": r[m] / t[m] for m in ("pxy", "pyy", "3T")}


def shang(exe, work, k):
    """Shang's cohesive shear reduced: phi = 0.45, 300 spheres, s = 12000 1/s, 20 strain units
    (the table: 480 spheres, 30 units), random seed k (seed(k) numbers discarded)."""
    shang_shear.SEED = k
    r = shang_shear.run(exe, 0.45, 300, 12000.0, 20.0, work)
    return {m: r[m] for m in ("pxy", "pyy", "3T")}


def pasha4(exe, work, k):
    """Pasha Ch. 4: one particle on the wall, his simplified linear law at 2 and 6 m/s and
    Thornton-Ning at 3 m/s (the speeds perturbed by k x 1e-6), FRAction 0.05: the restitution."""
    os.environ["TRUBAL_BIN"] = exe
    f = 1 + 1e-6 * k
    return {"e_pasha_2": pasha_single.run("pasha", 2.0 * f, 0.05),
            "e_pasha_6": pasha_single.run("pasha", 6.0 * f, 0.05),
            "e_tning_3": pasha_single.run("tning", 3.0 * f, 0.05)}


def pasha5(exe, work, k):
    """Pasha Ch. 5 reduced: scripts/pasha_indent.py's procedure (settle under 5 g, consolidate
    to 10 kPa at 20/s, unload at 1/s, indent at 20/s to h/r = 0.6) on a tiny bed: particles
    twice Pasha's size (Table 5.1 x 2, d_p = 2 mm), E/1000, MJKR EDEM with mu_r = 0.1, an
    18 mm die (9 d_p), a 12 mm bed of 346 particles (6 d_p), a 10 mm ball (5 d_p), settling
    for at most about 30,000 steps; random seed k (`--seed k`: seed(k) numbers discarded). The measures:
    the settled solids fraction, the compaction by the piston (1 - consolidated / settled
    height) and the hardness over h/r 0.35-0.6 (the table: 20 d_p beds of 12,800-30,300
    particles, balls of 13-22 d_p)."""
    os.environ["TRUBAL_BIN"] = exe
    os.environ["TRUBAL_PIPE"] = "1"
    pasha_indent.DATA = pasha_indent.WORK = work
    pasha_indent.CHARTS = False
    o = pasha_indent.main(["--scale", "2", "--die", "18", "--bed", "12", "--d", "10", "--law", "mjkr edem",
                           "--mur", "0.1", "--rate", "20", "--hold", "0", "--unload-rate", "1", "--gsettle", "5",
                           "--settle-cap", "30000", "--seed", str(k), "--tag", "_ci"])
    return {"solids_fraction": o["solids_fraction"], "compaction": 1 - o["consolidated_height"] / o["bed_height"],
            "hardness_kpa": o["hardness_plateau_kpa"]}


def triaxial_case(exe, work, k):
    """The triaxial test reduced: scripts/triaxial.tru with 200 spheres instead of 600-1000,
    the dense sample (friction 0 during the isotropic compression, 40,000 cycles instead of
    80,000, then 10,000 at rest instead of 20,000), compressed axially to 5 % instead of 25 %
    at 5/s, random seed k (seed(k) numbers discarded). The measures: the solid fraction at 100 kPa, the mobilised friction
    angle's peak and its mean over the last fifth, and the volumetric strain at the end."""
    deck = reduce_deck("triaxial.tru", [("cycle 20000 s0 $p", "cycle 10000 s0 $p")], work)
    _, s = triaxial.run(exe, {"np": 200, "mu0": 0.0, "gain": 5e-3, "strain": 0.05, "niso": 40000, "seed": k},
                        work, deck)
    return {"solid_fraction_at_p": s["solid_fraction_at_p"], "peak_phi_deg": s["peak_phi_deg"],
            "phi_last_fifth_deg": s["critical_phi_deg"], "final_volumetric_strain": s["final_volumetric_strain"]}


# case: (function, floor of the tolerance, relative)
CASES = {
    "lian6": (lian6, 0.01),
    "lian7": (lian7, 0.01),
    "olsson": (olsson, 0.01),
    "lun_shear": (lun, 0.01),
    "shang_shear": (shang, 0.01),
    "pasha4": (pasha4, 1e-4),
    "pasha5": (pasha5, 0.01),
    "triaxial": (triaxial_case, 0.01),
}


def sample(exe, name, k):
    work = tempfile.mkdtemp(prefix=f"ci_tables_{name}_{k}_")
    try:
        return CASES[name][0](exe, work, k)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def regenerate(exe, names, jobs=1):
    ref = {}
    if os.path.exists(REFERENCE):
        with open(REFERENCE) as fh:
            ref = json.load(fh)
    for name in names:
        # (--jobs N: the samples in N processes; the same figures, each sample is one run.)
        with concurrent.futures.ProcessPoolExecutor(max_workers=jobs) as pool:
            runs = list(pool.map(sample, [exe] * (SAMPLES + 1), [name] * (SAMPLES + 1), range(SAMPLES + 1)))
        floor = CASES[name][1]
        case = {"what": " ".join(CASES[name][0].__doc__.split()), "measures": {}}
        for m in runs[0]:
            vals = [r[m] for r in runs]
            sd = statistics.stdev(vals[1:] + vals[:1])
            tol = max(3 * sd, floor * abs(vals[0]), 1e-12)
            case["measures"][m] = {"value": vals[0], "samples": vals[1:], "scatter_sd": sd, "tolerance": tol}
            print(f"{name} {m}: {vals[0]:.6g}, samples {', '.join(f'{v:.4g}' for v in vals[1:])}; "
                  f"sd {sd:.3g}, tolerance {tol:.3g}", flush=True)
        case.update(provenance.stamp(exe))
        ref[name] = case
        with open(REFERENCE, "w") as fh:
            json.dump(ref, fh, indent=1)
            fh.write("\n")


def check(exe, names):
    with open(REFERENCE) as fh:
        ref = json.load(fh)
    bad = []
    for name in names:
        if name not in ref:
            bad.append(f"{name}: no reference in {REFERENCE}")
            continue
        got = sample(exe, name, 0)
        for m, r in ref[name]["measures"].items():
            d = got[m] - r["value"]
            ok = abs(d) <= r["tolerance"]
            print(f"{name} {m}: {got[m]:.6g}, reference {r['value']:.6g} ± {r['tolerance']:.3g} "
                  f"({'ok' if ok else 'OUTSIDE'})", flush=True)
            if not ok:
                bad.append(f"{name} {m}: {got[m]:.6g} against the reference {r['value']:.6g} ± {r['tolerance']:.3g} "
                           f"(made by {r.get('git', ref[name].get('git'))} on {ref[name].get('date')})")
    if bad:
        print("\n".join(["MOVED (a validated result changed: run the tables again, then "
                         "`python3 scripts/ci_tables.py --regenerate`; doc/validation.md):"] + bad))
        sys.exit(1)


def main():
    argv = sys.argv[1:]
    names = [a for a in argv if not a.startswith("--") and not a.isdigit()] or list(CASES)
    for n in names:
        if n not in CASES:
            raise SystemExit(f"unknown case {n}; cases: {', '.join(CASES)}")
    if "--list" in argv:
        for n in names:
            print(f"{n}: {' '.join(CASES[n][0].__doc__.split())}")
        return
    exe = run_table.trubal_binary()
    if "--regenerate" in argv:
        jobs = int(argv[argv.index("--jobs") + 1]) if "--jobs" in argv else 1
        regenerate(exe, names, jobs)
    elif "--check" in argv:
        check(exe, names)
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
