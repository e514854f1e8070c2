#!/usr/bin/env python3
"""Speed at equal error: the wall time trubal and LIGGGHTS need for the same S1 run at the
largest step at which each code's restitution is within a tolerance (issue 50, item 3).

1. Accuracy. The peers' binary impact (../shared/peers/s3_hertz_binary: two glass spheres,
   R = 10 mm, touching at t = 0, head on) with `DAmping REStitution e` / LIGGGHTS'
   `coefficientRestitution e`, for e = 0.1, 0.3, 0.5, 0.9 and impact speeds 1 and 10 m/s
   (the spheres at +-v/2), at FRAction 1 ... 0.01 of the Rayleigh step (the same definition
   in both codes). For each code: the largest FRAction at which it and every smaller one
   give every rebound within TOL (1 %) of the set e.
2. Speed. S1 (the peers' settling bed, 10,000 spheres; `scripts/bench/run_bench.sh` makes
   the bed) run for the simulated time of 5000 steps at FRAction 0.2, each code at its own
   step: 5000 x 0.2 / FRAction steps. Alternating runs, REPS repetitions, loop times
   (trubal's Cycle, LIGGGHTS' "Loop time of"), one thread / one rank, Mindlin no-slip +
   Coulomb in both (trubal `SET TANgential NOSLIP`).

    python3 scripts/bench/equal_error.py --bed DIR [--trubal target/release/trubal] [--reps 3]

DIR holds bed10000.data and bed10000.sav (from run_bench.sh: OUT=DIR SCENES=s1
S1_SIZES=10000 ...). Writes doc/data/bench/equal_error.csv (accuracy) and
doc/data/bench/equal_error_speed.tsv (timings), prints a summary.
"""
import argparse, csv, json, math, os, re, statistics, subprocess, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PEERS = os.environ.get("PEERS_DIR", os.path.join(ROOT, "..", "shared", "peers"))
S3 = os.path.join(PEERS, "s3_hertz_binary", "in.hertz2.liggghts")
S1 = os.path.join(PEERS, "s1_settle", "in.settle.liggghts")
LADDER = [1.0, 0.7, 0.5, 0.3, 0.2, 0.15, 0.1, 0.07, 0.05, 0.03, 0.02, 0.01]
ES = [0.1, 0.3, 0.5, 0.9]
SPEEDS = [1.0, 10.0]
TOL = 0.01
# S1's Rayleigh step (the peers' README: dt_R = 8.654e-5 s) and the reference run.
S1_DT_R = 8.654e-5
S1_STEPS_AT_02 = 5000


def steps_for(frac, v):
    """Enough steps for the contact (3.12 Rayleigh steps at 20 m/s, longer as v^-1/5) and
    the rebound."""
    return int(math.ceil(1.5 * 3.12 * (20.0 / v) ** 0.2 / frac)) + 5


