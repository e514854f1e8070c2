#!/usr/bin/env python3
"""Olsson 2017's dry agglomerate at a wall: one factor at a time (issue 39, doc/validation.md
"The dry-fragmentation gap").

Each variant is the baseline impact (scripts/olsson_impact.tru: our JKR + Thornton's
tangential law, the particle-wall pair at the smaller friction and restitution of its
materials, FRAction 0.2, 4 x 4300 steps = 600 us, DBSCAN 70 um) with one change: extra
command lines after the restart, another prepared state, a longer run or a different
fragment radius. The fragmentation printed is Olsson's (4000 - the largest DBSCAN fragment,
particles lost through the open work-space included).

usage: olsson_factors.py WORK [--only NAME,...] [--v 3,2] [--jobs N]
  WORK holds olsson_dry.sav (scripts/olsson_prepare_dry.tru); the variants that need
  olsson_dry_nguyen.sav (the same preparation with SET NORmal NGUYEN from the start) make it
  first (WORK/prep_nguyen.tru, a few minutes).
  TRUBAL_BIN: the binary (default target/release/trubal). Writes WORK/factors.csv.
"""
import argparse
import concurrent.futures as cf
import csv
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name -> (description, state, extra lines after the restart, cycles per print, DBSCAN radius)
VARIANTS = {
    "base": ("baseline (as doc/validation.md's Olsson table)", "olsson_dry.sav", [], 4300, 70e-6),
    "long": ("run 2.4 ms instead of 0.6 ms", "olsson_dry.sav", [], 17200, 70e-6),
    "dt_half": ("time step halved (FRAction 0.1)", "olsson_dry.sav", ["fraction 0.1"], 8600, 70e-6),
    "eps_35": ("DBSCAN radius 35 um instead of 70 um", "olsson_dry.sav", [], 4300, 35e-6),
    "wall_olsson": (
        "particle-wall friction 0.35, restitution 0.3 (Olsson's pair values)",
        "olsson_dry.sav",
        ["set pair 1 2 friction 0.35 restitution 0.3"],
        4300,
        70e-6,
    ),
    "no_damping": ("no restitution damping between particles", "olsson_dry.sav", ["damping restitution 1"], 4300, 70e-6),
    "nguyen": ("JKR of Nguyen et al. (LIGGGHTS), same state", "olsson_dry.sav", ["set normal nguyen"], 4300, 70e-6),
    "nguyen_prep": (
        "JKR of Nguyen et al., agglomerate prepared with it",
        "olsson_dry_nguyen.sav",
        ["set normal nguyen"],
        4300,
        70e-6,
    ),
    "olsson_all": (
        "all of Olsson's choices: Nguyen's JKR (prepared with it), wall friction 0.35 and restitution 0.3",
        "olsson_dry_nguyen.sav",
        ["set normal nguyen", "set pair 1 2 friction 0.35 restitution 0.3"],
        4300,
        70e-6,
    ),
    "olsson_all_long": (
        "all of Olsson's choices, run 2.4 ms",
        "olsson_dry_nguyen.sav",
        ["set normal nguyen", "set pair 1 2 friction 0.35 restitution 0.3"],
        17200,
        70e-6,
    ),
}


def prepare_nguyen(work):
    """olsson_dry_nguyen.sav: olsson_prepare_dry.tru with SET NORmal NGUYEN from the start."""
    if os.path.exists(os.path.join(work, "olsson_dry_nguyen.sav")):
        return
    text = open(os.path.join(ROOT, "scripts", "olsson_prepare_dry.tru")).read()
    text = text.replace("\nagglomerate 1 ", "\nset normal nguyen\nagglomerate 1 ", 1)
    assert "set normal nguyen" in text
    path = os.path.join(work, "prep_nguyen.tru")
    open(path, "w").write(text)
    with open(os.path.join(work, "prep_nguyen.log"), "w") as fh:
        subprocess.run([exe(), "--threads", "1", path, "--set", "state=olsson_dry_nguyen.sav"],
                       cwd=work, stdout=fh, stderr=subprocess.STDOUT, check=True)

IMPACT = """restart {state}
{extra}
fraction {fraction}
set fragment {eps}
dwall p 0 0 1 {wall:.8e} m 2
velocity 0 0 -{v} 1
plot save
print energy
cycle {n}
print bonds clusters energy
cycle {n}
print bonds clusters energy
cycle {n}
print bonds clusters energy
cycle {n}
print bonds clusters energy
print info
"""


