#!/usr/bin/env python3
"""The indentation command file (scripts/pasha_indent_lang.tru, doc/language.md) on the small
case of tests/it/procedures.rs, its summary and records as data files:
doc/data/pasha_indent_lang_small.json (the SHow lines' numbers under the names of
pasha_indent.py's summaries) and doc/data/pasha_indent_lang_small.csv (h, F, H of each
record), each with its provenance. Runs in a temporary directory (~10 s).

usage: scripts/pasha_indent_lang_small.py      (TRUBAL_BIN: the binary, else the cargo build)
Python 3 standard library only.
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import provenance  # noqa: E402
import run_table  # noqa: E402

DATA = os.path.join(os.path.dirname(HERE), "doc", "data")
# The small case (tests/it/procedures.rs, SMALL) with seed 0.
SETS = [("scale", "1"), ("soften", "1000"), ("d", "4e-3"), ("rate", "10"), ("sigma", "1e4"),
        ("hmax", "0.6"), ("seed", "0"), ("die", "8e-3"), ("bed", "4e-3"),
        ("law", "mjkr edem"), ("mur", "0.1"), ("gsettle", "5"), ("hold", "0"),
        ("unload", "10")]


def shows(text):
    """label -> the list of the numbers of each SHow line with that label."""
    out = {}
    for line in text.splitlines():
        if line.startswith("{"):
            o = json.loads(line)
            if "show" in o:
                out.setdefault(o["show"][0], []).append(o["show"][1:])
    return out


def main():
    if sys.argv[1:] in (["--help"], ["-h"]):
        print(__doc__)
        return
    if len(sys.argv) > 1:
        sys.exit(f"{sys.argv[1]}: this script takes no arguments\n{__doc__}")
    exe = run_table.trubal_binary()
    args = [exe, os.path.join(HERE, "pasha_indent_lang.tru"), "--json"]
    for k, v in SETS:
        args += ["--set", f"{k}={v}"]
    with tempfile.TemporaryDirectory() as work:
        run = subprocess.run(args, cwd=work, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"pasha_indent_lang.tru failed:\n{run.stderr}")
    s = shows(run.stdout)
    bed, cons, unl = s["bed"][0], s["consolidated"][0], s["unloaded"][0]
    hard, indent = s["hardness_kpa"][0], s["indent"]
    summary = {
        "particles": bed[0], "bed_height": bed[1], "solids_fraction": bed[2],
        "piston_force": cons[0], "piston_error": cons[1], "consolidated_height": cons[2],
        "unloaded_height": unl[0], "rest_kinetic_over_mgd": unl[1],
        "indent_records": len(indent),
        "hardness_plateau_kpa": hard[0], "hardness_sd_kpa": hard[1], "plateau_records": hard[2],
        "unload_depth": s["unload_depth"][0][0],
    }
    path = os.path.join(DATA, "pasha_indent_lang_small.json")
    with open(path, "w") as fh:
        json.dump(summary, fh, indent=1)
    provenance.record(path, exe)
    path = os.path.join(DATA, "pasha_indent_lang_small.csv")
    with open(path, "w") as fh:
        fh.write("h,force,hardness\n")
        for h, f, hh in indent:
            fh.write(f"{h!r},{f!r},{hh!r}\n")
    provenance.record(path, exe)
    print(f"H = {hard[0]:.3f} kPa (sd {hard[1]:.3f}, {hard[2]:.0f} records); wrote {path}")


if __name__ == "__main__":
    main()