def liggghts_e(frac, e, v, tmp):
    deck = open(S3).read()
    deck = deck.replace("set             atom 1 vx  10.0", f"set             atom 1 vx  {v / 2}")
    deck = deck.replace("set             atom 2 vx -10.0", f"set             atom 2 vx -{v / 2}")
    deck = re.sub(r"variable        nrun equal .*", f"variable        nrun equal {steps_for(frac, v)}", deck)
    path = os.path.join(tmp, "s3.liggghts")
    open(path, "w").write(deck)
    out = os.path.join(tmp, f"lig_{frac}_{e}_{v}.txt")
    subprocess.run(["liggghts", "-in", path, "-var", "dtfrac", str(frac), "-var", "e", str(e),
                    "-var", "out", out, "-log", "none"], cwd=tmp, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    last = open(out).read().split("\n")[-2].split()
    return -float(last[3]) / (v / 2)


def trubal_e(exe, frac, e, v, tmp):
    deck = (f"start 0.2 0.1 0.1 1000 10 2\nset open all\nrad 0.01 1\nymd 4.8e10 1\npra 0.2 1\n"
            f"density 2800 1\ndamping restitution {e}\nfraction {frac}\n"
            f"create 0.09 0.05 0.05 {v / 2} 0 0 0 0 0 1 1\n"
            f"create 0.11 0.05 0.05 -{v / 2} 0 0 0 0 0 1 1\n"
            f"cycle {steps_for(frac, v)}\nprint balls\n")
    out = subprocess.run([exe, "--json", "-"], input=deck, text=True, capture_output=True,
                         cwd=tmp, check=True).stdout
    balls = [json.loads(l) for l in out.splitlines() if l.startswith("{")][-1]["balls"]
    return (balls[1]["vel"][0] - balls[0]["vel"][0]) / v


def accuracy(exe, tmp):
    """Rows (code, fraction, e, v, e measured) and each code's largest passing FRAction."""
    rows, best = [], {}
    for code, fn in (("trubal", lambda f, e, v: trubal_e(exe, f, e, v, tmp)),
                     ("liggghts", lambda f, e, v: liggghts_e(f, e, v, tmp))):
        ok_below = True
        for f in reversed(LADDER):
            errs = []
            for e in ES:
                for v in SPEEDS:
                    got = fn(f, e, v)
                    rows.append((code, f, e, v, got))
                    errs.append(abs(got / e - 1))
            ok_below = ok_below and max(errs) <= TOL
            if ok_below:
                best[code] = f
    return rows, best


def trubal_cycle_seconds(exe, deck, cwd):
    """The wall time of the Cycles of a command file, one thread (TRUBAL_TIMING's lines)."""
    p = subprocess.run([exe, "--threads", "1", deck], cwd=cwd, capture_output=True, text=True,
                       env={**os.environ, "TRUBAL_TIMING": "1"}, check=True)
    return sum(float(x) for x in re.findall(r"cycle_wall_s=([0-9.eE+-]+)", p.stderr))


def peer_loop_seconds(stdout):
    """A LIGGGHTS or LAMMPS run's last "Loop time of"."""
    return float(re.findall(r"Loop time of ([0-9.eE+-]+)", stdout)[-1])


def time_trubal(exe, bed, frac, steps):
    deck = os.path.join(bed, f"equal_error_{frac}.tru")
    open(deck, "w").write(f"restart bed10000.sav\nset tangential noslip\nfraction {frac}\n"
                          f"cycle {steps}\nprint info\n")
    return trubal_cycle_seconds(exe, deck, bed)


def time_liggghts(bed, frac, steps, tmp):
    deck = open(S1).read().replace("timestep        1.7308e-5", f"timestep        {S1_DT_R * frac:.6e}")
    deck = deck.replace("fix             ts all check/timestep/gran 1000 0.25 0.25\n", "")
    deck = deck.replace(" f_ts[1] f_ts[2]", "")
    path = os.path.join(tmp, "s1.liggghts")
    open(path, "w").write(deck)
    p = subprocess.run(["liggghts", "-in", path, "-var", "data", os.path.join(bed, "bed10000.data"),
                        "-var", "nsteps", str(steps), "-log", "none"], cwd=tmp,
                       capture_output=True, text=True, check=True)
    return peer_loop_seconds(p.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trubal", default=os.path.join(ROOT, "target", "release", "trubal"))
    ap.add_argument("--bed", required=True)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "doc", "data", "bench"))
    a = ap.parse_args()
    exe, bed = os.path.abspath(a.trubal), os.path.abspath(a.bed)
    with tempfile.TemporaryDirectory() as tmp:
        rows, best = accuracy(exe, tmp)
        with open(os.path.join(a.out, "equal_error.csv"), "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["code", "fraction", "e_set", "impact_speed", "e_measured", "rel_error"])
            for code, f, e, v, got in rows:
                w.writerow([code, f, e, v, f"{got:.6f}", f"{got / e - 1:+.5f}"])
        print(f"largest FRAction with every rebound within {TOL:.0%}: {best}")
        if len(best) < 2:
            print("a code meets the tolerance at no step of the ladder: no speed comparison")
            return
        steps = {c: int(round(S1_STEPS_AT_02 * 0.2 / f)) for c, f in best.items()}
        times = {c: [] for c in best}
        for rep in range(a.reps):
            times["trubal"].append(time_trubal(exe, bed, best["trubal"], steps["trubal"]))
            times["liggghts"].append(time_liggghts(bed, best["liggghts"], steps["liggghts"], tmp))
            print(f"  rep {rep + 1}: trubal {times['trubal'][-1]:.2f} s, LIGGGHTS {times['liggghts'][-1]:.2f} s")
    ratios = [l / t for t, l in zip(times["trubal"], times["liggghts"])]
    with open(os.path.join(a.out, "equal_error_speed.tsv"), "w") as fh:
        fh.write(f"# {time.strftime('%Y-%m-%d')} trubal={exe} bed={bed}\n")
        fh.write("rep\tcode\tfraction\tsteps\tloop_s\n")
        for rep in range(a.reps):
            for c in ("trubal", "liggghts"):
                fh.write(f"{rep + 1}\t{c}\t{best[c]}\t{steps[c]}\t{times[c][rep]:.3f}\n")
    print(f"S1 10k, {S1_STEPS_AT_02 * 0.2 * S1_DT_R:.4f} s simulated: trubal {steps['trubal']} steps "
          f"(FRAction {best['trubal']}), LIGGGHTS {steps['liggghts']} steps (FRAction {best['liggghts']}); "
          f"LIGGGHTS / trubal loop time, median {statistics.median(ratios):.2f} "
          f"[{min(ratios):.2f}-{max(ratios):.2f}] over {a.reps}")


if __name__ == "__main__":
    main()
