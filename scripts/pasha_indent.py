#!/usr/bin/env python3
"""Ball indentation of a cohesive powder bed (Pasha 2013, ch. 5; issue 36; doc/indentation.md).

Feeds scripts/pasha_indent.tru (the set-up: die, floor, piston, materials of Tables 5.2-5.3,
sizes of Table 5.1 generated inside the die) to a trubal session and drives the procedure of
ch. 5 through it (scripts/trubal_session.py: the Python module `trubal` when installed, the
particles read as arrays; else `trubal --json -` on a pipe), reading the JSON of each PRint:
  1. settle under gravity (until the kinetic energy is below 1e-4 of m g d_p of the bed);
  2. consolidate: the piston, brought to the bed's top, comes down at rate x bed height
     (constant strain rate) until its force reaches sigma_pre x die area; then a servo of
     small gain holds it until the force stays within 2 % of the target;
  3. unload: the servo's target goes to 0 at the same top speed; then the piston is lifted
     out of the way;
  4. indent: an obstacle sphere of diameter d (material 3: glass without adhesion) moves
     down at rate x bed height; h = 0 at its first contact; the vertical force on it F and
     the hardness H = F / (pi (d h - h^2)) (Pasha (2.7)-(2.9)) are recorded until h = hmax r.
Writes doc/data/pasha_indent<tag>.csv (h, h/d, h/r, F, H) and .json, the charts
target/pasha_indent/pasha_indent<tag>.png (H against h/d) and pasha_indent_force<tag>.png (F
against h), and prints a JSON summary (bed, consolidation, hardness plateau, energy
ledger).

The scaled-down case (the default): Pasha's geometry in mm (39 mm die, the bed to about
13 mm, d = 16 mm), the particles `--scale` times larger (2: 16000 / 2^3 = 2000 particles of
1.2-2.8 mm), the moduli divided by `--soften` (1000: 55 MPa particles), the work of
adhesion scaled with the particle size (Gamma = 0.5 J/m^2 x scale: the cohesive stress
f_c / d_p^2 stays Pasha's), and the piston and indenter at 10 x Pasha's strain rate (10 1/s:
gamma* = 10 sqrt(d_p/g) = 0.14 for d_p = 2 mm, still quasi-static by Tardos's 0.15).

usage: scripts/pasha_indent.py [--scale S] [--soften K] [--d MM] [--rate 1/S] [--sigma PA]
                               [--hmax H/R] [--seed K] [--tag T] [--frac F]
                               [--die MM] [--bed MM] [--law hertz|mjkr] [--mur MU]
                               [--gsettle K] [--saves K] [--from TAG | --from-settled TAG]
                               [--Gamma J/M2] [--settle-mu MU] [--ball-mur MU] [--tang T]
                               [--cut MM] [--wall-mu MU]
  --die, --bed   the die's diameter (39 mm) and the settled bed's height (the particle count
                 from a settled solids fraction of 0.50; default: 16000 / scale^3 particles)
  --law, --mur   the particles' normal law (SET NORmal; hertz = JKR with the cohesion) and
                 rolling friction (SET ROLling; Pasha: mjkr, 0.1)
  --tang T       the tangential law (SET TANgential: noslip, the default, or hm, EDEM's
                 Hertz-Mindlin with its tangential dashpot)
  --Gamma G      Pasha's interface energy (work of adhesion) Gamma (0.5 J/m^2; COHesion
                 Gamma/2), scaled with --scale; 1.0 reads his 0.5 as EDEM's surface energy
  --gsettle K    settle under K g, then 5000 steps under g (a shorter fall)
  --seed K       the K-th bed: K x 10^7 random numbers discarded before the generation (0)
  --ball-mur MU  rolling friction between the particles and the indenter (0; Pasha's indenter
                 is his material 1, whose rolling friction is 0.1)
  --settle-mu MU settle with the particles' sliding friction MU and no rolling friction (a
                 denser bed; Table 5.3's 0.15 and --mur from the consolidation on)
  --servo-div K  the piston servo's gain v / (K F) (5; more if the log warns of hunting)
  --hold 0       Pasha's procedure: the piston reverses at the target force and unloads at
                 constant speed (no servo; the default 1 holds the target with the servo first)
  --unload-rate R  with --hold 0, the piston's unloading speed R x bed height (default --rate;
                 Pasha: 1/s; a fast retreat lets the bed spring up off the floor)
  --saves K      save K + 1 states while indenting, from h = 0 to hmax (scripts/pasha_bins.py)
  --from TAG     indent the unloaded bed of run TAG again (another --d; the same set-up)
  --from-settled TAG  start from run TAG's settled bed: consolidate, unload and indent with
                 this run's --soften, --law and --mur
  --wall-mu MU   with --from-settled: sliding friction MU between the particles and the die,
                 floor and piston (Table 5.3: 0, "to avoid the influence of wall friction")
  --settle-cap N settle for at most about N steps (default: 400,000 or 10 fall times); a
                 capped settling is flagged `settle_capped` in the summary (one seed's bed of
                 346 particles kept a constant kinetic energy of 4.5e-8 J, above the rest
                 criterion, for 120,000 steps; its cause not examined)
  --cut MM       with --from-settled: delete the settled bed's particles whose centres lie
                 above MM (DELete), to make a shallower bed with the deep bed's packing
       scripts/pasha_indent.py --compare [--out NAME.png] TAG[=LABEL]...   (H against h/d of
                               the runs TAG ("" = the default run) in doc/img/NAME.png, the
                               legend saying LABEL)
       scripts/pasha_indent.py --charts TAG [--out DIR]   (run TAG's two charts again from
                               doc/data, to DIR: target/pasha_indent/ unless given)
"""
import csv
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import provenance  # noqa: E402
import run_table  # noqa: E402
import trubal_session  # noqa: E402
from lun_shear import SEED_STRIDE, no_other_options, option as arg  # noqa: E402

