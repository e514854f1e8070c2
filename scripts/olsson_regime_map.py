#!/usr/bin/env python3
"""Olsson 2017's regime map (Fig. 4:7) from a run of scripts/sweeps/olsson_regime.sweep.

usage: olsson_regime_map.py SWEEP_DIR [--png doc/img/olsson_regime_map.png] [--csv doc/data/olsson_regime.csv]

Reads every finished run's output (SWEEP_DIR/runs/*/output.jsonl, the last printout) and
writes, per run: Olsson's total fragmentation (4000 - the largest DBSCAN fragment, particles
lost through the open work-space counted as fragmented), the number of fragments (DBSCAN
fragments besides the largest) and singles + binaries (Table 4:2's numbers in parentheses:
the particles in no fragment), the capture ratio and Delta (PRint BONds `delta`, his (67):
incident kinetic energy over the summed bond energy of the initial contacts). The PNG has
two panels: total fragmentation against impact velocity, ours against his Table 4:1, with
the regime borders 3, 20 and 50 %; and the regime map, liquid content against Delta, each
run coloured by its regime, with the borders interpolated linearly in Delta as he drew them,
and his border velocities (Table 4:1 interpolated in v^2) placed on our Delta axis (Delta is
proportional to v^2 for one agglomerate).
"""
import argparse
import csv
import glob
import json
import math
import os

N = 4000
LIQUIDS = ["dry", "0.01", "0.1", "1"]
# Table 4:1 (fragmented particles) and 4:2 (fragments, singles + binaries), olsson2017.md §4.
OLSSON_FRAG = {
    "dry": {0.5: 1, 1: 103, 1.5: 1092, 2: 1541, 2.5: 2603, 3: 2780},
    "0.01": {2: 8, 2.5: 16, 3: 124, 5.2: 986},
    "0.1": {2.5: 6, 3: 56, 5.2: 679},
    "1": {3: 2, 5.2: 259},
}
OLSSON_ZERO = {"dry": [], "0.01": [0.5, 1, 1.5], "0.1": [0.5, 1, 1.5, 2], "1": [0.5, 1, 1.5, 2, 2.5]}
OLSSON_FRAGMENTS = {
    "dry": {0.5: (0, 1), 1: (4, 23), 1.5: (27, 124), 2: (62, 203), 2.5: (85, 308), 3: (123, 431)},
    "0.01": {2: (0, 8), 2.5: (1, 13), 3: (11, 30), 5.2: (54, 138)},
    "0.1": {2.5: (1, 3), 3: (2, 13), 5.2: (29, 63)},
    "1": {3: (0, 2), 5.2: (17, 44)},
}
BORDERS = [3.0, 20.0, 50.0]
REGIME_NAMES = ["1 minor deformation", "2 minor fragmentation", "3 major fragmentation", "4 disintegration"]
COLOURS = ["#4c9be8", "#f2c14e", "#f08a4b", "#c0392b"]


def olsson_pct(liquid, v):
    if v in OLSSON_FRAG[liquid]:
        return 100.0 * OLSSON_FRAG[liquid][v] / N
    if v in OLSSON_ZERO[liquid]:
        return 0.0
    return None


def regime(pct):
    return sum(pct >= b for b in BORDERS)


def last(objs, kind):
    xs = [o for o in objs if o.get("print") == kind]
    return xs[-1] if xs else None


def read_runs(sweep):
    rows = []
    for out in sorted(glob.glob(os.path.join(sweep, "runs", "*", "output.jsonl"))):
        d = os.path.dirname(out)
        st = os.path.join(d, "status.json")
        if not os.path.exists(st) or json.load(open(st)).get("exit") != 0:
            continue
        objs = []
        for line in open(out):
            line = line.strip()
            if line.startswith("{"):
                try:
                    objs.append(json.loads(line))
                except json.JSONDecodeError:
                    pass
        c, b, info = last(objs, "clusters"), last(objs, "bonds"), last(objs, "info")
        name = os.path.basename(d)
        # The run's name (the `run` column of olsson_regime.csv): <liquid>_v<v>.
        liquid, v = name.rsplit("_v", 1)
        v = float(v)
        lost = info["lost"]
        frag = c["fragmentation"] + lost
        fragments = sorted(c["fragments"], reverse=True)
        rows.append({
            "liquid": liquid,
            "v": v,
            "fragmented": frag,
            "fragmented_pct": 100.0 * frag / N,
            "fragments": max(len(fragments) - 1, 0),
            # DBSCAN's noise (singles and binaries) and the particles lost through the sides.
            "singles_binaries": N - sum(fragments),
            "capture_pct": 100.0 * c["capture_ratio"],
            "largest": c["largest"],
            "delta": b["delta"],
            "damage_ratio": b["damage_ratio"],
            "net_damage": b["damage_ratio"] - b["new_ratio"],
            "wall_s": json.load(open(st)).get("wall_s"),
            "olsson_pct": olsson_pct(liquid, v),
        })
    rows.sort(key=lambda r: (LIQUIDS.index(r["liquid"]), r["v"]))
    return rows


