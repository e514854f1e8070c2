#!/usr/bin/env python3
"""Summarise results.tsv of run_bench.sh: medians over repetitions and ratios.

Per (scene, code, N, par, steps): runs used / dropped, median wall time, median
loop time (the code's own time for the time steps: trubal's Cycle, LAMMPS and
LIGGGHTS "Loop time of") with min-max, particle-steps per second on the loop
time (psps_loop = N*steps/loop_med) and on the wall time (psps_wall, which
includes start-up and reading the input), median peak RSS, contacts at the end
of the last run used, median CPU share.

Runs that FAILED, or got less than 90 % of 100 x ranks CPU (another process
competed on the shared machine; trubal is serial = 1 core), are dropped. The
CPU share is that of the timed loop where the code reports it (trubal:
TRUBAL_TIMING cycle_cpu_s / cycle_wall_s, column loop_cpu_pct), else that of the
whole process from /usr/bin/time (cpu_pct), as in the peers' runner. A
configuration whose runs were all dropped is still printed from all its runs,
marked "DISTURBED", so that there is a number to look at.

psps_cpu = N*steps / (CPU time of the loop) uses ALL runs that did not fail,
disturbed or not: the loop's CPU time is loop_s x CPU share (trubal: its
Cycle's own CPU time; peers: the process's share, whose start-up is short
against their loops). It is much less sensitive to other processes on the
machine than the wall-clock rate (not entirely: they share caches and memory
bandwidth), so it is the number to compare when few runs got 90 % CPU.

Then: ratio ours/theirs = psps(trubal) / psps(peer) for each scene size and
peer configuration, on the loop time of the undisturbed runs and on the CPU
time of all runs (< 1: trubal is slower), and the cost of the liquid bridges:
loop(moist) / loop(dry) per code (CPU-time based as well).

Paired ratios: the same ratio taken within each repetition (the runs of one
repetition follow each other within a minute, so a change of the machine's
load between repetitions cancels), median and range over the repetitions in
which both runs were undisturbed; likewise trubal's thread scaling, loop(t1) /
loop(tN) per repetition.

usage: summarize.py results.tsv
"""
import statistics
import sys
from collections import OrderedDict


def f(x):
    try:
        return float(x)
    except ValueError:
        return float("nan")


def cores(par):
    """The cores a run can get: its threads or ranks; one with a busy loop on the other core
    (par t1busy, t2busy)."""
    if par.endswith("busy"):
        return 1
    d = "".join(ch for ch in par if ch.isdigit())
    return int(d) if d else 1


def share(r):
    """CPU share (%) of the timed part: the loop's if known, else the process's."""
    x = f(r.get("loop_cpu_pct", "nan"))
    return x if x == x else f(r["cpu_pct"])


def load(path):
    rows = []
    with open(path) as fh:
        hdr = fh.readline().rstrip("\n").split("\t")
        for ln in fh:
            p = ln.rstrip("\n").split("\t")
            if len(p) >= len(hdr) - 1:
                rows.append(dict(zip(hdr, p + [""] * (len(hdr) - len(p)))))
    return rows


def summarize(rows):
    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["scene"], r["code"], r["N"], r["par"], r["steps"]), []).append(r)
    out = OrderedDict()
    for key, rs in groups.items():
        par = key[3]
        good = [r for r in rs if "FAILED" not in r["extra"] and "EXCLUDED" not in r["extra"]]
        ok = [r for r in good if not (share(r) < 0.9 * 100.0 * cores(par))]
        disturbed = False
        if not ok:
            if not good:
                out[key] = None
                continue
            ok, disturbed = good, True
        cpu_loop = statistics.median(f(r["loop_s"]) * share(r) / 100.0 for r in good)
        wall = statistics.median(f(r["wall_s"]) for r in ok)
        loops = [f(r["loop_s"]) for r in ok]
        loop = statistics.median(loops)
        work = int(key[2]) * int(key[4])
        out[key] = dict(
            used=len(ok), dropped=len(rs) - len(ok) if not disturbed else len(rs), disturbed=disturbed,
            wall=wall, loop=loop, lmin=min(loops), lmax=max(loops),
            psps_loop=work / loop if loop > 0 else float('nan'),
            psps_wall=work / wall if wall > 0 else float('nan'),  # /usr/bin/time rounds to 0.01 s
            cpu_loop=cpu_loop, psps_cpu=work / cpu_loop if cpu_loop > 0 else float('nan'), nall=len(good),
            rss=statistics.median(f(r["maxrss_kB"]) for r in ok) / 1024.0,
            contacts=ok[-1]["contacts"], extra=ok[-1]["extra"],
            cpu=statistics.median(share(r) for r in ok),
            load=statistics.median(f(r["loadavg_before"]) for r in ok))
    return out


