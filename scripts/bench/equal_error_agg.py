#!/usr/bin/env python3
"""Equal error for the agglomerate scenes: the largest time step at which each code's own
discretisation error on the scene's contact law is within a tolerance (issue 50, item 3;
the S1 version is equal_error.py). Accuracy only: nothing here is timed.

Both scenes run every code at FRAction x the Rayleigh step
dt_R = pi R sqrt(rho/G) / (0.1631 nu + 0.8766) = 3.1948e-8 s (R = 30 um, rho = 2650,
E = 70 GPa, nu = 0.3): trubal's FRAction is that definition; the peers' decks set
`timestep 6.3894e-9`, 0.2 dt_R by the same formula, which this script replaces by
FRAction x dt_R.

- s2: a head-on binary impact of two of S2's particles, each code with its own S2 deck:
  trubal the header of `agg2tru.py jkr` (material 1: JKR, cohesion 0.4 J/m^2, mu 0.3, no
  damping) with the tangential law of run_bench.sh (NOSLIP), LAMMPS
  `../shared/peers/s2_agglomerate/in.agglomerate.lammps` (`pair granular jkr`, damping
  viscoelastic 0) without its wall. Relative impact speeds 0.07 ... 2 m/s: all above the JKR
  sticking speed, 0.046 m/s (Thornton & Ning: v_s^2 = 2 W_p / m*), so the pair rebounds.
- moist: the same particles without adhesion with liquid bridges, trubal `agg2tru.py moist`
  (`liquid 0.1 0.025 0 0.01`), LIGGGHTS `in.agglomerate_moist.liggghts` (wet = 1,
  `cohesion easo/capillary/viscous`) without its wall; relative speeds 2, 5 and 10 m/s, at
  which the pair escapes the bridge in both codes (at 1 m/s trubal's pair stays bridged,
  LIGGGHTS' escapes: the two bridge laws differ, e.g. trubal's viscous gap cut-off is
  0.01 R*).

The spheres start 10 nm apart along x at +-v/2; at each FRAction of the ladder the run is
repeated with the gap grown by k/PHASES of a step's approach (k = 0 .. PHASES - 1), so that
the touch falls at PHASES places within a step, and the worst case counts. A run lasts until
the surface gap is past the range of the contact law (JKR detachment, bridge rupture): the
reference run (FRAction REF) doubles its duration until it is, and every run of the ladder
lasts as long. Measured: the relative speed after separation v' (the rebound) and the
fraction of the kinetic energy the contact dissipated, 1 - (v'/v)^2. Error = each code's
value at FRAction f against its own value at REF (20 x or more below the FRActions that
decide); REF/2 is run too, to show the reference's own error. A code's equal-error FRAction
is the largest of the ladder at which it and every smaller one give every case's rebound
within TOL (and, reported beside it, every case's dissipated energy).

    python3 scripts/bench/equal_error_agg.py [--trubal target/release/trubal] [--scenes s2 moist] [--phases 4]

Needs `lmp` (s2) and `liggghts` (moist) on the PATH. Writes doc/data/bench/
equal_error_s2.csv and equal_error_moist.csv (with .provenance.json) and prints, for each
code, the largest FRAction with every rebound (and, separately, every dissipated energy)
within TOL. `--rebuilds` (or `--rebuilds-only`) also runs the whole scenes for the same
simulated time at FRAction 1, 0.2 and 0.05 and writes their neighbour-list rebuild counts
(equal_error_SCENE_rebuilds.csv): whether a step costs the same at any step.
"""
import argparse, csv, json, math, os, re, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
import provenance  # noqa: E402

