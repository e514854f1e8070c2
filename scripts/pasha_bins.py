#!/usr/bin/env python3
"""Stresses in bins under the indenter (Pasha 2013, ch. 5, Figs. 5.9-5.19; issue 36;
doc/indentation.md, "Stresses under the indenter").

Reads the states that `scripts/pasha_indent.py --saves K --tag TAG` saved while indenting
(target/pasha_indent/indentTAG_NN.sav) and, in each, takes the stress in bins with Pasha's
definition (5.1) (the particles whose centre is in the bin, all their contacts, walls
included; doc/output.md, "Bins"):

- Pasha's fixed bins: 5 columns x rows of 5.2 x 5.2 x 4.2 mean particle diameters (his 5.2 x
  5.2 x 4.2 mm for d_p = 1 mm) in the x-z plane through the die's axis, column 3 under the
  indenter, row 1 on the floor, as many rows as the unloaded bed holds; named
  <column><row> as his 11 ... 53: all of them from one command, `FIEld 5 1 R BIN IN box`
  (its nodes are the bins, x fastest). A bin the indenter cuts is skipped (as Pasha does);
- his dynamic bin: the same size, centred on the axis, its top at the indenter's lowest point
  (`Window` + `PRint Stress`: one box, which moves with the indenter);
- a check of the measure: the slab of the whole die between 2 d_p above the floor and the
  dynamic bin's bottom (`Window` + `PRint Stress`). The die and the floor have no friction and the bed moves slowly, so
  the vertical force across any horizontal section is the indenter's force plus the weight of
  the particles above it: the slab's mean sigma_zz should be (F + W_above(z)) / (pi R_die^2)
  averaged over the slab's height (the window is the square around the die: its sigma times
  its volume is the sum, divided here by the slab's volume).

The bins' stress is FIEld's contact and kinetic stress plus rho V V (FIEld takes the kinetic
stress about the bin's mean velocity, `PRint Stress`'s window about zero): `Window` + `PRint
Stress`'s stress of the same box. With --check-window K (or K1,K2,...), state K's fixed bins
are also taken box by box with `Window` + `PRint Stress` and compared (every component, to
1e-12 of the largest): the result goes to the summary JSON (`window_check`, one entry per
state checked); the script stops, writing nothing, if a state does not agree.

Writes doc/data/pasha_binsTAG.csv and doc/img/pasha_binsTAG.png (vertical stress against h/d),
and prints a JSON summary.

usage: scripts/pasha_bins.py TAG [--chart-only] [--check-window K[,K...]]
       (--chart-only: the chart again from doc/data)
"""
import csv
import glob
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import provenance  # noqa: E402
import run_table  # noqa: E402
import trubal_session  # noqa: E402
from pasha_indent import G, sizes  # noqa: E402