# Pasha 2013 Table 5.1: diameter (mm), number frequency (%).
TABLE_5_1 = [(0.59, 0.33), (0.72, 3.84), (0.81, 11.24), (0.90, 21.00), (1.00, 27.75),
             (1.10, 20.85), (1.19, 10.95), (1.28, 3.74), (1.41, 0.29)]
DIE, BED, N_PASHA = 39e-3, 13e-3, 16000
RHO = 2456  # Table 5.2, material 1 (kg/m^3; scripts/pasha_indent.tru)
G = 9.81


def steps_in(t, dt):
    """The steps of dt in the time t (0 if the step is not known)."""
    return int(t / dt) if dt > 0 else 0


def say(text):
    print(text, file=sys.stderr, flush=True)


IMG = os.path.join(ROOT, "doc", "img")
WORK = os.path.join(ROOT, "target", "pasha_indent")
# Where a run writes its data files and its work files (states, log, charts); a caller that
# runs the procedure for its own use (scripts/ci_tables.py) points both at its directory and
# sets CHARTS to False.
DATA = os.path.join(ROOT, "doc", "data")
CHARTS = True
PASHA = dict(hlines=[6.0, 8.0], hline_label="Pasha (2013): 6 and 8 kPa")


def load(tag):
    """The JSON summary and the CSV records of run TAG (doc/data/pasha_indent<tag>.*)."""
    base = os.path.join(DATA, f"pasha_indent{tag}")
    with open(base + ".json") as fh:
        o = json.load(fh)
    with open(base + ".csv") as fh:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)]
    return o, rows


def hardness(o, rows):
    """H (kPa) against h/r (r the indenter's radius), as Pasha plots it, from a penetration of
    one particle diameter on (his start)."""
    dp = o["d"] / o["d_over_dp"]
    return [(r["h_over_r"], r["hardness"] / 1e3) for r in rows if r["h"] >= dp]


def compare(tags, out="pasha_indent_compare.png", title="Ball indentation hardness, σ_pre = 10 kPa"):
    """One chart of H against h/r of the runs TAG[=LABEL] in doc/img/OUT."""
    series = []
    for spec in tags:
        # TAG or TAG=LABEL (the legend's label; default from the run's parameters).
        tag, _, given = spec.partition("=")
        o, rows = load(tag)
        label = f"d = {o['d'] * 1e3:.0f} mm, E/{o['soften']:.0f}, {o['particles']} particles"
        if o.get("law", "hertz") != "hertz" or o.get("mur", 0):
            label = f"d = {o['d'] * 1e3:.0f} mm, E/{o['soften']:.0f}, μ_r = {o['mur']:g}"
        series.append((given or label, hardness(o, rows)))
    run_table.chart(os.path.join(IMG, out), title, series, "penetration h/r (r: indenter radius)", "hardness H [kPa]", **PASHA)


