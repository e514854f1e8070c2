#!/usr/bin/env python3
"""Olsson 2017's regime map (Fig. 4:7) from a run of scripts/sweeps/olsson_regime.sweep.

usage: olsson_regime_map.py SWEEP_DIR [--chart-only] [--table] [--png doc/img/olsson_regime_map.png] [--csv doc/data/olsson_regime.csv]

Reads every finished run's output (SWEEP_DIR/runs/*/output.jsonl, the last printout) and
writes, per run: Olsson's total fragmentation (4000 - the largest DBSCAN fragment, particles
lost through the open work-space counted as fragmented), the number of fragments (DBSCAN
fragments besides the largest) and singles + binaries (Table 4:2's numbers in parentheses:
the particles in no fragment), the capture ratio and Delta (PRint BONds `delta`, his (67):
incident kinetic energy over the summed bond energy of the initial contacts). Two charts
(`trubal chart`): total fragmentation against impact velocity, ours against his Table 4:1,
with the regime borders 3, 20 and 50 % (PNG_fragmentation.png); and the regime map (PNG):
fragmentation against Delta (log), one line per liquid content, the borders as grey lines,
his Table 4:1 placed on our Delta axis (Delta is proportional to v^2 for one agglomerate).
--chart-only draws both again from the CSV (SWEEP_DIR is then not read). --table prints
doc/validation.md's results table and regime borders from the CSV (SWEEP_DIR not read).
The CSV's provenance file names the sweep's runs (those finished, those missing, threads).
"""
import argparse
import csv
import glob
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import provenance  # noqa: E402
import run_table as rt  # noqa: E402

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
        objs = rt.json_lines(out)
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


def borders_in(vs, pcts):
    """The velocities at which the fragmentation crosses 3, 20, 50 %, interpolated linearly in
    v^2 (in Delta, as Olsson drew Fig. 4:7: Delta is proportional to v^2 for one agglomerate)
    between the velocities run (None: not crossed)."""
    out = []
    for b in BORDERS:
        hit = None
        for (v0, p0), (v1, p1) in zip(zip(vs, pcts), zip(vs[1:], pcts[1:])):
            if p0 < b <= p1:
                hit = math.sqrt(v0 * v0 + (b - p0) * (v1 * v1 - v0 * v0) / (p1 - p0))
                break
        out.append(hit)
    return out


def olsson_cells(liquid, v):
    """Olsson's Table 4:1 (count (%)) and 4:2 (fragments (singles + binaries)) cells."""
    if v in OLSSON_FRAG[liquid]:
        n = OLSSON_FRAG[liquid][v]
        f, s = OLSSON_FRAGMENTS[liquid][v]
        return f"{n} ({100.0 * n / N:.2f})", f"{f} ({s})"
    if v in OLSSON_ZERO[liquid]:
        return "0 (0.00)", "0 (0)"
    return "– (not run)", "–"


def outside(hit, border, vs, pcts):
    """A border's cell: the velocity, or the side of the velocities run it lies on ("< 3":
    the slowest run is already beyond it; "> 5.2": the fastest is not yet; "–": no runs)."""
    if hit is not None:
        return f"{hit:.2f}"
    if not vs:
        return "–"
    return f"< {vs[0]:g}" if pcts[0] >= border else f"> {vs[-1]:g}"


def print_table(rows):
    """doc/validation.md's results table and regime borders, from the CSV's rows."""
    print("| liquid | v (m/s) | fragmented (%) | Olsson (Table 4:1) | regime ours / his "
          "| fragments (singles + binaries) | Olsson (Table 4:2) | largest cluster | capture % "
          "| D_r | net D_r − n_r | Δ | wall (s) |")
    print("|---" * 13 + "|")
    for r in rows:
        v = r["v"]
        his, his2 = olsson_cells(r["liquid"], v)
        p = olsson_pct(r["liquid"], v)
        print(f"| {r['liquid']} | {v:g} | {int(r['fragmented'])} ({r['fragmented_pct']:.2f}) | {his} "
              f"| {regime(r['fragmented_pct']) + 1} / {'–' if p is None else regime(p) + 1} "
              f"| {int(r['fragments'])} ({int(r['singles_binaries'])}) | {his2} | {int(r['largest'])} "
              f"| {r['capture_pct']:.1f} | {r['damage_ratio']:.3f} | {r['net_damage']:.3f} "
              f"| {r['delta']:.3g} | {r['wall_s']:.0f} |")
    print()
    print("| | 3 % | 20 % | 50 % |")
    print("|---|---|---|---|")
    for liq in LIQUIDS:
        ours = [r for r in rows if r["liquid"] == liq]
        mine = borders_in([r["v"] for r in ours], [r["fragmented_pct"] for r in ours])
        vs = sorted(set(OLSSON_FRAG[liq]) | set(OLSSON_ZERO[liq]))
        his = borders_in(vs, [olsson_pct(liq, v) for v in vs])
        ours_v, ours_p = [r["v"] for r in ours], [r["fragmented_pct"] for r in ours]
        cells = []
        for b, m, h in zip(BORDERS, mine, his):
            if m is None and h is None and max(ours_p + [0.0]) < b:
                cells.append("–")
            else:
                cells.append(f"{outside(m, b, ours_v, ours_p)} / "
                             f"{outside(h, b, vs, [olsson_pct(liq, v) for v in vs])} m/s")
        name = "dry" if liq == "dry" else f"{liq} %"
        print(f"| {name}, ours / Olsson | " + " | ".join(cells) + " |")