PEERS = os.environ.get("PEERS_DIR", os.path.join(ROOT, "..", "shared", "peers"))
LAMMPS_DECK = os.path.join(PEERS, "s2_agglomerate", "in.agglomerate.lammps")
LIGGGHTS_DECK = os.path.join(HERE, "in.agglomerate_moist.liggghts")
LADDER = [1.0, 0.7, 0.5, 0.3, 0.2, 0.15, 0.1, 0.07, 0.05, 0.03, 0.02]
REF = 0.002
TOL = 0.01
# --rebuilds: the scenes for the simulated time of this many steps at FRAction 0.2.
REBUILD_STEPS = 2000
REBUILD_FRACTIONS = (1.0, 0.2, 0.05)
R, RHO, E, NU = 30e-6, 2650.0, 70e9, 0.3
DT_R = math.pi * R * math.sqrt(RHO / (E / (2 * (1 + NU)))) / (0.1631 * NU + 0.8766)
GAP0 = 10e-9
CENTRE = 1.1e-3
# travel: the first reference run lasts travel / v. clear: a pair counts as separated when its
# surface gap is past the contact law's range, the JKR detachment gap (theory 3.0 nm, LAMMPS
# 1.44 nm) or the bridge rupture distance (4.84 um; LIGGGHTS' cut-off 0.1 x 2R = 6 um).
SCENES = {
    "s2": {"peer": "lammps", "speeds": [0.07, 0.1, 1.0, 2.0], "clear": 20e-9, "travel": 1e-7},
    "moist": {"peer": "liggghts", "speeds": [2.0, 5.0, 10.0], "clear": 6.5e-6, "travel": 10e-6},
}


def steps_for(frac, duration):
    return int(math.ceil(duration / (frac * DT_R)))


def positions(v, gap):
    """x of the two centres and their velocities: `gap` apart, approaching at v."""
    return CENTRE - R - gap / 2, CENTRE + R + gap / 2, v / 2, -v / 2


def substitute(text, old, new):
    """text with the line(s) matching the regex old replaced; an error if the deck changed."""
    out, n = re.subn(old, new, text, flags=re.M)
    if n == 0:
        sys.exit(f"equal_error_agg: the peer deck has no line matching {old!r}")
    return out


def trubal_header(variant, tmp):
    """The material and model lines of the scene's trubal deck (agg2tru.py), without the
    agglomerate, the wall and the impact velocity."""
    path = os.path.join(tmp, f"agg_{variant}.tru")
    subprocess.run([sys.executable, os.path.join(HERE, "agg2tru.py"), variant, "0", path],
                   check=True, stdout=subprocess.DEVNULL)
    keep, tail = [], []
    for line in open(path):
        word = line.split()[0].lower() if line.split() else ""
        if word in (";", "agglomerate", "agen", "dwall", "velocity", "print", "cycle") or line.startswith(";"):
            continue
        if word == "liquid":
            tail.append(line)
            continue
        if word == "fraction":
            keep.append("set tangential noslip\n")  # run_bench.sh's TANG default
            continue
        keep.append(line)
    return keep, tail


def run_trubal(exe, variant, frac, v, gap, duration, tmp):
    head, tail = trubal_header(variant, tmp)
    x1, x2, v1, v2 = positions(v, gap)
    deck = "".join(head) + f"fraction {frac}\n"
    deck += f"create {x1!r} {CENTRE!r} {CENTRE!r} {v1!r} 0 0 0 0 0 1 1\n"
    deck += f"create {x2!r} {CENTRE!r} {CENTRE!r} {v2!r} 0 0 0 0 0 1 1\n"
    deck += "".join(tail) + f"cycle {steps_for(frac, duration)}\nprint balls\n"
    out = subprocess.run([exe, "--json", "-"], input=deck, text=True, capture_output=True,
                         cwd=tmp, check=True).stdout
    balls = json_items(out, "print", "balls")[-1]["balls"]
    return balls[0]["pos"][0], balls[1]["pos"][0], balls[0]["vel"][0], balls[1]["vel"][0]


def json_items(out, key, value):
    """The JSON objects of trubal's --json output with out[key] == value."""
    items = [json.loads(l) for l in out.splitlines() if l.startswith("{")]
    return [d for d in items if d.get(key) == value]


def write_data(path, v, gap):
    x1, x2, _, _ = positions(v, gap)
    with open(path, "w") as f:
        f.write("equal_error_agg.py: two S2 particles\n\n2 atoms\n1 atom types\n\n")
        f.write("0 2.2e-3 xlo xhi\n0 2.2e-3 ylo yhi\n0 2.2e-3 zlo zhi\n\nAtoms\n\n")
        for i, x in enumerate((x1, x2), 1):
            f.write(f"{i} 1 {2 * R!r} {RHO!r} {x!r} {CENTRE!r} {CENTRE!r}\n")


