#!/usr/bin/env python3
"""The first table of doc/performance.md, from the harness's files (issue 50).

For S1 10k and 50k, S2 and the moist agglomerate: trubal's loop time on one thread, on two
threads of an idle machine, on two threads with a busy loop on the other core (against one
thread on the same busy machine), the peer's loop time, trubal's speed over the peer's at
the same step (paired medians over the repetitions) and at equal error: each code at the
largest step at which its own error on the scene's contact is within 1 %.

At equal error every figure is measured: both codes run the same simulated time, each at
its own step. S1 10k: scripts/bench/equal_error.py (equal_error_speed.tsv; the restitution
ladder). S2 and moist: scripts/bench/equal_error_agg_speed.py (equal_error_agg_speed.tsv; the
steps from equal_error_agg.py's binary impacts). S1 50k at equal error is derived: the
measured 10k figure scaled by the two sizes' ratios at equal step.

    python3 scripts/bench/first_table.py RESULTS.tsv [--bench-dir doc/data/bench]

Prints the markdown table. scripts/bench/first_table.sh runs everything and then this.
"""
import argparse
import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import summarize  # noqa: E402

PEER = {"s1": "liggghts", "s2": "lammps", "moist": "liggghts"}
PEER_NAME = {"liggghts": "LIGGGHTS", "lammps": "LAMMPS"}
NAME = {("s1", "10000"): "S1 10k (5000 steps)", ("s1", "50000"): "S1 50k (3000 steps)",
        ("s2", "4062"): "S2 JKR agglomerate (4000 steps)",
        ("moist", "4062"): "moist agglomerate (4000 steps)"}


def s1_equal_error(bench):
    """LIGGGHTS / trubal loop time at equal error on S1 10k, paired by repetition, and the
    two FRActions; None without the file."""
    path = os.path.join(bench, "equal_error_speed.tsv")
    if not os.path.exists(path):
        return None
    t, frac = {}, {}
    for ln in open(path):
        if ln.startswith("#") or ln.startswith("rep"):
            continue
        rep, code, f, _steps, loop = ln.split("\t")
        t.setdefault(code, {})[rep] = float(loop)
        frac[code] = float(f)
    r = summarize.paired(t["liggghts"], t["trubal"])
    return r, frac


def agg_equal_error(bench):
    """{case: (paired median [min, max, n] of peer / trubal loop time, trubal's FRAction, the
    peer's FRAction)} from equal_error_agg_speed.tsv; {} without the file."""
    path = os.path.join(bench, "equal_error_agg_speed.tsv")
    if not os.path.exists(path):
        return {}
    t, p, fr = {}, {}, {}
    for ln in open(path):
        if ln.startswith("#") or ln.startswith("rep\t"):
            continue
        rep, case, ft, _st, tt, _peer, fp, _sp, tp = ln.rstrip("\n").split("\t")
        t.setdefault(case, {})[rep] = float(tt)
        p.setdefault(case, {})[rep] = float(tp)
        fr[case] = (float(ft), float(fp))
    return {c: (summarize.paired(p[c], t[c]),) + fr[c] for c in t}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("results")
    ap.add_argument("--bench-dir", default=os.path.join(ROOT, "doc", "data", "bench"))
    a = ap.parse_args()
    rows = summarize.load(a.results)
    med = summarize.summarize(rows)
    reps = summarize.per_rep(rows)
    eq = s1_equal_error(a.bench_dir)
    agg = agg_equal_error(a.bench_dir)

    def loop(scene, code, n, par, steps):
        v = med.get((scene, code, n, par, steps))
        return v["loop"] if v else None

    def ratio(scene, n, steps, a_code, a_par, b_code, b_par):
        """Paired median of b's loop / a's loop (a's speed over b's)."""
        ra = reps.get((scene, a_code, n, a_par, steps))
        rb = reps.get((scene, b_code, n, b_par, steps))
        return summarize.paired(rb, ra) if ra and rb else None

    def fmt(r):
        return "—" if r is None else f"{r[0]:.2f} × ({r[1]:.2f}–{r[2]:.2f}, n = {r[3]})"

    print("| scene | trubal, 1 thread | 2 threads, idle machine (over 1) | 2 threads, a busy loop on "
          "the other core (over 1 thread on the same busy machine) | peer, 1 rank | trubal over the "
          "peer, equal step | trubal over the peer, equal error (1 %) |")
    print("|---|---|---|---|---|---|---|")
    keys = sorted({(k[0], k[2], k[4]) for k in med if k[1] == "trubal" and k[0] in PEER},
                  key=lambda k: (["s1", "s2", "moist"].index(k[0]), int(k[1])))
    s1_10k_step = None
    for scene, n, steps in keys:
        peer = PEER[scene]
        t1 = loop(scene, "trubal", n, "t1", steps)
        p = loop(scene, peer, n, "np1", steps)
        if t1 is None or p is None:
            continue
        idle = ratio(scene, n, steps, "trubal", "t2", "trubal", "t1")
        busy = ratio(scene, n, steps, "trubal", "t2busy", "trubal", "t1busy")
        step = ratio(scene, n, steps, "trubal", "t1", peer, "np1")
        def agg_cell(case, what):
            r, ft, fp = agg[case]
            return (f"**{r[0]:.2f} ×** ({r[1]:.2f}–{r[2]:.2f}, n = {r[3]}; {what}: trubal at FRAction "
                    f"{ft:g}, {PEER_NAME[peer]} at {fp:g})")
        if scene == "s1" and n == "10000" and eq:
            r, f = eq
            equal = (f"**{r[0]:.1f} ×** ({r[1]:.1f}–{r[2]:.1f}, n = {r[3]}; restitution: trubal at "
                     f"FRAction {f['trubal']:g}, {PEER_NAME[peer]} at {f['liggghts']:g})")
        elif scene == "s1" and eq and step and s1_10k_step:
            equal = (f"≈ {eq[0][0] * step[0] / s1_10k_step[0]:.0f} × (derived: the 10k figure × "
                     f"{step[0]:.2f} / {s1_10k_step[0]:.2f}, the ratios at equal step)")
        elif scene == "s2" and "s2 rebound" in agg:
            equal = agg_cell("s2 rebound", "JKR rebound")
        elif scene == "moist" and "moist energy" in agg:
            equal = agg_cell("moist energy", "energy dissipated")
            if "moist rebound" in agg:
                equal += "; " + agg_cell("moist rebound", "rebound speed")
        else:
            equal = "not measured"
        if scene == "s1" and n == "10000":
            s1_10k_step = step
        print(f"| {NAME.get((scene, n), scene + ' ' + n)} | {t1:.2f} s | {fmt(idle)} | {fmt(busy)} | "
              f"{PEER_NAME[peer]} {p:.2f} s | **{fmt(step)}** | {equal} |")


if __name__ == "__main__":
    main()