def run_charts(tag, directory):
    """The charts of run TAG (H against h/d, F against h) in DIRECTORY."""
    o, rows = load(tag)
    size = f"d = {o['d'] * 1e3:.0f} mm ({o['d_over_dp']:.0f} d_p), {o['particles']} particles"
    run_table.chart(os.path.join(directory, f"pasha_indent{tag}.png"), f"Ball indentation, {size}",
                    [("trubal", hardness(o, rows))], "penetration h/r (r: indenter radius)", "hardness H [kPa]", **PASHA)
    run_table.chart(os.path.join(directory, f"pasha_indent_force{tag}.png"), f"Force on the indenter, {size}",
                    [("trubal", [(r["h"] * 1e3, r["force"]) for r in rows])],
                    "penetration h [mm]", "force on the indenter F [N]")


def sizes(scale):
    """Table 5.1's diameters x scale: [(d, f)], the number-mean d and <d^3>."""
    diam = [(d * 1e-3 * scale, f) for d, f in TABLE_5_1]
    d_mean = sum(d * f for d, f in diam) / sum(f for _, f in diam)
    d3 = sum(d ** 3 * f for d, f in diam) / sum(f for _, f in diam)
    return diam, d_mean, d3


def bed_top(balls):
    """The bed's height: the mean top of its highest 5 % of particles."""
    tops = sorted(float(x[2] + r) for x, r in zip(balls["pos"], balls["radius"]))
    k = max(1, len(tops) // 20)
    return sum(tops[-k:]) / k, tops


def main(argv=None):
    """Runs the procedure with the command line's options (argv: sys.argv[1:] if None) and
    returns its JSON summary."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if "--help" in argv or "-h" in argv:
        print(__doc__)
        return
    if argv and argv[0] == "--compare":
        # --compare [--out NAME.png] TAG...
        rest = argv[1:]
        out = arg(rest, "--out", "pasha_indent_compare.png")
        compare([t.strip("'\"") for t in rest], out)
        return
    if argv and argv[0] == "--charts":
        # --charts TAG [--out DIR]: run TAG's charts again from doc/data.
        rest = argv[1:]
        out = arg(rest, "--out", WORK)
        run_charts((rest or [""])[0], os.path.join(ROOT, out))
        return
    scale = arg(argv, "--scale", 2.0)
    soften = arg(argv, "--soften", 1000.0)
    d_ind = arg(argv, "--d", 16.0) * 1e-3
    rate = arg(argv, "--rate", 10.0)
    sigma = arg(argv, "--sigma", 1e4)
    hmax = arg(argv, "--hmax", 0.6)
    seed = arg(argv, "--seed", 0)
    tag = arg(argv, "--tag", "")
    frac = arg(argv, "--frac", 0.2)
    die = arg(argv, "--die", DIE * 1e3) * 1e-3
    bed = arg(argv, "--bed", 0.0) * 1e-3
    law = arg(argv, "--law", "hertz")
    mur = arg(argv, "--mur", 0.0)
    saves = arg(argv, "--saves", 0)
    from_unloaded = arg(argv, "--from", "")
    from_settled = arg(argv, "--from-settled", "")
    gsettle = arg(argv, "--gsettle", 1.0)
    settle_mu = arg(argv, "--settle-mu", -1.0)
    ball_mur = arg(argv, "--ball-mur", 0.0)
    servo_div = arg(argv, "--servo-div", 5.0)
    hold = arg(argv, "--hold", 1)
    unload_rate = arg(argv, "--unload-rate", 0.0)
    big_gamma = arg(argv, "--Gamma", 0.5)
    tang = arg(argv, "--tang", "noslip")
    cut = arg(argv, "--cut", 0.0) * 1e-3
    wall_mu = arg(argv, "--wall-mu", 0.0)
    settle_cap_opt = arg(argv, "--settle-cap", 0)
    no_other_options(argv)
    if from_unloaded and from_settled:
        sys.exit("--from and --from-settled exclude each other")
    if cut > 0 and not from_settled:
        sys.exit("--cut needs --from-settled (it cuts a settled bed)")
    diam, d_mean, d3 = sizes(scale)
    rdie = die / 2
    area = math.pi * rdie ** 2
    if bed > 0:
        # The settled bed's solids fraction is about 0.50 (the runs below).
        np_ = int(round(0.50 * area * bed / (math.pi / 6 * d3)))
    else:
        np_ = int(round(N_PASHA / scale ** 3))
    # Generation region: the bed's volume at solids fraction 0.25 (random sequential placement
    # jams near 0.38; at 0.3 a few per cent of the particles found no place).
    vsolid = np_ * math.pi / 6 * d3
    hgen = vsolid / 0.25 / area
    side = die + 2e-3
    c = side / 2
    gamma_w = big_gamma * scale  # Pasha's Gamma = 0.5 J/m^2, scaled with d_p
    sets = {
        "side": side, "zmax": hgen + d_ind + 0.02, "c": c, "rdie": rdie, "hgen": hgen,
        "np": np_, "nball": np_ + 10,
        "rnom": d_mean / 2, "rtab": " ".join(f"{d / 2:.6e} {f}" for d, f in diam),
        "E": 55e9 / soften, "Ew": 182e9 / soften, "gamma": gamma_w / 2, "frac": frac,
        # (Seeds 0 and 3 of the small case, 3 numbers apart, gave the same bed to the bit.)
        "seed": seed * SEED_STRIDE, "law": law, "mur": mur, "tang": tang,
    }
    work = WORK
    os.makedirs(work, exist_ok=True)
    log = open(os.path.join(work, f"run{tag}.log"), "w")
    t0 = time.time()
    # The module when installed (pip install .) and TRUBAL_PIPE is not set, else the binary
    # on a pipe (the build of TRUBAL_BIN when set).
    binary = run_table.trubal_binary()
    tr = trubal_session.Session(sets, log, work, binary=binary)
    out = {"particles": np_, "scale": scale, "soften": soften, "d": d_ind, "die": die,
           "law": law, "mur": mur, "Gamma": gamma_w, "d_over_dp": d_ind / d_mean, "die_over_dp": die / d_mean,
           "rate": rate, "sigma_pre": sigma, "gamma_star": rate * math.sqrt(d_mean / G)}
    if tang != "noslip":
        out["tangential"] = tang
    if from_unloaded:
        # Indent the unloaded bed of run TAG (its set-up: the same --scale, --die, --bed, ...).
        with open(os.path.join(DATA, f"pasha_indent{from_unloaded}.json")) as fh:
            prev = json.load(fh)
        for k in ("settle_cycles", "bed_height", "bed_over_dp", "solids_fraction",
                  "cycles_to_target", "consolidation_cycles", "piston_force", "piston_error",
                  "piston_within_2pc_records", "consolidated_height", "unloaded_height"):
            if k in prev:
                out[k] = prev[k]
        out["from"] = from_unloaded
        tr.send(f"restart unloaded{from_unloaded}.sav")
        tr.send(f"set tangential {tang}")
        tr.cycle(0)
        info = tr.print("info")
        dt = info["dt"] or 0.0
        balls = tr.balls()
        h_bed = prev["bed_height"]
        v = rate * h_bed
        out["particles"] = info["balls"]
    else:
        if from_settled:
            tr.send(f"restart settled{from_settled}.sav")
            if cut > 0:
                # The particles whose centres lie above the cut go (DELete); the 2000 steps
                # below let the new top relax before the piston comes.
                tr.send(f"delete -1 {side + 1!r} -1 {side + 1!r} {cut!r} 10")
                out["cut"] = cut
            # The summary of the run that settled the bed (missing while that run is still
            # going: then its --soften is taken as the default).
            try:
                with open(os.path.join(DATA, f"pasha_indent{from_settled}.json")) as fh:
                    settled = json.load(fh)
            except OSError:
                settled = {}
            # The moduli of this run (the settled bed was made with other ones). A bed made
            # much softer is stiffened in steps of at most x 3.2 with 2000 cycles each: at
            # fixed overlaps the contact forces grow with E, and a x 100 jump would blow the
            # bed apart.
            s_prev = float(settled.get("soften", 1000.0))
            ramp = []
            s_k = s_prev
            while s_k / soften > 3.5:
                s_k /= 3.2
                ramp.append(s_k)
            for s_k in ramp + [soften]:
                tr.send(f"ymd {55e9 / s_k!r} 1\nymd {182e9 / s_k!r} 2\nymd {55e9 / s_k!r} 3")
                if s_k != soften:
                    tr.cycle(2000)
            if ramp:
                out["stiffened_from"] = s_prev
            # The law and the rolling friction of this run (from the consolidation on).
            tr.send(f"set normal {law} 1\nset rolling {mur!r} 1 1\nset tangential {tang}")
            tr.send(f"cohesion {gamma_w / 2!r} 1")
            if wall_mu > 0:
                # Friction between the particles and the die, floor and piston (Table 5.3: 0).
                tr.send(f"set pair 1 2 friction {wall_mu!r}")
                out["wall_mu"] = wall_mu
            out["from_settled"] = from_settled
            if "settle_cycles" in settled:
                out["settle_cycles"] = settled["settle_cycles"]
            tr.cycle(2000)
        else:
            with open(os.path.join(HERE, "pasha_indent.tru")) as fh:
                tr.send(fh.read())
            tr.cycle(1)
        info = tr.print("info")
        dt = info["dt"] or 0.0
        out["particles"] = info["balls"]
        if not from_settled and info["balls"] < np_:
            # RGEnerate gave up (its try limit, or the rate of placement showed it could not
            # reach the target): a smaller bed than the case's, recorded and said.
            out["particles_asked"] = np_
            say(f"  WARNING: RGEnerate placed {info['balls']} of {np_} particles: a smaller bed than the case asks")
        mass = np_ * RHO * math.pi / 6 * d3
        if not from_settled:
            # 1. Settle: until the kinetic energy is below 1e-4 of m g d_p of the bed. With
            # --gsettle k the bed settles under k g (a shorter fall), then under g again.
            if gsettle != 1.0:
                tr.send(f"gravity 0 0 {-G * gsettle!r}")
            if settle_mu >= 0:
                tr.send(f"friction {settle_mu!r} 1\nset rolling 0 1 1")
                out["settle_mu"] = settle_mu
            chunk = 5000
            settle = 0
            # The caps on the steps of each stage scale with the step (at E = 55 GPa and
            # Pasha's 1/s the stages take millions of steps); they bind only if a stage fails.
            fall = math.sqrt(2 * hgen / (G * gsettle))
            settle_cap = settle_cap_opt or max(400000, steps_in(10 * fall, dt))
            while True:
                tr.cycle(chunk)
                settle += chunk
                e = tr.print("energy")
                kin = e["kinetic"]
                if settle % 20000 == 0:
                    say(f"  settling: {settle} cycles, kinetic {kin:.3g} J, {time.time() - t0:.0f} s")
                if (settle * dt > math.sqrt(2 * hgen / (G * gsettle))
                        and kin < 1e-4 * mass * G * gsettle * d_mean):
                    break
                if settle > settle_cap:
                    say(f"  WARNING: settling stopped at {settle} cycles, not at rest")
                    out["settle_capped"] = True
                    break
            if gsettle != 1.0:
                tr.send(f"gravity 0 0 {-G!r}")
                tr.cycle(5000)
                settle += 5000
            out["gsettle"] = gsettle
            if settle_mu >= 0:
                # Table 5.3's friction and the run's rolling friction from here on (the
                # settled bed is saved with them).
                tr.send(f"friction 0.15 1\nset rolling {mur!r} 1 1")
            tr.send(f"save settled{tag}.sav")
            out["settle_cycles"] = settle
        balls = tr.balls()
        h_bed, tops = bed_top(balls)
        if cut > 0:
            # The solids and the mass of the particles kept (the rest criterion's m g d_p).
            vsolid = sum(4 / 3 * math.pi * float(r) ** 3 for r in balls["radius"])
            mass = RHO * vsolid
        say(f"settled: {time.time() - t0:.0f} s, bed {h_bed:.4g} m")
        out.update({"bed_height": h_bed, "bed_over_dp": h_bed / d_mean,
                    "solids_fraction": vsolid / (area * h_bed)})

        # 2. Consolidate: the piston just above the bed comes down at rate x h until its force
        # reaches sigma x area; then a servo holds it there until the force stays within 2 %.
        f_target = sigma * area
        v = rate * h_bed
        tr.send(f"awall 3 p 0 0 -1 {-(tops[-1] + 0.2 * d_mean)!r} v 0 0 {-v!r}")
        consolidation = []
        n = 0
        f = 0.0
        # (The cap: 3 x the steps to travel 0.2 d_p of gap and a tenth of the bed.)
        cons_cap = max(200000, steps_in(3 * (0.2 * d_mean + 0.1 * h_bed) / v, dt))
        while n < cons_cap and f < f_target:
            # (Short records near the target: the overshoot is one record's travel.)
            k = 100 if f < 0.5 * f_target else 10
            tr.cycle(k)
            n += k
            f = tr.print("walls")["walls"][2]["normal_force"]
            consolidation.append((n, f))
        out["cycles_to_target"] = n
        if f < f_target:
            say(f"  WARNING: the piston stopped at {f:.4g} N of {f_target:.4g} after {n} cycles")
            out["target_missed"] = True
        say(f"  piston at the target after {n} cycles ({f:.4g} N of {f_target:.4g}), {time.time() - t0:.0f} s")
        out["hold"] = hold
        # The servo's gain: a fifth (1/--servo-div) of the gain that would take the whole
        # target for full speed (a larger one makes the wall hunt through the dashpots of its
        # contacts: trubal warns, in the log).
        gain = v / (servo_div * f_target)
        if hold:
            out["servo_gain"] = gain
            tr.send(f"awall 3 se {f_target!r} {v!r} {gain!r}")
        within = 0
        chunk = 499
        m = 0
        while hold and m < 60000:
            tr.cycle(chunk)
            m += chunk
            f = tr.print("walls")["walls"][2]["normal_force"]
            consolidation.append((n + m, f))
            if m % 4990 == 0:
                say(f"  holding: {m} cycles, piston force {f:.4g} N of {f_target:.4g}")
            within = within + 1 if abs(f / f_target - 1) < 0.02 else 0
            if within >= 6:
                break
        n += m
        piston = tr.print("walls")["walls"][2]
        z_piston = -piston["geometry"]["Plane"]["d"] / abs(piston["geometry"]["Plane"]["normal"][2])
        out.update({"consolidation_cycles": n, "piston_force": consolidation[-1][1],
                    "piston_error": consolidation[-1][1] / f_target - 1,
                    "piston_within_2pc_records": within,
                    "consolidated_height": z_piston})
        with open(os.path.join(DATA, f"pasha_consolidation{tag}.csv"), "w", newline="") as fh:
            wr = csv.writer(fh)
            wr.writerow(["cycle", "piston_force", "target"])
            # (At most about 2000 rows: at E and 1/s the piston takes millions of steps.)
            stride = max(1, len(consolidation) // 2000)
            kept = consolidation[::stride]
            if kept[-1] != consolidation[-1]:
                kept.append(consolidation[-1])
            wr.writerows([(c_, f_, f_target) for c_, f_ in kept])
        provenance.record(os.path.join(DATA, f"pasha_consolidation{tag}.csv"), run_table.trubal_binary())

        say(f"consolidated: {n} cycles, force {consolidation[-1][1]:.4g} N of {f_target:.4g}, {time.time() - t0:.0f} s")
        # 3. Unload at the same top speed (the servo's target 0, or with --hold 0 the piston
        # going up at v); then lift the piston out of the way.
        if hold:
            tr.send(f"awall 3 se 0 {v!r} {gain!r}")
            chunk = 500
        else:
            vu = (unload_rate or rate) * h_bed
            out["unload_speed"] = vu
            tr.send(f"awall 3 v 0 0 {vu!r}")
            chunk = 20
        n = 0
        # (The cap: 3 x the steps to travel a tenth of the bed at the unloading speed.)
        unload_cap = max(40000, steps_in(3 * 0.1 / (unload_rate or rate), dt))
        while n < unload_cap:
            tr.cycle(chunk)
            n += chunk
            if tr.print("walls")["walls"][2]["normal_force"] < 1e-2 * f_target:
                break
        out["unload_cycles"] = n
        if not hold:
            # The piston stops there while the bed comes to rest.
            tr.send("awall 3 v 0 0 0")
        tr.cycle(2000)
        balls = tr.balls()
        z_top = max(float(x[2] + r) for x, r in zip(balls["pos"], balls["radius"]))
        # A plane at rest (a velocity turns the servo off).
        tr.send(f"awall 3 p 0 0 -1 {-(z_top + d_ind + 4e-3)!r} v 0 0 0")
        out["unloaded_height"] = z_top
        # The bed at rest before the indenter comes: until its kinetic energy is below 1e-4 of
        # m g d_p (or 20000 steps).
        m = 0
        while m < 20000:
            e = tr.print("energy")["kinetic"]
            if e < 1e-4 * mass * G * d_mean:
                break
            tr.cycle(1000)
            m += 1000
        out["rest_cycles"] = m
        out["rest_kinetic_over_mgd"] = e / (mass * G * d_mean)
        say(f"  at rest after {m} more cycles (kinetic {e:.3g} J)")
        # The unloaded bed: --from TAG indents it again; scripts/bench/indenter_cost.py.
        tr.send(f"save unloaded{tag}.sav")
        say(f"unloaded: bed top {z_top:.4g} m, {time.time() - t0:.0f} s")

    # 4. Indent at constant speed from just above the highest particle under the indenter.
    under = [float(x[2] + r) for x, r in zip(balls["pos"], balls["radius"])
             if math.hypot(x[0] - c, x[1] - c) < d_ind / 2]
    z0 = max(under) + 0.2 * d_mean + d_ind / 2
    if ball_mur > 0:
        tr.send(f"set rolling {ball_mur!r} 1 3")
        out["ball_mur"] = ball_mur
    tr.send(f"dwall ob {c!r} {c!r} {z0!r} {d_ind / 2!r} v 0 0 {-v!r} m 3")
    nwall = len(tr.print("walls")["walls"])
    travel = hmax * d_ind / 2 + 0.2 * d_mean
    steps = travel / v / dt
    chunk = max(1, int(steps / 250))
    rows = []
    zc_first = None
    n = 0
    saved = 0
    while n < 3 * steps:
        tr.cycle(chunk)
        n += chunk
        w = tr.print("walls")["walls"][nwall - 1]
        zc = w["geometry"]["Obstacle"]["centre"][2]
        f = w["force"][2]  # the vertical component: the indenter's load
        if zc_first is None and f > 0:
            zc_first = zc
        if zc_first is None:
            continue
        h = zc_first - zc
        area_h = math.pi * (d_ind * h - h * h)
        rows.append({"h": h, "h_over_d": h / d_ind, "h_over_r": 2 * h / d_ind, "force": f,
                     "hardness": f / area_h if area_h > 0 else 0.0, "zc": zc})
        if saves and 2 * h / d_ind >= hmax * saved / saves:
            # States for the bin stresses (scripts/pasha_bins.py).
            tr.send(f"save indent{tag}_{saved:02d}.sav")
            saved += 1
        if len(rows) % 25 == 0:
            say(f"  indenting: h/r {2 * h / d_ind:.3f}, F {f:.4g} N, {time.time() - t0:.0f} s")
        if h >= hmax * d_ind / 2:
            break
    energy = tr.print("energy")
    tr.close()
    log.close()
    data = os.path.join(DATA, f"pasha_indent{tag}.csv")
    with open(data, "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)
    provenance.record(data, run_table.trubal_binary())
    plateau = [r["hardness"] for r in rows if 0.35 <= r["h_over_r"] <= hmax]
    mean = sum(plateau) / max(1, len(plateau))
    sd = math.sqrt(sum((x - mean) ** 2 for x in plateau) / max(1, len(plateau)))
    out.update({
        "indent_records": len(rows), "hardness_plateau_kpa": mean / 1e3, "hardness_sd_kpa": sd / 1e3,
        "h_over_sigma_pre": mean / sigma,
        "energy_residual": energy["residual"], "energy_input": energy["input"],
        "wall_work": energy["inputs"]["walls"], "seconds": time.time() - t0,
    })
    with open(os.path.join(DATA, f"pasha_indent{tag}.json"), "w") as fh:
        json.dump(out, fh, indent=1)
    provenance.record(os.path.join(DATA, f"pasha_indent{tag}.json"), run_table.trubal_binary())
    if CHARTS:
        run_charts(tag, WORK)
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