def peer_deck(deck_path, velocity_line, frac, v):
    deck = open(deck_path).read()
    deck = substitute(deck, r"^timestep\s+6\.3894e-9\s*$", f"timestep        {frac * DT_R!r}")
    deck = substitute(deck, r"^fix\s+wall\s.*$", "")
    deck = substitute(deck, velocity_line,
                      f"velocity        all set 0 0 0 units box\nset atom 1 vx {v / 2!r}\nset atom 2 vx {-v / 2!r}")
    deck += ("\nvariable bx1 equal x[1]\nvariable bx2 equal x[2]\nvariable bv1 equal vx[1]\n"
             "variable bv2 equal vx[2]\nprint \"BINARY ${bx1} ${bx2} ${bv1} ${bv2}\"\n")
    return deck


def run_lammps(frac, v, gap, duration, tmp):
    data = os.path.join(tmp, "pair.data")
    write_data(data, v, gap)
    deck = peer_deck(LAMMPS_DECK, r"^velocity\s+all set 0\.0 0\.0 -\$\{vimp\} units box\s*$", frac, v)
    path = os.path.join(tmp, "pair.lammps")
    open(path, "w").write(deck)
    out = subprocess.run(["lmp", "-in", path, "-var", "data", data, "-var", "zwall", "0",
                          "-var", "nsteps", str(steps_for(frac, duration)), "-var", "outdir", tmp,
                          "-log", "none"], cwd=tmp, capture_output=True, text=True, check=True).stdout
    return binary_line(out)


def run_liggghts(frac, v, gap, duration, tmp):
    data = os.path.join(tmp, "pair.data")
    write_data(data, v, gap)
    deck = peer_deck(LIGGGHTS_DECK, r"^velocity\s+all set 0\.0 0\.0 -1\.0 units box\s*$", frac, v)
    path = os.path.join(tmp, "pair.liggghts")
    open(path, "w").write(deck)
    out = subprocess.run(["liggghts", "-in", path, "-var", "data", data, "-var", "zwall", "0",
                          "-var", "nsteps", str(steps_for(frac, duration)), "-var", "wet", "1",
                          "-log", "none"], cwd=tmp, capture_output=True, text=True, check=True).stdout
    return binary_line(out)


def binary_line(out):
    lines = [l for l in out.splitlines() if l.startswith("BINARY ")]
    if not lines:
        sys.exit("equal_error_agg: the peer printed no BINARY line:\n" + out[-2000:])
    return tuple(float(x) for x in lines[-1].split()[1:5])


def measure(run, frac, v, gap, duration, clear):
    """(rebound speed v', surface gap at the end, separated?) of one run."""
    x1, x2, v1, v2 = run(frac, v, gap, duration)
    end_gap = x2 - x1 - 2 * R
    return v2 - v1, end_gap, end_gap > clear and v2 > v1


def reference(run, sc, v):
    """The code's converged run at FRAction REF and the duration of every run: 1.5 x the
    first of travel / v, doubled, after which the pair has separated at REF."""
    duration = sc["travel"] / v
    while not measure(run, REF, v, GAP0, duration, sc["clear"])[2]:
        if duration > 64 * sc["travel"] / v:
            break
        duration *= 2
    return measure(run, REF, v, GAP0, 1.5 * duration, sc["clear"]), 1.5 * duration