def borders_in(xs, pcts):
    """Where the fragmentation crosses 3, 20, 50 % by linear interpolation in x (None: not
    crossed)."""
    out = []
    for b in BORDERS:
        hit = None
        for (x0, p0), (x1, p1) in zip(zip(xs, pcts), zip(xs[1:], pcts[1:])):
            if p0 < b <= p1:
                hit = x0 + (b - p0) * (x1 - x0) / (p1 - p0)
                break
        out.append(hit)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep")
    ap.add_argument("--png", default="doc/img/olsson_regime_map.png")
    ap.add_argument("--csv", default="doc/data/olsson_regime.csv")
    a = ap.parse_args()
    rows = read_runs(a.sweep)
    if not rows:
        raise SystemExit(f"no finished runs in {a.sweep}/runs")
    keys = list(rows[0].keys())
    os.makedirs(os.path.dirname(a.csv) or ".", exist_ok=True)
    with open(a.csv, "w", newline="") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (round(x, 4) if isinstance(x, float) else x) for k, x in r.items()})
    print(",".join(keys))
    for r in rows:
        print(",".join(str(round(r[k], 4) if isinstance(r[k], float) else r[k]) for k in keys))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.2))
    markers = {"dry": "o", "0.01": "s", "0.1": "^", "1": "D"}
    colours = {"dry": "#333333", "0.01": "#1f77b4", "0.1": "#2ca02c", "1": "#d62728"}
    for liq in LIQUIDS:
        ours = [r for r in rows if r["liquid"] == liq]
        label = "dry" if liq == "dry" else f"{liq} %"
        if ours:
            ax1.plot([r["v"] for r in ours], [r["fragmented_pct"] for r in ours], "-", marker=markers[liq],
                     color=colours[liq], label=f"trubal, {label}")
        vs = sorted(set(OLSSON_FRAG[liq]) | set(OLSSON_ZERO[liq]))
        ax1.plot(vs, [olsson_pct(liq, v) for v in vs], "--", marker=markers[liq], mfc="none",
                 color=colours[liq], alpha=0.7, label=f"Olsson Table 4:1, {label}")
    for b in BORDERS:
        ax1.axhline(b, color="grey", lw=0.8, ls=":")
        ax1.text(0.45, b * 1.08, f"{b:g} %", color="grey", fontsize=8)
    ax1.set_yscale("symlog", linthresh=1.0)
    ax1.set_xlabel("impact velocity (m/s)")
    ax1.set_ylabel("total fragmentation (% of 4000)")
    ax1.set_title("Total fragmentation: trubal (solid) vs Olsson 2017 Table 4:1 (dashed)")
    ax1.legend(fontsize=7, ncol=2)

    ypos = {liq: k for k, liq in enumerate(LIQUIDS)}
    for r in rows:
        ax2.scatter(r["delta"], ypos[r["liquid"]], s=90, color=COLOURS[regime(r["fragmented_pct"])],
                    edgecolor="black", zorder=3)
        ax2.annotate(f"{r['v']:g} m/s\n{r['fragmented_pct']:.1f} %", (r["delta"], ypos[r["liquid"]]),
                     textcoords="offset points", xytext=(0, 9), ha="center", fontsize=7)
    for liq in LIQUIDS:
        ours = [r for r in rows if r["liquid"] == liq]
        if len(ours) >= 2:
            xs = [r["delta"] for r in ours]
            ps = [r["fragmented_pct"] for r in ours]
            for b, x in zip(BORDERS, borders_in(xs, ps)):
                if x:
                    ax2.plot([x, x], [ypos[liq] - 0.3, ypos[liq] + 0.3], color="black", lw=2)
                    ax2.text(x, ypos[liq] - 0.42, f"{b:g}%", ha="center", fontsize=7)
            # Olsson's borders (Table 4:1 interpolated in v^2) on our Delta axis: Delta = k v^2.
            k = sum(r["delta"] / r["v"] ** 2 for r in ours) / len(ours)
            vs = sorted(set(OLSSON_FRAG[liq]) | set(OLSSON_ZERO[liq]))
            for b, x in zip(BORDERS, borders_in([v * v for v in vs], [olsson_pct(liq, v) for v in vs])):
                if x:
                    ax2.plot([k * x] * 2, [ypos[liq] - 0.3, ypos[liq] + 0.3], color="black", lw=1.2, ls="--")
    ax2.set_xscale("log")
    ax2.set_yticks(range(len(LIQUIDS)))
    ax2.set_yticklabels(["dry", "0.01 %", "0.1 %", "1 %"])
    ax2.set_ylim(-0.6, len(LIQUIDS) - 0.3)
    ax2.set_xlabel("Δ = incident kinetic energy / summed bond energy (Olsson (67))")
    ax2.set_ylabel("liquid content")
    ax2.set_title("Regime map (cf. Olsson Fig. 4:7): borders ours (solid), his (dashed)")
    from matplotlib.patches import Patch
    ax2.legend(handles=[Patch(color=c, label=n) for c, n in zip(COLOURS, REGIME_NAMES)], fontsize=7,
               loc="lower right")
    fig.tight_layout()
    os.makedirs(os.path.dirname(a.png) or ".", exist_ok=True)
    fig.savefig(a.png, dpi=110)
    print(f"wrote {a.png} and {a.csv}")


if __name__ == "__main__":
    main()
