#!/usr/bin/env python3
"""Single-particle impact benchmark of Pasha (2013) Ch. 4 (§4.1.5): runs scripts/pasha_single.tru
for a range of impact speeds with Pasha's simplified linear law (Table 4.2) and with
Thornton-Ning (Table 4.1), and prints the coefficient of restitution of each next to the
closed form of the simplified law (Pasha (A3.6), (A3.9), integrated independently here), and
Thornton's (1997) closed form for the same impact without adhesion (Thornton-Ning's limit at
Gamma = 0).

The table goes to doc/data/pasha_single.csv (with its provenance, scripts/provenance.py) when
run with the default FRAction 0.05, the run of doc/validation.md.

With --gamma G the interface energy is G instead of Table 4.1's 0.2 J/m^2 (COHesion G/2 on
both materials): 0.4 reads Ning's 0.2 as the energy gamma of each surface (P_c = 3 pi gamma R*,
a work of adhesion of 2 gamma) instead of the work of adhesion Gamma (P_c = 3/2 pi Gamma R*, as
Pasha's (3.59) and Lian's (2.3) write it). The table then goes to
doc/data/pasha_single_gamma<G>.csv.

usage: scripts/pasha_single.py [--frac F] [--gamma G]     (TRUBAL_BIN selects the binary)
"""
import atexit
import csv
import functools
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

R, RHO, BIG_GAMMA = 2.45e-6, 1350.0, 0.2
KE, KP, KCP, F0P = 1500.0, 210.0, 20.0, 4.0e-6
M = RHO * 4.0 / 3.0 * math.pi * R ** 3
SPEEDS = [1.0, 1.4, 1.5, 1.6, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 15.0, 20.0, 25.0]
LAWS = {
    "pasha": f"pasha {KE} {KP} {KCP} {F0P}",
    "tning": "tning 35.3e6",
}


def analytic(v):
    """e of the simplified law: loading on k_p(a - a0), elastic unloading k_e, pull-off locus
    f_cp = k_cp a_cp + f_0p, zero-force breakage (doc/contact_laws.md)."""
    f_ce = 1.5 * math.pi * R * BIG_GAMMA
    a0 = 8.0 / 9.0 * f_ce / KP
    amax = a0 + math.sqrt(a0 * a0 + M * v * v / KP)  # (A3.6)
    fmax = KP * (amax - a0)
    ap = amax - fmax / KE
    acp = (KE * ap - F0P) / (KE + KCP)
    fcp = KCP * acp + F0P
    afp = 2.0 * acp - ap
    vr2 = (fmax * (amax - ap) - fcp * (ap - afp)) / M  # (A3.9)
    return math.sqrt(vr2) / v if vr2 > 0 else 0.0


def thornton97(v, py=35.3e6):
    """e of Thornton's (1997) elastic-perfectly plastic impact without adhesion (Thornton-Ning
    at Gamma = 0), in closed form (Thornton 1997, J. Appl. Mech. 64: 383, eq. (30)) for
    Table 4.1's sphere on the silicon wall: with x = v_y / v and the yield velocity
    v_y = 1.56 (p_y^5 / (E*^4 rho))^(1/2),
    e = (6 sqrt(3) / 5)^(1/2) (1 - x^2/6)^(1/2) (x / (x + 2 (6/5 - x^2/5)^(1/2)))^(1/4), 1 below v_y."""
    e_star = 1.0 / ((1 - 0.3 ** 2) / 1.2e9 + (1 - 0.3 ** 2) / 182e9)
    vy = 1.56 * math.sqrt(py ** 5 / (e_star ** 4 * RHO))
    if v <= vy:
        return 1.0
    x = vy / v
    return math.sqrt(6 * math.sqrt(3) / 5) * math.sqrt(1 - x * x / 6) * (x / (x + 2 * math.sqrt(1.2 - x * x / 5))) ** 0.25


def binary():
    exe = os.environ.get("TRUBAL_BIN") or os.path.join(ROOT, "target", "release", "trubal")
    if not os.path.exists(exe):
        subprocess.run(["cargo", "build", "--release"], cwd=ROOT, check=True)
    return exe


@functools.lru_cache(maxsize=None)
def script():
    """pasha_single.tru, or a copy with COHesion BIG_GAMMA / 2 when --gamma changed it."""
    path = os.path.join(HERE, "pasha_single.tru")
    if BIG_GAMMA == 0.2:
        return path
    with open(path) as fh:
        text = fh.read()
    assert text.count("cohesion 0.1 ") == 2
    fd, tmp = tempfile.mkstemp(suffix=".tru")
    atexit.register(os.remove, tmp)
    with os.fdopen(fd, "w") as fh:
        fh.write(text.replace("cohesion 0.1 ", f"cohesion {BIG_GAMMA / 2!r} "))
    return tmp


def run(law, v, frac):
    out = subprocess.run(
        [binary(), script(), "--json", "--threads", "1",
         "--set", f"v={v}", "--set", f"law={LAWS[law]}", "--set", f"frac={frac}",
         "--set", "n=4000"],
        capture_output=True, text=True, check=True).stdout
    rows = [json.loads(l) for l in out.splitlines() if l.startswith("{")]
    balls = next(r for r in rows if r.get("print") == "balls")["balls"]
    contacts = next(r for r in rows if r.get("print") == "contacts")["contacts"]
    if contacts:
        return 0.0  # stuck
    return balls[0]["vel"][2] / v


def main():
    global BIG_GAMMA
    frac = 0.05
    if "--frac" in sys.argv:
        frac = float(sys.argv[sys.argv.index("--frac") + 1])
    if "--gamma" in sys.argv:
        BIG_GAMMA = float(sys.argv[sys.argv.index("--gamma") + 1])
    print(f"{'v (m/s)':>8} {'e Pasha (run)':>14} {'e Pasha (closed)':>17} {'e T-N (run)':>12}"
          f" {'e T97 (closed)':>13}")
    rows = []
    for v in SPEEDS:
        row = {"v": v, "e_pasha": run("pasha", v, frac), "e_pasha_closed": analytic(v), "e_tning": run("tning", v, frac),
               "e_thornton97_closed": thornton97(v)}
        rows.append(row)
        print(f"{v:8.2f} {row['e_pasha']:14.4f} {row['e_pasha_closed']:17.4f} {row['e_tning']:12.4f}"
              f" {row['e_thornton97_closed']:13.4f}")
    print(f"asymptote (k_p/k_e)^1/2 = {math.sqrt(KP / KE):.4f}")
    if frac == 0.05:
        sys.path.insert(0, HERE)
        import provenance
        name = "pasha_single.csv" if BIG_GAMMA == 0.2 else f"pasha_single_gamma{BIG_GAMMA:g}.csv"
        out = os.path.join(ROOT, "doc", "data", name)
        with open(out, "w", newline="") as fh:
            w = csv.DictWriter(fh, list(rows[0].keys()))
            w.writeheader()
            w.writerows({k: f"{x:.6g}" for k, x in r_.items()} for r_ in rows)
        provenance.record(out, binary(), frac=frac, gamma=BIG_GAMMA)


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