def scene_rows(name, runners, phases):
    """Runs every code of the scene over the ladder; returns the rows (code, v, FRAction,
    phase, dt, steps, v', end gap, separated, dissipated fraction, errors) and, per code, the
    largest passing FRAction by rebound and by dissipated energy. At each FRAction of the
    ladder the touch falls at `phases` places within a step (the initial gap grows by
    k/phases of a step's approach, k = 0 .. phases - 1) and the worst error counts: a first
    order contact law's error changes sign with it (doc/limits.md, JKR)."""
    sc = SCENES[name]
    rows, best = [], {}
    for code, run in runners:
        errs = {}  # FRAction -> (max |rebound error|, max |dissipation error|)
        for v in sc["speeds"]:
            ref, duration = reference(run, sc, v)
            if not ref[2]:
                sys.exit(f"equal_error_agg: {code} {name} at {v} m/s did not separate in {duration:.3g} s")
            d_ref = 1 - (ref[0] / v) ** 2
            rows.append((code, v, REF, 0, REF * DT_R, steps_for(REF, duration), *ref, d_ref, 0.0, 0.0))
            for f in [REF / 2] + LADDER:
                for k in range(1 if f < REF else phases):
                    gap = GAP0 + k / phases * v * f * DT_R
                    got = measure(run, f, v, gap, duration, sc["clear"])
                    d = 1 - (got[0] / v) ** 2
                    er, ed = (got[0] / ref[0] - 1, d / d_ref - 1) if got[2] else (math.inf, math.inf)
                    rows.append((code, v, f, k, f * DT_R, steps_for(f, duration), *got, d, er, ed))
                    a, b = errs.get(f, (0.0, 0.0))
                    errs[f] = (max(a, abs(er)), max(b, abs(ed)))
        for k, label in ((0, "rebound"), (1, "dissipated")):
            ok = True
            for f in reversed(LADDER):
                ok = ok and errs[f][k] <= TOL
                if ok:
                    best[(code, label)] = f
            best[(code, label + " REF/2")] = errs[REF / 2][k]
    return rows, best