def exe():
    return os.environ.get("TRUBAL_BIN", os.path.join(ROOT, "target", "release", "trubal"))


def objects(text):
    out = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                pass
    return out


def wall_height(work, state, clearance=0.5e-6):
    path = os.path.join(work, f"balls_{state}.tru")
    with open(path, "w") as fh:
        fh.write(f"restart {state}\nprint balls\n")
    out = subprocess.run([exe(), "--json", path], cwd=work, capture_output=True, text=True, check=True)
    balls = [o for o in objects(out.stdout) if o.get("print") == "balls"][-1]["balls"]
    return min(b["pos"][2] - b["radius"] for b in balls) - clearance


def run(work, name, v, wall):
    desc, state, extra, n, eps = VARIANTS[name]
    fraction = "0.1" if "fraction 0.1" in extra else "0.2"
    extra = [e for e in extra if not e.startswith("fraction")]
    tag = f"{name}_v{v}"
    cmd = os.path.join(work, f"{tag}.tru")
    with open(cmd, "w") as fh:
        fh.write(IMPACT.format(state=state, extra="\n".join(extra), fraction=fraction, eps=eps,
                               wall=wall, v=v, n=n))
    log = os.path.join(work, f"{tag}.log")
    done = os.path.exists(log) and '"print":"info"' in open(log).read().replace(" ", "")
    if not done:
        with open(log, "w") as fh:
            r = subprocess.run([exe(), "--json", "--threads", "1", cmd], cwd=work, stdout=fh,
                               stderr=subprocess.STDOUT)
        if r.returncode:
            return {"variant": name, "v": v, "error": open(log).read()[-400:]}
    objs = objects(open(log).read())
    clus = [o for o in objs if o.get("print") == "clusters"]
    bonds = [o for o in objs if o.get("print") == "bonds"]
    info = [o for o in objs if o.get("print") == "info"][-1]
    c, b = clus[-1], bonds[-1]
    lost = info["lost"]
    total = sum(c["sizes"]) + lost
    frag = c["fragmentation"] + lost
    return {
        "variant": name,
        "description": desc,
        "v": v,
        "fragmented": frag,
        "fragmented_pct": round(100.0 * frag / total, 2),
        "by_print": "/".join(str(x["fragmentation"]) for x in clus),
        "fragments": max(len(c["fragments"]) - 1, 0),
        "capture_pct": round(100.0 * c["capture_ratio"], 1),
        "damage_ratio": round(b["damage_ratio"], 3),
        "net_damage": round(b["damage_ratio"] - b["new_ratio"], 3),
        "largest_cluster": c["largest"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("work")
    ap.add_argument("--only", default=",".join(VARIANTS))
    ap.add_argument("--v", default="3")
    ap.add_argument("--jobs", type=int, default=1)
    a = ap.parse_args()
    names = a.only.split(",")
    for n in names:
        if n not in VARIANTS:
            sys.exit(f"unknown variant {n}; known: {', '.join(VARIANTS)}")
    walls = {}
    if any(VARIANTS[n][1] == "olsson_dry_nguyen.sav" for n in names):
        prepare_nguyen(a.work)
    for n in names:
        st = VARIANTS[n][1]
        if st not in walls:
            if not os.path.exists(os.path.join(a.work, st)):
                sys.exit(f"{a.work}/{st} is missing (see the usage)")
            walls[st] = wall_height(a.work, st)
    jobs = [(n, v) for v in a.v.split(",") for n in names]
    with cf.ThreadPoolExecutor(a.jobs) as pool:
        rows = list(pool.map(lambda j: run(a.work, j[0], j[1], walls[VARIANTS[j[0]][1]]), jobs))
    keys = ["variant", "v", "fragmented", "fragmented_pct", "by_print", "fragments", "capture_pct",
            "damage_ratio", "net_damage", "largest_cluster", "description"]
    with open(os.path.join(a.work, "factors.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            if "error" in r:
                print(f"{r['variant']} v={r['v']}: FAILED\n{r['error']}", file=sys.stderr)
                continue
            w.writerow(r)
            print(",".join(str(r[k]) for k in keys[:-1]))


if __name__ == "__main__":
    main()