def sweep_runs(sweep, rows):
    """What the provenance file says of the sweep: its runs finished and missing, threads."""
    try:
        with open(os.path.join(sweep, "sweep.json")) as fh:
            m = json.load(fh)
    except (OSError, ValueError):
        return {"runs": len(rows)}
    done = {f"{r['liquid']}_v{r['v']:g}" for r in rows}
    names = [r["name"] for r in m.get("runs", [])]
    return {"runs": len(rows), "of_runs": len(names), "missing": [n for n in names if n not in done],
            "threads_per_run": m.get("threads"), "sets": m.get("sets")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep")
    ap.add_argument("--png", default="doc/img/olsson_regime_map.png")
    ap.add_argument("--csv", default="doc/data/olsson_regime.csv")
    ap.add_argument("--chart-only", action="store_true", help="draw the charts again from the CSV")
    ap.add_argument("--table", action="store_true", help="print the doc's tables from the CSV")
    a = ap.parse_args()
    if a.chart_only or a.table:
        with open(a.csv) as fh:
            rows = [{k: (v if k == "liquid" else float(v) if v else 0.0) for k, v in r.items()}
                    for r in csv.DictReader(fh)]
        if a.table:
            print_table(rows)
        else:
            draw(rows, a.png)
        return
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
    provenance.record(a.csv, rt.trubal_binary(), sweep=a.sweep, **sweep_runs(a.sweep, rows))
    print(",".join(keys))
    for r in rows:
        print(",".join(str(round(r[k], 4) if isinstance(r[k], float) else r[k]) for k in keys))

    draw(rows, a.png)


def draw(rows, png):
    """The two charts: fragmentation against v (PNG_fragmentation.png) and against Delta (PNG),
    ours solid, Olsson's Table 4:1 dashed, the regime borders 3, 20, 50 % as grey lines."""
    names = {"dry": "dry", "0.01": "0.01 % liquid", "0.1": "0.1 % liquid", "1": "1 % liquid"}
    keys = [names[liq] for liq in LIQUIDS]
    borders = dict(hlines=BORDERS, hline_label="regime borders 3, 20, 50 %")
    series, refs, series_d, refs_d = [], [], [], []
    for liq in LIQUIDS:
        ours = [r for r in rows if r["liquid"] == liq]
        vs = sorted(set(OLSSON_FRAG[liq]) | set(OLSSON_ZERO[liq]))
        series.append((names[liq], [(r["v"], r["fragmented_pct"]) for r in ours]))
        refs.append((names[liq], [(v, olsson_pct(liq, v)) for v in vs]))
        # Olsson's points placed on our Delta axis: Delta = k v^2 for one agglomerate.
        ours = [r for r in ours if r["delta"] > 0]
        if ours:
            kk = sum(r["delta"] / r["v"] ** 2 for r in ours) / len(ours)
            series_d.append((names[liq], [(r["delta"], r["fragmented_pct"]) for r in ours]))
            refs_d.append((names[liq], [(kk * v * v, olsson_pct(liq, v)) for v in vs]))
    rt.chart(png.replace(".png", "_fragmentation.png"), "Total fragmentation against impact velocity",
             series, "impact velocity v [m/s]", "fragmentation [%]", refs=refs, ours="trubal",
             ref="Olsson (2017)", keys=keys, **borders)
    rt.chart(png, "Regime map (cf. Olsson Fig. 4:7): fragmentation against Δ (Olsson's v at our Δ/v²)", series_d,
             "Δ = incident kinetic energy / bond energy (Olsson (67))", "fragmentation [%]", logx=True,
             refs=refs_d, ours="trubal", ref="Olsson (2017)", keys=keys, **borders)

if __name__ == "__main__":
    main()