def scene_rebuilds(name, code, frac, exe, tmp):
    """(steps, neighbour-list rebuilds) of the whole scene run for the simulated time of
    REBUILD_STEPS steps at FRAction 0.2, at FRAction frac: the deck run_bench.sh times."""
    steps = int(round(REBUILD_STEPS * 0.2 / frac))
    if code == "trubal":
        deck = os.path.join(tmp, "scene.tru")
        subprocess.run([sys.executable, os.path.join(HERE, "agg2tru.py"),
                        "jkr" if name == "s2" else "moist", str(steps), deck],
                       check=True, stdout=subprocess.DEVNULL)
        text = substitute(open(deck).read(), r"^fraction 0\.2$",
                          f"fraction {frac}\nset tangential noslip")
        out = subprocess.run([exe, "--json", "--threads", "1", "-"], cwd=tmp, check=True,
                             input=text + "print entries\n", capture_output=True, text=True).stdout
        return steps, json_items(out, "print", "entries")[-1]["rebuilds"]
    if code == "lammps":
        data = os.path.join(tmp, "agg.data")
        info = subprocess.run([sys.executable, os.path.join(PEERS, "s2_agglomerate", "gen_agglomerate.py"),
                               data], check=True, capture_output=True, text=True).stdout
        zwall = float(re.search(r"zbottom=(\S+)", info).group(1)) - 1e-6
        deck = LAMMPS_DECK
        cmd = ["lmp"]
    else:
        data = os.path.join(tmp, "agg_lig.data")
        info = subprocess.run([sys.executable, os.path.join(HERE, "agg2tru.py"), "data", data],
                              check=True, capture_output=True, text=True).stdout
        zwall = float(re.search(r"zwall=(\S+)", info).group(1))
        deck = LIGGGHTS_DECK
        cmd = ["liggghts"]
    text = substitute(open(deck).read(), r"^timestep\s+6\.3894e-9\s*$", f"timestep        {frac * DT_R!r}")
    path = os.path.join(tmp, "scene.in")
    open(path, "w").write(text)
    out = subprocess.run(cmd + ["-in", path, "-var", "data", data, "-var", "zwall", repr(zwall),
                                "-var", "nsteps", str(steps), "-var", "outdir", tmp, "-var", "wet", "1",
                                "-log", "none"], cwd=tmp, check=True, capture_output=True, text=True).stdout
    return steps, int(re.findall(r"Neighbor list builds = (\d+)", out)[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trubal", default=os.environ.get("TRUBAL_BIN", os.path.join(ROOT, "target", "release", "trubal")))
    ap.add_argument("--scenes", nargs="+", default=["s2", "moist"], choices=list(SCENES))
    ap.add_argument("--out", default=os.path.join(ROOT, "doc", "data", "bench"))
    ap.add_argument("--phases", type=int, default=4)
    ap.add_argument("--rebuilds", action="store_true",
                    help="also count the neighbour-list rebuilds of the whole scenes at FRAction 1, "
                         "0.2 and 0.05 (equal_error_SCENE_rebuilds.csv)")
    ap.add_argument("--rebuilds-only", action="store_true",
                    help="only the rebuild counts")
    a = ap.parse_args()
    exe = os.path.abspath(a.trubal)
    if a.rebuilds_only:
        rebuilds(a, exe)
        return
    peers = {"lammps": run_lammps, "liggghts": run_liggghts}
    for name in a.scenes:
        variant = "jkr" if name == "s2" else "moist"
        with tempfile.TemporaryDirectory() as tmp:
            peer = SCENES[name]["peer"]
            runners = [("trubal", lambda f, v, g, t: run_trubal(exe, variant, f, v, g, t, tmp)),
                       (peer, lambda f, v, g, t: peers[peer](f, v, g, t, tmp))]
            rows, best = scene_rows(name, runners, a.phases)
        path = os.path.join(a.out, f"equal_error_{name}.csv")
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["code", "impact_speed", "fraction", "phase", "dt_s", "steps", "rebound_speed",
                        "gap_end_m", "separated", "dissipated_fraction", "rel_error_rebound",
                        "rel_error_dissipated"])
            for code, v, f, k, dt, n, vr, gap, sep, d, er, ed in rows:
                w.writerow([code, v, f, f"{k}/{a.phases}", f"{dt:.6e}", n, f"{vr:.9e}", f"{gap:.4e}",
                            int(sep), f"{d:.6e}", f"{er:+.3e}", f"{ed:+.3e}"])
        provenance.record(path, exe, tolerance=TOL, reference_fraction=REF, phases=a.phases,
                          peer=SCENES[name]["peer"], peer_deck=os.path.relpath(
                              LAMMPS_DECK if name == "s2" else LIGGGHTS_DECK, ROOT),
                          dt_rayleigh_s=DT_R)
        print(f"{name}: largest FRAction with every case within {TOL:.0%} of the code's own answer at {REF}:")
        for code in ("trubal", SCENES[name]["peer"]):
            print(f"  {code}: rebound speed {best.get((code, 'rebound'), 'none')}, "
                  f"dissipated energy {best.get((code, 'dissipated'), 'none')} "
                  f"(reference's own error, REF/2 against REF: rebound {best[(code, 'rebound REF/2')]:.1e}, "
                  f"dissipated {best[(code, 'dissipated REF/2')]:.1e})")
    if a.rebuilds:
        rebuilds(a, exe)


def rebuilds(a, exe):
    """Neighbour-list rebuilds per step of the whole scenes (the decks run_bench.sh times, one
    thread) for the same simulated time at FRAction 1, 0.2 and 0.05: whether a step's cost
    depends on the step. Writes equal_error_SCENE_rebuilds.csv."""
    for name in a.scenes:
        rows = []
        with tempfile.TemporaryDirectory() as tmp:
            for code in ("trubal", SCENES[name]["peer"]):
                for f in REBUILD_FRACTIONS:
                    steps, n = scene_rebuilds(name, code, f, exe, tmp)
                    rows.append((code, f, steps, n))
                    print(f"  {name} {code} FRAction {f}: {n} rebuilds in {steps} steps "
                          f"({1000 * n / steps:.1f} per 1000 steps)")
        path = os.path.join(a.out, f"equal_error_{name}_rebuilds.csv")
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["code", "fraction", "steps", "rebuilds", "rebuilds_per_1000_steps"])
            for code, f, steps, n in rows:
                w.writerow([code, f, steps, n, f"{1000 * n / steps:.2f}"])
        provenance.record(path, exe, simulated_time_s=REBUILD_STEPS * 0.2 * DT_R,
                          note="whole scene (agg2tru.py; in.agglomerate.lammps or "
                               "in.agglomerate_moist.liggghts), one thread / one rank")


if __name__ == "__main__":
    main()
