#!/usr/bin/env python3
"""Speed at equal error on the agglomerate scenes (issue 50, item 3): the loop time each code
needs for the same simulated time of S2 (trubal against LAMMPS) and of the moist agglomerate
(trubal against LIGGGHTS), each at the largest step at which its own error on the scene's
contact is within 1 % (scripts/bench/equal_error_agg.py; doc/data/bench/equal_error_s2.csv,
equal_error_moist.csv):

- S2, by the binary JKR rebound: trubal FRAction 1, LAMMPS 0.05;
- moist, by the energy the wet binary impact dissipates: both 0.1;
- moist, by the wet rebound speed: trubal 0.05, LIGGGHTS 0.5.

The simulated time is that of 4000 steps at FRAction 0.2 (25.6 µs), the scenes of
run_bench.sh. Alternating runs, one thread / one rank, loop times (trubal's Cycle, the peers'
"Loop time of"). Writes doc/data/bench/equal_error_agg_speed.tsv.

    python3 scripts/bench/equal_error_agg_speed.py --bed DIR [--reps 3]

DIR is a run_bench.sh work folder with the agglomerate scenes (agg_jkr.tru, agg_moist.tru,
agg.data, agg_lig.data and their .info files).
"""
import argparse
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from equal_error import peer_loop_seconds, trubal_cycle_seconds  # noqa: E402

PEERS = os.environ.get("PEERS_DIR", os.path.join(ROOT, "..", "shared", "peers"))
LAMMPS_DECK = os.path.join(PEERS, "s2_agglomerate", "in.agglomerate.lammps")
LIGGGHTS_DECK = os.path.join(HERE, "in.agglomerate_moist.liggghts")
DT_R = 6.3894e-9 / 0.2  # the decks' step is 0.2 of the Rayleigh step
STEPS_AT_02 = int(os.environ.get("EQ_STEPS_AT_02", "4000"))  # smoke test: fewer
# (case, scene, trubal's FRAction, peer, peer's FRAction)
CASES = [("s2 rebound", "s2", 1.0, "lammps", 0.05),
         ("moist energy", "moist", 0.1, "liggghts", 0.1),
         ("moist rebound", "moist", 0.05, "liggghts", 0.5)]


def steps(frac):
    return int(round(STEPS_AT_02 * 0.2 / frac))


def time_trubal(exe, bed, scene, frac):
    src = open(os.path.join(bed, "agg_jkr.tru" if scene == "s2" else "agg_moist.tru")).read()
    text, n = re.subn(r"^fraction 0\.2$", f"fraction {frac!r}", src, flags=re.M)
    text, m = re.subn(r"^cycle \d+$", f"cycle {steps(frac)}", text, flags=re.M)
    if n != 1 or m != 1:
        sys.exit(f"the {scene} deck of {bed} has no single 'fraction 0.2' and 'cycle N' line")
    deck = os.path.join(bed, f"equal_error_{scene}_{frac}.tru")
    open(deck, "w").write(text)
    return trubal_cycle_seconds(exe, deck, bed)


def zwall(bed, info):
    return re.search(r"zwall=(\S+)", open(os.path.join(bed, info)).read()).group(1)


def time_peer(bed, peer, frac):
    deck, data, info, cmd = ((LAMMPS_DECK, "agg.data", "agg_jkr.info", "lmp") if peer == "lammps"
                             else (LIGGGHTS_DECK, "agg_lig.data", "agg_lig.info", "liggghts"))
    text, n = re.subn(r"^timestep\s+6\.3894e-9\s*$", f"timestep        {frac * DT_R!r}",
                      open(deck).read(), flags=re.M)
    if n != 1:
        sys.exit(f"{deck}: no single 'timestep 6.3894e-9' line")
    work = os.path.join(bed, f"equal_error_{peer}")
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, "deck.in")
    open(path, "w").write(text)
    args = [cmd, "-in", path, "-var", "data", os.path.join(bed, data), "-var", "zwall",
            zwall(bed, info), "-var", "nsteps", str(steps(frac)), "-var", "outdir", work, "-log", "none"]
    args += ["-var", "vimp", "1.0", "-var", "px", "1", "-nocite"] if peer == "lammps" else ["-var", "wet", "1"]
    return peer_loop_seconds(subprocess.run(args, cwd=work, capture_output=True, text=True, check=True).stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trubal", default=os.path.join(ROOT, "target", "release", "trubal"))
    ap.add_argument("--bed", required=True)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "doc", "data", "bench", "equal_error_agg_speed.tsv"))
    a = ap.parse_args()
    exe, bed = os.path.abspath(a.trubal), os.path.abspath(a.bed)
    rows = []
    for rep in range(1, a.reps + 1):
        for case, scene, ft, peer, fp in CASES:
            t = time_trubal(exe, bed, scene, ft)
            p = time_peer(bed, peer, fp)
            rows.append((rep, case, ft, steps(ft), t, peer, fp, steps(fp), p))
            print(f"  rep {rep} {case}: trubal {t:.2f} s ({steps(ft)} steps), {peer} {p:.2f} s "
                  f"({steps(fp)} steps): {p / t:.2f} ×", flush=True)
    with open(a.out, "w") as fh:
        fh.write(f"# {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())} trubal={exe} bed={bed} "
                 f"command: python3 scripts/bench/equal_error_agg_speed.py --bed DIR --reps {a.reps}\n")
        fh.write("rep\tcase\ttrubal_fraction\ttrubal_steps\ttrubal_loop_s\tpeer\tpeer_fraction\t"
                 "peer_steps\tpeer_loop_s\n")
        for r in rows:
            fh.write("\t".join(str(x) if not isinstance(x, float) else f"{x:.6g}" for x in r) + "\n")


if __name__ == "__main__":
    main()