def per_rep(rows):
    """Loop time of each undisturbed run, by (scene, code, N, par, steps) and repetition
    (the last undisturbed attempt of a repetition)."""
    out = {}
    for r in rows:
        if "FAILED" in r["extra"] or "EXCLUDED" in r["extra"]:
            continue
        if share(r) < 0.9 * 100.0 * cores(r["par"]):
            continue
        key = (r["scene"], r["code"], r["N"], r["par"], r["steps"])
        out.setdefault(key, {})[r["rep"]] = f(r["loop_s"])
    return out


def paired(a, b):
    """Median, min and max of a[rep] / b[rep] over the repetitions both have; None if none."""
    x = sorted(a[k] / b[k] for k in a if k in b and b[k] > 0)
    return (statistics.median(x), x[0], x[-1], len(x)) if x else None


def main():
    rows = load(sys.argv[1])
    reps = per_rep(rows)
    s = summarize(rows)
    print("%-7s %-8s %7s %6s %6s %4s %8s %8s %17s %10s %10s %7s %8s %5s %5s %4s %8s %10s" % (
        "scene", "code", "N", "par", "steps", "runs", "wall_s", "loop_s", "loop_min-max",
        "psps_loop", "psps_wall", "rss_MB", "contacts", "cpu%", "load", "all", "cpu_s", "psps_cpu"))
    for (scene, code, n, par, steps), v in s.items():
        if v is None:
            print("%-7s %-8s %7s %6s %6s  all runs FAILED" % (scene, code, n, par, steps))
            continue
        note = ""
        if v["disturbed"]:
            note = "  DISTURBED: all %d run(s) < 90 %% CPU" % v["dropped"]
        elif v["dropped"]:
            note = "  (%d dropped)" % v["dropped"]
        print("%-7s %-8s %7s %6s %6s %4d %8.2f %8.2f %8.2f-%-8.2f %10.3e %10.3e %7.1f %8s %5.0f %5.2f %4d %8.2f %10.3e%s" % (
            scene, code, n, par, steps, v["used"], v["wall"], v["loop"], v["lmin"], v["lmax"],
            v["psps_loop"], v["psps_wall"], v["rss"], v["contacts"], v["cpu"], v["load"],
            v["nall"], v["cpu_loop"], v["psps_cpu"], note))

    print("\nratio ours/theirs = psps(trubal) / psps(peer)   (< 1: trubal slower); loop time of the"
          "\nundisturbed runs, and CPU time of the loop over all runs")
    for (scene, code, n, par, steps), v in s.items():
        if code != "trubal" or v is None:
            continue
        for (sc2, c2, n2, p2, st2), w in s.items():
            if sc2 != scene or c2 == "trubal" or st2 != steps or w is None:
                continue
            if scene == "s1" and n2 != n:
                continue
            mark = " (disturbed)" if v["disturbed"] or w["disturbed"] else ""
            print("  %-5s N=%-6s steps=%-6s trubal %-3s vs %-8s %-4s  loop %.3f%s   cpu %.3f (peer %.2fx faster)" % (
                scene, n, steps, par, c2, p2, v["psps_loop"] / w["psps_loop"], mark,
                v["psps_cpu"] / w["psps_cpu"], w["psps_cpu"] / v["psps_cpu"]))

    print("\npaired ratios, per repetition (median [min-max] over n repetitions with both runs undisturbed)")
    for (scene, code, n, par, steps), a in reps.items():
        if code != "trubal":
            continue
        for (sc2, c2, n2, p2, st2), b in reps.items():
            if sc2 != scene or c2 == "trubal" or st2 != steps or n2 != n:
                continue
            # psps ratio = loop(peer) / loop(trubal) (same N and steps)
            r = paired(b, a)
            if r:
                print("  %-5s N=%-6s steps=%-6s trubal %-3s vs %-8s %-4s  %.3f [%.3f-%.3f] n=%d" % (
                    scene, n, steps, par, c2, p2, r[0], r[1], r[2], r[3]))
        if par not in ("t1", "t1busy"):
            base = "t1busy" if par.endswith("busy") else "t1"
            one = reps.get((scene, code, n, base, steps))
            r = paired(one, a) if one else None
            if r:
                print("  %-5s N=%-6s steps=%-6s trubal %s vs %s (thread scaling)      %.3f [%.3f-%.3f] n=%d" % (
                    scene, n, steps, par, base, r[0], r[1], r[2], r[3]))

    print("\ncost of liquid bridges = loop(moist) / loop(dry), same particles and steps")
    for (scene, code, n, par, steps), v in s.items():
        if scene != "moist" or v is None:
            continue
        d = s.get(("dry", code, n, par, steps))
        if d:
            print("  %-8s %-6s loop: moist %.2f s / dry %.2f s = %.2f   cpu: %.2f s / %.2f s = %.2f" % (
                code, par, v["loop"], d["loop"], v["loop"] / d["loop"],
                v["cpu_loop"], d["cpu_loop"], v["cpu_loop"] / d["cpu_loop"]))


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
