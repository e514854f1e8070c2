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
the regime borders 3, 20 and 50 % (PNG_fragmentation.png); and the regime map (PNG), liquid content against Delta, each
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
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
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

    # The PNGs with run_table.py's small PNG writer (no plotting library on this machine).

    names = {"dry": "DRY", "0.01": "0.01 %", "0.1": "0.1 %", "1": "1 %"}
    series, refs = [], []
    for liq in LIQUIDS:
        ours = [(r["v"], r["fragmented_pct"]) for r in rows if r["liquid"] == liq]
        if ours:
            series.append((names[liq], ours))
            vs = sorted(set(OLSSON_FRAG[liq]) | set(OLSSON_ZERO[liq]))
            refs.append((f"OLSSON {names[liq]}", [(v, olsson_pct(liq, v)) for v in vs]))
    rt.chart(a.png.replace(".png", "_fragmentation.png"),
             "TOTAL FRAGMENTATION (%): TRUBAL (SOLID), OLSSON TABLE 4:1 (DASHED); BORDERS 3, 20, 50 %",
             series, "V (M/S)", "%", refs=refs, cap=False)

    # The regime map: liquid content (rows) against log10 Delta; each run a box coloured by
    # its regime; our borders (interpolated in Delta) as tall black ticks, Olsson's (Table
    # 4:1 interpolated in v^2, placed at our Delta = k v^2) as grey ones.
    W, H, L, R, T, B = 1000, 520, 110, 250, 60, 80
    cv = rt.Canvas(W, H)
    ds = [r["delta"] for r in rows if r["delta"] > 0]
    lo, hi = math.floor(math.log10(min(ds))) - 0.2, math.ceil(math.log10(max(ds))) + 0.2
    X = lambda d: round(L + (math.log10(d) - lo) / (hi - lo) * (W - L - R))
    Y = lambda k: round(T + (k + 0.5) * (H - T - B) / len(LIQUIDS))
    regime_rgb = [(76, 155, 232), (242, 193, 78), (240, 138, 75), (192, 57, 43)]
    cv.line(L, H - B, W - R, H - B, (0, 0, 0))
    cv.line(L, T, L, H - B, (0, 0, 0))
    for e in range(int(math.ceil(lo)), int(math.floor(hi)) + 1):
        x = X(10.0**e)
        cv.line(x, T, x, H - B + 5, (200, 200, 200))
        cv.text(x - 12, H - B + 10, f"1E{e}")
    cv.text(L, 8, "REGIME MAP (CF. OLSSON FIG. 4:7): LIQUID CONTENT VS DELTA")
    cv.text(L + 150, H - 30, "DELTA = INCIDENT KE / BOND ENERGY (67)")
    for k, liq in enumerate(LIQUIDS):
        y = Y(k)
        cv.text(8, y - 7, names[liq])
        ours = [r for r in rows if r["liquid"] == liq and r["delta"] > 0]
        for r in ours:
            cv.box(X(r["delta"]), y, 7, regime_rgb[regime(r["fragmented_pct"])])
            cv.text(X(r["delta"]) - 14, y + 12, f"{r['v']:g}", (60, 60, 60), 1)
            cv.text(X(r["delta"]) - 14, y + 22, f"{r['fragmented_pct']:.1f}%", (60, 60, 60), 1)
        if len(ours) >= 2:
            for b, x in zip(BORDERS, borders_in([r["delta"] for r in ours], [r["fragmented_pct"] for r in ours])):
                if x:
                    cv.line(X(x), y - 22, X(x), y + 22, (0, 0, 0), 3)
                    cv.text(X(x) - 5, y - 32, f"{b:g}", (0, 0, 0), 1)
            kk = sum(r["delta"] / r["v"] ** 2 for r in ours) / len(ours)
            vs = sorted(set(OLSSON_FRAG[liq]) | set(OLSSON_ZERO[liq]))
            for b, x in zip(BORDERS, borders_in([v * v for v in vs], [olsson_pct(liq, v) for v in vs])):
                if x:
                    cv.line(X(kk * x), y - 22, X(kk * x), y + 22, (150, 150, 150), 3)
                    cv.text(X(kk * x) - 5, y - 32, f"{b:g}", (150, 150, 150), 1)
    ly = T
    for c, n in zip(regime_rgb, REGIME_NAMES):
        cv.box(W - R + 20, ly + 7, 6, c)
        cv.text(W - R + 34, ly, n.upper(), (0, 0, 0), 1)
        ly += 18
    cv.line(W - R + 14, ly + 7, W - R + 26, ly + 7, (0, 0, 0), 3)
    cv.text(W - R + 34, ly + 3, "BORDER 3/20/50 %, TRUBAL", (0, 0, 0), 1)
    ly += 18
    cv.line(W - R + 14, ly + 7, W - R + 26, ly + 7, (150, 150, 150), 3)
    cv.text(W - R + 34, ly + 3, "BORDER, OLSSON (AT OUR DELTA/V2)", (0, 0, 0), 1)
    os.makedirs(os.path.dirname(a.png) or ".", exist_ok=True)
    cv.png(a.png)
    print(f"wrote {a.png}, {a.png.replace('.png', '_fragmentation.png')} and {a.csv}")


if __name__ == "__main__":
    main()
