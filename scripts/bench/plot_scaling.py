#!/usr/bin/env python3
"""Cost per particle-step against N from scaling.sh's results (issue 9, item 3).

    python3 scripts/bench/plot_scaling.py OUT/scaling.tsv [doc/data]
    python3 scripts/bench/plot_scaling.py doc/data/scaling.csv [doc/data]   (the chart again)

Writes DIR/scaling.csv (median loop time per particle-step over the undisturbed runs of each
scene and N, with the peak memory per particle) and DIR/scaling.png (log N on x). Cost per step
growing linearly with N shows as a flat line. Python 3 standard library only.
"""
import csv
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE)))
import run_table  # noqa: E402  (chart)


def main():
    tsv = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.dirname(HERE)), "doc", "data")
    if tsv.endswith(".csv"):
        # A scaling.csv written before: draw its chart again into OUT.
        with open(tsv) as f:
            draw(list(csv.DictReader(f)), out)
        return
    groups = {}
    with open(tsv) as f:
        for r in csv.DictReader(f, delimiter="\t"):
            try:
                loop, n, steps = float(r["loop_s"]), int(r["N"]), int(r["steps"])
                share = float(r.get("loop_cpu_pct") or r["cpu_pct"])
            except (ValueError, KeyError):
                continue
            if loop != loop or "FAILED" in r.get("extra", ""):
                continue
            g = groups.setdefault((r["scene"], n, r["par"]), {"ok": [], "all": [], "rss": [], "steps": steps,
                                                             "contacts": r.get("contacts", "")})
            ns = 1e9 * loop / (n * steps)
            g["all"].append(ns)
            if share >= 90.0 * max(1, int("".join(c for c in r["par"] if c.isdigit()) or 1)):
                g["ok"].append(ns)
            g["rss"].append(float(r["maxrss_kB"]))
    rows = []
    for (scene, n, par), g in sorted(groups.items()):
        v = g["ok"] or g["all"]
        rows.append({"scene": scene, "N": n, "par": par, "steps": g["steps"], "runs": len(v),
                     "disturbed": "" if g["ok"] else "yes",
                     "ns_per_particle_step": round(statistics.median(v), 2),
                     "psps": round(1e9 / statistics.median(v)),
                     "peak_rss_MB": round(max(g["rss"]) / 1024, 1),
                     "rss_bytes_per_particle": round(max(g["rss"]) * 1024 / n),
                     "contacts_end": g["contacts"]})
    if not rows:
        sys.exit("no usable rows in " + tsv)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "scaling.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("wrote", path)
    for r in rows:
        print("  %-8s N=%-8d %-3s %8.1f ns/particle-step  %6.2e psps  %7.1f MB%s" % (
            r["scene"], r["N"], r["par"], r["ns_per_particle_step"], r["psps"], r["peak_rss_MB"],
            "  (disturbed)" if r["disturbed"] else ""))
    draw(rows, out)


def draw(rows, out):
    """OUT/scaling.png: ns per particle-step against N, one line per scene and threads."""
    series = []
    for scene in sorted({r["scene"] for r in rows}):
        for par in sorted({r["par"] for r in rows if r["scene"] == scene}):
            series.append(("%s, %s" % (scene, par),
                           [(float(r["N"]), float(r["ns_per_particle_step"])) for r in rows
                            if r["scene"] == scene and r["par"] == par]))
    run_table.chart(os.path.join(out, "scaling.png"), "Cost per particle-step against N (flat = linear in N)",
                    series, "number of particles N", "time per particle-step [ns]", logx=True)

if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