def bin_stress(fl, node):
    """The stress (3x3, row-major lists) of FIEld node `node` as `Window` + `PRint Stress`
    gives it for the same box: contact + kinetic + rho V V."""
    rho, v = fl["density"][node], fl["velocity"][node]
    t = [fl["stress_contact"][node][k] + fl["stress_kinetic"][node][k] + rho * v[k // 3] * v[k % 3]
         for k in range(9)]
    return [t[0:3], t[3:6], t[6:9]]


def field_in(tr, n, box):
    """`FIEld n1 n2 n3 BIN IN box`: its JSON object."""
    return tr.ask(f"field {n[0]} {n[1]} {n[2]} bin in " + " ".join(repr(x) for x in box), "field")


def draw(tag, rows, o, d_mean, nrow):
    """The chart doc/img/pasha_bins<tag>.png: sigma_zz in the bins and H against h/d (kPa)."""
    series = [("dynamic bin", [(r["h_over_d"], r["dyn_szz"] / 1e3) for r in rows]),
              ("hardness H", [(r["h_over_d"], r["hardness"] / 1e3) for r in rows if r["h"] >= d_mean / 2])]
    for name in ["31", "21", "11", f"3{nrow}"]:
        pts = [(r["h_over_d"], r[f"szz_{name}"] / 1e3) for r in rows if r.get(f"szz_{name}", "") not in ("", None)]
        if pts:
            series.append((f"bin {name}", pts))
    run_table.chart(
        os.path.join(ROOT, "doc", "img", f"pasha_bins{tag}.png"),
        f"Vertical stress in bins, d = {o['d'] * 1e3:.0f} mm, {o['particles']} particles",
        series,
        "penetration h/d",
        "σ_zz, hardness H [kPa]",
        extra=["--xmin", "0"],
    )


def main():
    tag = sys.argv[1] if len(sys.argv) > 1 else ""
    with open(os.path.join(ROOT, "doc", "data", f"pasha_indent{tag}.json")) as fh:
        o = json.load(fh)
    if "--chart-only" in sys.argv:
        # Draw the chart again from doc/data/pasha_bins<tag>.csv and .json (no run).
        with open(os.path.join(ROOT, "doc", "data", f"pasha_bins{tag}.csv")) as fh:
            rows = [{k: float(v) if v != "" else "" for k, v in r.items()} for r in csv.DictReader(fh)]
        with open(os.path.join(ROOT, "doc", "data", f"pasha_bins{tag}.json")) as fh:
            nrow = json.load(fh)["rows_of_bins"]
        draw(tag, rows, o, sizes(o["scale"])[1], nrow)
        return
    work = os.path.join(ROOT, "target", "pasha_indent")
    saves = sorted(glob.glob(os.path.join(work, f"indent{tag}_[0-9][0-9].sav")))
    if not saves:
        sys.exit(f"no target/pasha_indent/indent{tag}_NN.sav: run pasha_indent.py --saves K --tag {tag}")
    _, d_mean, _ = sizes(o["scale"])
    rdie = o["die"] / 2
    c = (o["die"] + 2e-3) / 2
    d_ind = o["d"]
    bx, bz = 5.2 * d_mean, 4.2 * d_mean
    nrow = int(o["unloaded_height"] // bz)
    log = open(os.path.join(work, f"bins{tag}.log"), "w")
    binary = None if trubal_session.trubal else run_table.trubal_binary()
    tr = trubal_session.Session({}, log, work, binary=binary)
    check_at = set()
    if "--check-window" in sys.argv:
        i = sys.argv.index("--check-window") + 1
        try:
            check_at = {int(k) for k in sys.argv[i].split(",")}
        except (IndexError, ValueError):
            sys.exit("--check-window needs state numbers K or K1,K2,... (00 is h = 0)")
        if not check_at <= set(range(len(saves))):
            sys.exit(f"--check-window: the states are 0 to {len(saves) - 1}")
    window_check = []
    rows = []
    z_first = None
    for k, path in enumerate(saves):
        if k:
            tr.send("new")
        tr.send(f"restart {os.path.basename(path)}")
        walls = tr.print("walls")["walls"]
        ind = walls[-1]
        zc = ind["geometry"]["Obstacle"]["centre"][2]
        rad = ind["geometry"]["Obstacle"]["radius"]
        force = ind["force"][2]
        balls = tr.print("balls")["balls"]
        if z_first is None:
            # The first state is saved at the first record (h = 0, first contact).
            z_first = zc
        h = z_first - zc
        area_h = math.pi * (d_ind * h - h * h)
        row = {"h": h, "h_over_d": h / d_ind, "force": force,
               "hardness": force / area_h if area_h > 0 else 0.0}

        def stress(b):
            tr.send("window " + " ".join(repr(x) for x in b))
            return tr.print("stress")["window"]

        # Pasha's fixed bins, all in one FIEld (node (col-1, 0, r-1) is bin <col><r>);
        # skipped where the indenter's sphere cuts them.
        x0 = c - 2.5 * bx
        grid = [x0, x0 + 5 * bx, c - bx / 2, c + bx / 2, 0.0, nrow * bz]
        fl = field_in(tr, [5, 1, nrow], grid)
        diff, top = 0.0, 0.0
        for col in range(1, 6):
            for r in range(1, nrow + 1):
                b = [x0 + (col - 1) * bx, x0 + col * bx, grid[2], grid[3], (r - 1) * bz, r * bz]
                node = (col - 1) + 5 * (r - 1)
                sigma = bin_stress(fl, node)
                if k in check_at:
                    w = stress(b)["stress"]
                    for i in range(3):
                        for j in range(3):
                            diff = max(diff, abs(sigma[i][j] - w[i][j]))
                            top = max(top, abs(w[i][j]))
                # The box's nearest point to the indenter's centre.
                q = [min(max(c, b[0]), b[1]), min(max(c, b[2]), b[3]), min(max(zc, b[4]), b[5])]
                cut = math.dist(q, [c, c, zc]) < rad
                row[f"szz_{col}{r}"] = "" if cut else sigma[2][2]
        if k in check_at:
            window_check.append({"state": k, "h_over_d": h / d_ind, "bins": 5 * nrow,
                            "largest_stress_pa": top, "largest_difference_pa": diff,
                            "relative": diff / top if top > 0 else 0.0})
            print(f"state {k}: FIEld BIN against Window + PRint Stress on {5 * nrow} bins: "
                  f"largest difference {diff:.3e} Pa of {top:.4g} Pa", file=sys.stderr, flush=True)
            if diff > 1e-12 * top:
                sys.exit("FIEld BIN differs from Window + PRint Stress")
        # The dynamic bin under the indenter.
        ztop = zc - rad
        w = stress([c - bx / 2, c + bx / 2, c - bx / 2, c + bx / 2, ztop - bz, ztop])
        row.update({"dyn_szz": w["stress"][2][2], "dyn_hydrostatic": w["hydrostatic"],
                    "dyn_deviatoric": w["deviatoric"], "dyn_particles": w["particles"]})
        # The slab of the whole die: its force balance with the indenter.
        z1, z2 = 2 * d_mean, ztop - bz
        if z2 < z1 + d_mean:
            # (A bed too shallow for a slab under the dynamic bin.)
            z1, z2 = 2 * d_mean, ztop - d_mean
        w = stress([c - rdie, c + rdie, c - rdie, c + rdie, z1, z2])
        vbox = (2 * rdie) ** 2 * (z2 - z1)
        vslab = math.pi * rdie ** 2 * (z2 - z1)
        szz = w["stress"][2][2] * vbox / vslab
        # (F + W above z) / A, averaged over z in [z1, z2]: W above z is the weight of the
        # particles whose centre is above z.
        zs = [b["pos"][2] for b in balls]
        ms = [2456 * 4 / 3 * math.pi * b["radius"] ** 3 for b in balls]
        nz = 20
        want = 0.0
        for q in range(nz):
            z = z1 + (q + 0.5) * (z2 - z1) / nz
            want += (force + G * sum(m for m, zz in zip(ms, zs) if zz > z)) / (math.pi * rdie ** 2) / nz
        row.update({"slab_szz": szz, "slab_expected": want})
        rows.append(row)
        print(f"h/d {h / d_ind:.3f}: F {force:.4g} N, H {row['hardness']:.4g} Pa, dynamic bin "
              f"{row['dyn_szz']:.4g} Pa, slab {szz:.4g} Pa vs (F + W)/A {want:.4g} Pa",
              file=sys.stderr, flush=True)
    tr.close()
    log.close()
    with open(os.path.join(ROOT, "doc", "data", f"pasha_bins{tag}.csv"), "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)
    provenance.record(os.path.join(ROOT, "doc", "data", f"pasha_bins{tag}.csv"), run_table.trubal_binary())
    draw(tag, rows, o, d_mean, nrow)
    late = [r for r in rows if r["h_over_d"] >= 0.1]
    summary = {
        "tag": tag, "states": len(rows), "rows_of_bins": nrow,
        "dyn_szz_kpa_h_d_from_0.1": sum(r["dyn_szz"] for r in late) / max(1, len(late)) / 1e3,
        "dyn_over_hardness": sum(r["dyn_szz"] / r["hardness"] for r in late if r["hardness"] > 0) / max(1, len(late)),
        "slab_over_expected": [round(r["slab_szz"] / r["slab_expected"], 4) for r in rows],
        "fixed_bins": f"FIEld 5 1 {nrow} BIN IN (the five columns through the axis); the dynamic bin and the slab: Window + PRint Stress",
    }
    if window_check:
        summary["window_check"] = window_check
    with open(os.path.join(ROOT, "doc", "data", f"pasha_bins{tag}.json"), "w") as fh:
        json.dump(summary, fh, indent=1)
    provenance.record(os.path.join(ROOT, "doc", "data", f"pasha_bins{tag}.json"), run_table.trubal_binary())
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print(__doc__.strip()))  # the usage above, without running anything
    main()
