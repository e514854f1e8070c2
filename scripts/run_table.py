#!/usr/bin/env python3
"""Run a table of thesis experiments with `trubal sweep`, collect the measures, write CSV and PNG.

    python3 scripts/run_table.py TABLE [--jobs 2] [--work DIR] [--only key=value ...]
                                      [--force] [--list] [--plot-only]

TRUBAL_BIN=/path/to/trubal selects another binary than target/release/trubal.

TABLE is one of the names in TABLES below (`--list` shows them with their runs). This script
keeps what is particular to the thesis tables: the prepared states (made once in the work
directory, default target/experiments/TABLE), the --set values derived from them (the wall
height, the approach of two agglomerates), the measures derived from the printouts (energy
shares of the impact, fragmentation, ...), Lian's and Olsson's curves and the threshold fits.
The runs themselves are a `trubal sweep` of the table's command file with one row per run
(WORK/sweep_SCRIPT/: runs/NAME/output.jsonl, the --json output, and status.json), --jobs at a
time (default 2: one per core, one thread each); the sweep never runs a finished run again
(--force deletes the selected runs and the prepared states first). Runs finished by earlier
versions of this script (WORK/logs/NAME.log ending with the final printout) are read and not
run again. Run names leave out n, wall, dx, frac and state: a run whose name the work
directory holds with other values (two tables sharing a work directory whose runs differ only
in n) stops the script with both values, instead of collecting the other table's result. The
measures are read from the JSON printouts (the last PRint BONds / CLUsters /
ENErgy; the first PRint ENErgy, taken right after `PLot SAve`, is the reference for the energy
split of the impact) into doc/data/TABLE.csv, and a line chart of the table's main measure is
drawn with `trubal chart` (the points in target/charts/TABLE.csv) to doc/data/TABLE.png for the
tables the docs show, else to WORK/TABLE.png; `--chart-only` draws it again from
doc/data/TABLE.csv without running or collecting anything.

A few tables run a command file with one setting added (`VARIANTS`: e.g. SET GOLdman ON),
written under target/variants/ from that command file whenever it is used.

The same tables without Python: scripts/sweeps/*.sweep (`trubal sweep scripts/sweeps/lian6.sweep
--out DIR`, doc/sweeps.md).

Python 3 standard library only (the charts: `trubal chart`).
"""

import argparse
import concurrent.futures as cf
import csv
import functools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

try:
    # The Python module (pip install .; doc/python.md): prepared states are read into arrays
    # in-process. Without it (or with TRUBAL_BIN naming another build) through the binary's
    # JSON, as before.
    import trubal as trubal_module
except ImportError:
    trubal_module = None
import provenance

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPTS = os.path.join(ROOT, "scripts")
DATA = os.path.join(ROOT, "doc", "data")


@functools.lru_cache(maxsize=None)
def trubal_binary():
    # TRUBAL_BIN: run another build (e.g. the one whose checkpoint layout wrote the prepared
    # states); the command line at the top of every log names the binary used.
    if os.environ.get("TRUBAL_BIN"):
        return os.environ["TRUBAL_BIN"]
    # Always through cargo: a release binary left from an older checkout would otherwise run
    # silently (cargo returns at once when it is up to date).
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    return os.path.join(ROOT, "target", "release", "trubal")


# ---------------------------------------------------------------------------------------------
# The tables. A run is a dict of --set values; `x`, `group` and `y` name the chart's axes.
# `prepare` lists (script, sets, state file) made once before the runs; `derive` computes
# further --set values from the prepared states (e.g. the wall height).


def lian6_runs(velocities, state, eta_cycles):
    runs = []
    for eta, vs in velocities:
        n = eta_cycles[eta]
        for v in vs:
            runs.append({"state": state, "v": v, "eta": eta, "frac": "0.4", "n": n})
    return runs


LIAN6_V = [
    ("0", ["0.2", "0.3", "0.4", "0.5", "1", "2"]),
    ("0.01", ["0.2", "0.3", "0.44", "0.6", "1", "2", "3"]),
    ("0.1", ["0.6", "1", "2", "4", "8"]),
]
SMALL_BOX = {"box": "2.2e-3", "nbox": "27000", "centre": "1.0478907385791707e-3"}
BIG_BOX = {"box": "6.2e-3", "nbox": "300000", "centre": "2.98778764305631e-3"}
# Four printouts n cycles apart: 4 x 12500 x 12.8 ns = 640 us; eta = 0.1 runs at the viscous
# step limit 3.8 ns: 4 x 21000 x 3.8 ns = 320 us.
LIAN6_N = {"0": "12500", "0.01": "12500", "0.1": "21000"}


# Lian ch. 6's agglomerate in the 2.2 mm work-space (SMALL_BOX; Table 6.1).
LIAN6_PREPARE = [("lian_ch6_prepare.tru", dict(SMALL_BOX, ra="575e-6", state="lian_ch6.sav"), "lian_ch6.sav")]


def lian6_big_prepare(pvol=None):
    """The preparation of the agglomerate in the 6.2 mm work-space (BIG_BOX), with the bridge
    volume pvol (lian_ch6_prepare.tru's default when None)."""
    if pvol is None:
        return [("lian_ch6_prepare.tru", dict(BIG_BOX, ra="575e-6", state="lian_ch6_big.sav"), "lian_ch6_big.sav")]
    state = f"lian_ch6_big_pvol{pvol}.sav"
    return [("lian_ch6_prepare.tru", dict(BIG_BOX, ra="575e-6", pvol=pvol, state=state), state)]


def lian7_runs(full=True):
    """Lian's Table 7.1, normal collisions (cases-lian1994.md: 26 runs); `full=False` the ten
    of the earlier reduced table (the runs `lian7_lianprep` repeats from his preparation).
    At eta = 0.1 the bridges' dashpots limit the step to 2.2 ns (9.2 ns otherwise): 4 x 50,100
    steps keep the 442 us of the other runs."""
    series = [
        ("0.01", "0.025", ["0.5", "1", "2", "3", "5"], ["1.5", "2.5", "4"]),
        ("0.001", "0.025", ["0.5", "1", "2"], ["0.2", "1.2", "1.5"]),
        ("0.01", "0.05", ["2", "5"], ["0.5", "1", "3", "4"]),
        ("0.1", "0.025", [], ["2", "5", "6", "7", "10", "15"]),
    ]
    runs = []
    for eta, gam, reduced, rest in series:
        vs = sorted(reduced + rest, key=float) if full else reduced
        for v in vs:
            run = {"v": v, "theta": "0", "eta": eta, "gamma": gam}
            if eta == "0.1":
                run["n"] = "50100"
            runs.append(run)
    return runs


def lian7_oblique_runs():
    return [
        {"v": "2", "theta": t, "eta": "0.01", "gamma": "0.025"}
        for t in ["15", "30", "45", "60", "75", "85"]
    ]


def lian7_oblique_long_runs():
    return [
        {"v": "2", "theta": t, "eta": "0.01", "gamma": "0.025", "n": "30000"}
        for t in ["15", "30", "45", "60"]
    ]


def olsson_runs():
    runs = []
    for v in ["0.5", "1", "1.5", "2", "2.5", "3"]:
        runs.append({"liquid": "dry", "v": v})
    for pvol in ["0.01", "0.1", "1"]:
        for v in ["1", "2", "3", "5.2"]:
            runs.append({"liquid": pvol, "v": v})
    return runs


def olsson_regime_runs():
    """Olsson's regime map (Fig. 4:7): velocity x liquid content, wet runs with his
    Rabinovich bridges and viscous cut-off (scripts/olsson_regime.tru)."""
    runs = []
    for liquid in ["dry", "0.01", "0.1", "1"]:
        for v in ["0.5", "1", "1.5", "2", "2.5", "3", "4", "5.2"]:
            runs.append({"liquid": liquid, "v": v})
    return runs


def olsson_long_runs(extra=None):
    return [dict({"liquid": "dry", "v": v, "n": "17200"}, **(extra or {})) for v in ["1", "1.5", "2", "3"]]


def olsson_liggghts_runs():
    """Tables 4:1-4:2 with Olsson's dashpot (his eq. (6): LIGGGHTS' hertz form, SET DASHpot
    LIGGGHTS) in the impact, from the same prepared states."""
    return [dict(r, dashpot="liggghts") for r in olsson_runs()]


# The prepared Olsson agglomerates: dry and at three liquid contents (each table that
# impacts them prepares them alike).
OLSSON_PREPARE = [
    ("olsson_prepare_dry.tru", {"state": "olsson_dry.sav"}, "olsson_dry.sav"),
    ("olsson_prepare_wet.tru", {"pvol": "0.01", "state": "olsson_0.01.sav"}, "olsson_0.01.sav"),
    ("olsson_prepare_wet.tru", {"pvol": "0.1", "state": "olsson_0.1.sav"}, "olsson_0.1.sav"),
    ("olsson_prepare_wet.tru", {"pvol": "1", "state": "olsson_1.sav"}, "olsson_1.sav"),
]

# Lian ch. 7's agglomerates: ours (`lian_ch7_prepare.tru`) and prepared as his §7.2.1.
LIAN7_PREPARE = [("lian_ch7_prepare.tru", {"state": "lian_ch7.sav"}, "lian_ch7.sav")]
LIAN7_PREPARE_LIAN = [("lian_ch7_prepare_lian.tru", {"state": "lian_ch7_lian.sav"}, "lian_ch7_lian.sav")]


def lian7_oblique_table(title, runs, prepare=LIAN7_PREPARE, **more):
    """A table of oblique collisions of lian_ch7_collision.tru: D_r against the angle, one
    curve per (eta, v); `more` adds keys (work, figure)."""
    return dict({
        "title": title,
        "script": "lian_ch7_collision.tru",
        "prepare": list(prepare),
        "derive": "approach",
        "runs": runs,
        "x": "theta", "group": ("eta", "v"), "y": "damage_ratio", "logx": False,
    }, **more)


TABLES = {
    "lian6": {
        "figure": True,  # shown in doc/validation.md
        "title": "Lian ch. 6: 4062-sphere BCC agglomerate on a wall, damage ratio against velocity",
        "script": "lian_ch6_impact.tru",
        "prepare": LIAN6_PREPARE,
        "derive": "wall",
        "runs": lian6_runs(LIAN6_V, "lian_ch6.sav", LIAN6_N),
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True,
    },
    # Table 6.1's viscous rows near and above their thresholds with the bridges' tangential
    # viscous force (SET GOLdman ON), from lian6's state: does ch. 6 move as ch. 7 does
    # (lian7_goldman)?
    "lian6_goldman": {
        "title": "Lian ch. 6 with the tangential viscous force (SET GOLdman ON)",
        "script": "lian_ch6_impact_goldman.tru",
        "prepare": LIAN6_PREPARE,
        "derive": "wall",
        "work": "lian6",
        "runs": lian6_runs([("0.01", ["0.6", "1", "2"]), ("0.1", ["2", "4"])], "lian_ch6.sav", LIAN6_N),
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True, "fit": False,
    },
    # The attrition cases again in a work-space large enough to keep all debris (for the
    # debris size distribution, Lian's Fig. 6.9).
    "lian6_debris": {
        "title": "Lian ch. 6, 6.2 mm work-space: damage ratio against velocity",
        "script": "lian_ch6_impact.tru",
        "prepare": lian6_big_prepare(),
        "derive": "wall",
        "runs": lian6_runs([("0", ["2"]), ("0.01", ["2", "3"]), ("0.1", ["8"])], "lian_ch6_big.sav", LIAN6_N),
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True,
    },
    # The worst case (eta = 0, 2 m/s) and eta = 0.01 at 2 m/s of lian6_debris with SET
    # TANgential MD from the same state: is the tangential law what moves the main cluster and
    # the debris's clusters from the older builds'?
    "lian6_debris_md": {
        "title": "Lian ch. 6, 6.2 mm work-space, SET TANgential MD: damage ratio at 2 m/s",
        "script": "lian_ch6_impact_md.tru",
        "prepare": lian6_big_prepare(),
        "derive": "wall",
        "work": "lian6_debris",  # (its state; the script's own sweep directory)
        "runs": lian6_runs([("0", ["2"]), ("0.01", ["2"])], "lian_ch6_big.sav", LIAN6_N),
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True, "fit": False,
    },
    # Lian's way (issue 53 item 5): a smooth elastic wall without particle-wall bridges,
    # counted once the impact's kinetic energy is dissipated (the stopping rule in
    # scripts/lian_ch6_impact_rest.tru); with wall bridges too, to separate the two.
    "lian6_rest": {
        "title": "Lian ch. 6, 6.2 mm work-space, counted at rest: damage ratio against velocity",
        "script": "lian_ch6_impact_rest.tru",
        "prepare": lian6_big_prepare(),
        "derive": "wall",
        "runs": [{"state": "lian_ch6_big.sav", "v": "2", "eta": "0", "wb": wb, "frac": "0.4", "n": "6250"}
                 for wb in ("off", "on")],
        "x": "v", "group": ("eta", "wb"), "y": "damage_ratio", "logx": True,
        "progress": True,  # also doc/data/lian6_rest_progress.csv: every check in time
        "fit": False,  # (one velocity: no threshold fit)
    },
    # The worst case of lian6_debris alone (eta = 0, 2 m/s, 640 us, the 6.2 mm work-space), the
    # same run drawing the pictures of doc/validation.md at its end (`pictures` below).
    "lian6_worst": {
        "title": "Lian ch. 6, 6.2 mm work-space, the worst case: damage ratio at 2 m/s",
        "script": "lian_ch6_impact.tru",
        "prepare": lian6_big_prepare(),
        "derive": "wall",
        "runs": [dict(r, pictures="1") for r in lian6_runs([("0", ["2"])], "lian_ch6_big.sav", LIAN6_N)],
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True,
        "fit": False,
        # PLot's files of the run (plot_cNNNNNNNN_ITEMS.png, the last cycle) copied to
        # doc/img/PREFIX_NAME.png; doc/data/TABLE_pictures.txt names the run and the files.
        "pictures": ("validation_lian6_v2_eta0", {"lcluster": "lcluster", "lcnd": "lcnd",
                                                  "bou_rdisp": "rdisp", "bou_lcluster": "lcluster_top"}),
    },
    # The worst case with Lian's App. B bridge volume read literally: "pvol % of the volume of
    # the two spheres", twice ours (pvol = 0.2 for his 0.1), in the preparation and the impact,
    # wall bridges as lian6_debris; the speed perturbed by 1e-6 for one run's scatter.
    "lian6_volume": {
        "title": "Lian ch. 6, 6.2 mm work-space, twice the bridge volume: damage ratio at 2 m/s",
        "script": "lian_ch6_impact.tru",
        "prepare": lian6_big_prepare(pvol="0.2"),
        "derive": "wall",
        "runs": [{"state": "lian_ch6_big_pvol0.2.sav", "v": v, "eta": "0", "frac": "0.4", "n": "12500", "pvol": "0.2"}
                 for v in ("2", "2.000002", "1.999998")],
        "x": "v", "group": ("eta", "pvol"), "y": "damage_ratio", "logx": True,
        "fit": False,
    },
    # Lian's way (lian6_rest, no wall bridges, counted late) with the literal bridge volume.
    "lian6_volume_rest": {
        "title": "Lian ch. 6, twice the bridge volume, no wall bridges, counted at rest: damage ratio at 2 m/s",
        "script": "lian_ch6_impact_rest.tru",
        "prepare": lian6_big_prepare(pvol="0.2"),
        "derive": "wall",
        "runs": [{"state": "lian_ch6_big_pvol0.2.sav", "v": v, "eta": "0", "wb": "off", "frac": "0.4", "n": "6250",
                  "pvol": "0.2"} for v in ("2", "2.000002", "1.999998")],
        "x": "v", "group": ("eta", "pvol"), "y": "damage_ratio", "logx": True,
        "progress": True,
        "fit": False,
    },
    # The worst case (eta = 0, 2 m/s, 640 us, the 6.2 mm work-space of lian6_debris) with the
    # wall's friction as the one factor changed (issue 53): Lian's wall has the particles'
    # properties (mu = 0.3), against a frictionless one.
    "lian6_wall": {
        "title": "Lian ch. 6, 6.2 mm work-space, wall friction: damage ratio at 2 m/s",
        "script": "lian_ch6_impact_wall.tru",
        "prepare": lian6_big_prepare(),
        "derive": "wall",
        # The time step, which the thesis does not give: TRUBAL's default FRAction 1 (Lian 1994
        # App. B; 4 x 5000 x 32 ns = 640 us) and 0.2, against 0.4. The scatter of one run:
        # the impact speed perturbed by 1e-6 (as scripts/ci_tables.py's samples).
        "runs": [dict(r, wmu=mu) for mu in ("0", "0.3") for r in lian6_runs([("0", ["2"])], "lian_ch6_big.sav", LIAN6_N)]
        + [{"state": "lian_ch6_big.sav", "v": "2", "eta": "0", "frac": f, "n": n, "wmu": "0.3", "step": f}
           for f, n in (("1", "5000"), ("0.2", "25000"))]
        + [{"state": "lian_ch6_big.sav", "v": v, "eta": "0", "frac": "0.4", "n": "12500", "wmu": "0.3"}
           for v in ("2.000002", "1.999998")],
        "x": "v", "group": ("eta", "wmu"), "y": "damage_ratio", "logx": True,
        "fit": False,  # (one velocity: no threshold fit)
    },
    # The worst case with Lian's tangential law and his wall without bridges together
    # (scripts/lian_ch6_impact_lian.tru), each of which lian6_debris_md / lian6_rest ran alone.
    "lian6_lianway": {
        "title": "Lian ch. 6, 6.2 mm work-space, MD and no wall bridges: damage ratio at 2 m/s",
        "script": "lian_ch6_impact_lian.tru",
        "prepare": lian6_big_prepare(),
        "derive": "wall",
        "runs": lian6_runs([("0", ["2"])], "lian_ch6_big.sav", LIAN6_N),
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True,
        "fit": False,
    },
    "lian6_small": {
        "title": "Lian ch. 6, reduced 983-sphere BCC: damage ratio against velocity",
        "script": "lian_ch6_impact.tru",
        "prepare": [("lian_ch6_prepare.tru", dict(SMALL_BOX, ra="370e-6", state="lian_ch6_r370.sav"), "lian_ch6_r370.sav")],
        "derive": "wall",
        "runs": lian6_runs(LIAN6_V, "lian_ch6_r370.sav", {"0": "10000", "0.01": "10000", "0.1": "21000"}),
        "x": "v", "group": "eta", "y": "damage_ratio", "logx": True,
    },
    "lian7": {
        "figure": True,  # shown in doc/validation.md
        "title": "Lian ch. 7: two 1000-sphere agglomerates, normal collision",
        "script": "lian_ch7_collision.tru",
        "prepare": list(LIAN7_PREPARE),
        "derive": "approach",
        "runs": lian7_runs(),
        "x": "v", "group": ("eta", "gamma"), "y": "damage_ratio", "logx": True,
    },
    "lian7_oblique": lian7_oblique_table(
        "Lian ch. 7: oblique collisions at 2 m/s", lian7_oblique_runs(),
        figure=True,  # shown in doc/validation.md
        work="lian7",  # shares the prepared state (and the log directory) with lian7
    ),
    # One run of lian7_oblique (60 deg) again, by the build that ran lian7_oblique_lianprep:
    # the control that separates the preparation from the build.
    "lian7_oblique_rerun": lian7_oblique_table(
        "Lian ch. 7: oblique collision at 2 m/s, 60 deg, rerun",
        [r for r in lian7_oblique_runs() if r["theta"] == "60"],
    ),
    # 45 and 75 deg of lian7_oblique with SET TANgential MD from the same state.
    "lian7_oblique_md": dict(lian7_oblique_table(
        "Lian ch. 7: oblique collisions at 2 m/s, SET TANgential MD",
        [r for r in lian7_oblique_runs() if r["theta"] in ("45", "75")],
        work="lian7",
    ), script="lian_ch7_collision_md.tru"),
    # The 5 m/s oblique series (Lian's Figs. 7.12, 7.14), 442 us as the 2 m/s one.
    "lian7_oblique5": lian7_oblique_table(
        "Lian ch. 7: oblique collisions at 5 m/s",
        [{"v": "5", "theta": t, "eta": "0.01", "gamma": "0.025"} for t in ["30", "45", "60", "15", "75", "85"]],
        work="lian7",
    ),
    # The third oblique series of Table 7.1: eta = 0.001 at 2 m/s.
    "lian7_oblique001": lian7_oblique_table(
        "Lian ch. 7: oblique collisions at 2 m/s, eta = 0.001",
        [{"v": "2", "theta": t, "eta": "0.001", "gamma": "0.025"} for t in ["15", "30", "45", "60", "75", "85"]],
        work="lian7",
    ),
    # The grazing collisions need longer to end: 4 x 30,000 x 9.2 ns = 1.1 ms.
    "lian7_oblique_long": lian7_oblique_table(
        "Lian ch. 7: oblique collisions at 2 m/s, 1.1 ms", lian7_oblique_long_runs(),
    ),
    # Table 7.1 from agglomerates prepared as Lian's §7.2.1 (issue 53 item 4): friction and
    # no damping but the bridges' viscosity, ~340,000 cycles (scripts/lian_ch7_prepare_lian.tru).
    "lian7_lianprep": {
        "title": "Lian ch. 7, Lian's preparation: two 1000-sphere agglomerates, normal collision",
        "script": "lian_ch7_collision.tru",
        "prepare": list(LIAN7_PREPARE_LIAN),
        "derive": "approach",
        "runs": [dict(r, state="lian_ch7_lian.sav") for r in lian7_runs(full=False)],
        "x": "v", "group": ("eta", "gamma"), "y": "damage_ratio", "logx": True,
    },
    # lian7_goldman's 2 and 5 m/s (eta = 0.01) from Lian's preparation: does his denser
    # agglomerate bring D_r up to his fit with the tangential viscous force on?
    "lian7_lianprep_goldman": {
        "title": "Lian ch. 7, Lian's preparation, SET GOLdman ON: normal collisions",
        "script": "lian_ch7_collision_goldman.tru",
        "prepare": list(LIAN7_PREPARE_LIAN),
        "derive": "approach",
        "work": "lian7_lianprep",
        "runs": [{"v": v, "theta": "0", "eta": "0.01", "gamma": "0.025", "state": "lian_ch7_lian.sav"}
                 for v in ["2", "5"]],
        "x": "v", "group": ("eta", "gamma"), "y": "damage_ratio", "logx": True, "fit": False,
    },
    # The oblique series (lian7_oblique, 442 us) from Lian's preparation (lian7_lianprep's
    # state, issue 53): does D_r = D_o cos^2 Theta close?
    "lian7_oblique_lianprep": lian7_oblique_table(
        "Lian ch. 7, Lian's preparation: oblique collisions at 2 m/s",
        # (and the normal collision, Theta = 0: D_o of this state, by the same build)
        [dict(r, state="lian_ch7_lian.sav") for r in lian7_oblique_runs() if r["theta"] in ("30", "45", "60", "75")]
        + [{"v": "2", "theta": "0", "eta": "0.01", "gamma": "0.025", "state": "lian_ch7_lian.sav"}],
        prepare=LIAN7_PREPARE_LIAN,
    ),
    # The same for 1.1 ms (as lian7_oblique_long): coalescence or separation.
    "lian7_oblique_lianprep_long": lian7_oblique_table(
        "Lian ch. 7, Lian's preparation: oblique collisions at 2 m/s, 1.1 ms",
        # (and 30 and 45 deg with the speed perturbed by 1e-6: is the outcome one run's chance?)
        [dict(r, state="lian_ch7_lian.sav") for r in lian7_oblique_long_runs() if r["theta"] in ("30", "45", "60")]
        + [dict(r, state="lian_ch7_lian.sav", v="2.000002") for r in lian7_oblique_long_runs() if r["theta"] in ("45", "30")],
        prepare=LIAN7_PREPARE_LIAN,
    ),
    # Sensitivity of the energy split to S_min: Lian's lower bound R/1000 (the step shrinks
    # with it).
    "lian7_smin": {
        "title": "Lian ch. 7: 2 m/s, S_min = 30 nm",
        "script": "lian_ch7_collision.tru",
        "prepare": list(LIAN7_PREPARE),
        "derive": "approach",
        "work": "lian7",
        # The step is 3.43 ns instead of 9.2: 4 x 32,200 steps = 442 us as the other runs.
        "runs": [{"v": "2", "theta": "0", "eta": "0.01", "gamma": "0.025", "smin": "3e-8", "n": "32200"}],
        "x": "v", "group": ("eta", "smin"), "y": "e_viscous", "logx": False,
    },
    # The energy split with the bridges' tangential viscous force (SET GOLdman ON; Lian's
    # §8.2 says Goldman's equations were applied, §5.7.2 that they were not): is it what
    # keeps our viscous share below his (issue 53)? The same state and steps as `lian7`.
    "lian7_goldman": {
        "title": "Lian ch. 7 with the tangential viscous force (SET GOLdman ON)",
        "script": "lian_ch7_collision_goldman.tru",
        "prepare": list(LIAN7_PREPARE),
        "derive": "approach",
        "work": "lian7",
        "runs": [{"v": v, "theta": "0", "eta": "0.01", "gamma": "0.025"} for v in ["1", "2", "5"]]
        + [{"v": "5", "theta": "0", "eta": "0.1", "gamma": "0.025", "n": "50100"}]
        # (and the coalescence angle: 45 and 60 deg at 2 m/s for 1.1 ms, as lian7_oblique_long)
        + [{"v": "2", "theta": t, "eta": "0.01", "gamma": "0.025", "n": "30000"} for t in ["45", "60"]],
        "x": "v", "group": ("eta", "theta"), "y": "e_viscous", "logx": False,
    },
    "olsson": {
        "figure": True,  # shown in doc/validation.md
        "title": "Olsson: 4000-particle polydisperse agglomerate on a wall",
        "script": "olsson_impact.tru",
        "prepare": OLSSON_PREPARE,
        "derive": "olsson",
        "runs": olsson_runs(),
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
    # The dry half of `olsson` (the same runs and work directory): its own data file, for the
    # dry runs made again by a build when the wet ones are not.
    "olsson_dry": {
        "figure": True,  # shown in doc/validation.md
        "title": "Olsson, dry: 4000-particle polydisperse agglomerate on a wall",
        "script": "olsson_impact.tru",
        "work": "olsson",
        "prepare": OLSSON_PREPARE[:1],
        "derive": "olsson",
        "runs": [r for r in olsson_runs() if r["liquid"] == "dry"],
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
    # The regime map with Olsson's wet model (~600 us: dry 4 x 4300 x 35 ns, wet
    # 4 x 125,000 x 1.2 ns with his S_min = R*/1000).
    "olsson_regime": {
        "title": "Olsson's regime map runs (Rabinovich bridges)",
        "script": "olsson_regime.tru",
        "work": "olsson",
        "prepare": OLSSON_PREPARE,
        "derive": "olsson_regime",
        "runs": olsson_regime_runs(),
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
    # Tables 4:1-4:2 with Olsson's (LIGGGHTS') dashpot in the impact (issue 53 item 2).
    "olsson_liggghts": {
        "title": "Olsson, LIGGGHTS' dashpot: 4000-particle agglomerate on a wall",
        "script": "olsson_impact.tru",
        "work": "olsson",
        "prepare": OLSSON_PREPARE,
        "derive": "olsson",
        "runs": olsson_liggghts_runs(),
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
    # The same dry, 2.4 ms (Olsson: "until the capture ratio and damage ratio reach
    # asymptotic values", §3.4).
    "olsson_long_liggghts": {
        "title": "Olsson, dry, LIGGGHTS' dashpot, 2.4 ms",
        "script": "olsson_impact.tru",
        "work": "olsson_long",  # (the run names of olsson_liggghts without n: not in its work)
        "prepare": [("olsson_prepare_dry.tru", {"state": "olsson_dry.sav"}, "olsson_dry.sav")],
        "derive": "olsson",
        "runs": olsson_long_runs({"dashpot": "liggghts"}),
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
    # The wet rows at 5.2 m/s with the tangential law of the builds before a2bb51c (SET
    # TANgential MD) in the wet preparation (--set md=1) and so in the impact, which restarts
    # the state and keeps its law: is MDR what moved them between builds? The 0.1 % run also
    # 1e-6 faster: one run's scatter.
    "olsson_wet_md": {
        "title": "Olsson, wet, SET TANgential MD: 4000-particle agglomerate on a wall",
        "script": "olsson_impact.tru",
        "prepare": [(script, dict(sets, md="1"), state) for script, sets, state in OLSSON_PREPARE[1:]],
        "derive": "olsson",
        "runs": [{"liquid": pvol, "v": "5.2"} for pvol in ["0.01", "0.1", "1"]]
        + [{"liquid": "0.1", "v": "5.2000052"}],
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
    # Fragments drift apart slowly: the dry cases again for 2.4 ms (4 x 17,200 x 35 ns).
    "olsson_long": {
        "title": "Olsson, dry, 2.4 ms",
        "script": "olsson_impact.tru",
        "prepare": [("olsson_prepare_dry.tru", {"state": "olsson_dry.sav"}, "olsson_dry.sav")],
        "derive": "olsson",
        "runs": olsson_long_runs(),
        "x": "v", "group": "liquid", "y": "fragmentation_pct", "logx": False,
    },
}

# ---------------------------------------------------------------------------------------------
# Running


def run_name(run):
    return "_".join(f"{k}{v}" for k, v in run.items() if k not in ("state", "frac", "n", "wall", "dx"))


def json_lines(path):
    out = []
    if not os.path.exists(path):
        return out
    with open(path) as f:
        for line in f:
            if line.startswith("{"):
                try:
                    out.append(json.loads(line))
                except json.JSONDecodeError:
                    pass
    return out


def complete(path):
    """A log is complete when its last line is the final PRint Info."""
    objs = json_lines(path)
    return bool(objs) and objs[-1].get("print") == "info"


# Command files that are another one with one setting added (`SET TANgential MD`, `SET GOLdman
# ON`): name -> (the command file, the line after which the setting goes, the setting). They
# are written under target/variants from the command file each time they are used, so they
# never drift from it; the sweep keeps the copy it ran.
VARIANTS = {
    "lian_ch6_impact_md.tru": ("lian_ch6_impact.tru", 'restart "$state"', "set tangential md"),
    "lian_ch7_collision_md.tru": ("lian_ch7_collision.tru", 'restart "$state"', "set tangential md"),
    "lian_ch6_impact_goldman.tru": ("lian_ch6_impact.tru", "liquid $pvol 0.025 0 $eta", "set goldman on"),
    "lian_ch7_collision_goldman.tru": ("lian_ch7_collision.tru", "set smin $smin", "set goldman on"),
}


def script_path(script):
    """The path of a table's command file: scripts/SCRIPT, or a variant (`VARIANTS`) written
    from its command file."""
    if script not in VARIANTS:
        return os.path.join(SCRIPTS, script)
    base, after, setting = VARIANTS[script]
    with open(os.path.join(SCRIPTS, base)) as f:
        lines = f.read().split("\n")
    assert lines.count(after) == 1, f"{base}: no single line `{after}`"
    k = lines.index(after) + 1
    lines[k:k] = [setting]
    text = f"; {script}: scripts/{base} with `{setting}` after `{after}` (scripts/run_table.py).\n"
    path = os.path.join(ROOT, "target", "variants", script)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text + "\n".join(lines))
    return path


def script_names(script):
    """The `$name`s a command file uses (outside comments)."""
    names = set()
    with open(script_path(script)) as f:
        for line in f:
            line = re.split(r"[;#]", line, maxsplit=1)[0]
            names.update(a or b for a, b in re.findall(r"\$\{(\w+)\}|\$(\w+)", line))
    return names


def sweep_dir(work, script):
    return os.path.join(work, "sweep_" + os.path.splitext(script)[0])


def recorded_values(work, script, name):
    """The --set values with which the sweep in the work directory ran (or will run) the
    run `name` (its manifest, sweep.json), as {name: value}; {} when it has none."""
    try:
        with open(os.path.join(sweep_dir(work, script), "sweep.json")) as fh:
            runs = json.load(fh).get("runs") or []
    except (OSError, ValueError):
        return {}
    for r in runs:
        if r.get("name") == name:
            return {k: v for k, v in r.get("values") or []}
    return {}


def same_values(work, script, run):
    """Refuses a run whose name the work directory already holds with other values: the
    run names leave out n, wall, dx, frac and state (`run_name`), so a table run in the
    work directory of another whose runs differ only in those would otherwise collect the
    other table's results as its own."""
    rec = recorded_values(work, script, run_name(run))
    diff = [k for k, v in run.items() if k != "state" and k in rec and str(v) != rec[k]]
    if diff:
        sys.exit(f"{sweep_dir(work, script)}: run {run_name(run)} is there with "
                 + ", ".join(f"{k} = {rec[k]}" for k in diff) + ", this table's has "
                 + ", ".join(f"{k} = {run[k]}" for k in diff)
                 + ": give the table a work directory of its own (\"work\" in TABLES)")


def finished(work, script, run):
    """(JSON objects, wall-clock seconds) of a finished run, or None: the sweep's run
    directory, or the log of an earlier run_table.py. Stops if the work directory holds a
    run of that name with other values (`same_values`)."""
    same_values(work, script, run)
    d = os.path.join(sweep_dir(work, script), "runs", run_name(run))
    try:
        with open(os.path.join(d, "status.json")) as f:
            st = json.load(f)
        if st.get("exit") == 0:
            objs = json_lines(os.path.join(d, "output.jsonl"))
            if objs and objs[-1].get("print") == "info":
                return objs, st.get("wall_s", "")
    except (OSError, ValueError):
        pass
    log = os.path.join(work, "logs", run_name(run) + ".log")
    if complete(log):
        wall = ""
        with open(log) as f:
            for line in f:
                if line.startswith("# exit"):
                    wall = float(line.split()[4])
        return json_lines(log), wall
    return None


def run_sweep(exe, work, script, todo, jobs):
    """Runs [(run, sets)] as one `trubal sweep` of the script: a rows file with a `run`
    column (the names of run_name) and the --set values the script uses (a prepared state by
    its absolute path)."""
    used = script_names(script)
    keys = [k for k in todo[0][1] if k in used]
    for r, sets in todo:
        if sorted(k for k in sets if k in used) != sorted(keys):
            sys.exit(f"run {run_name(r)}: other parameters than the first run ({keys})")
    # The parameters in the order of the sweep already in the work directory (`trubal sweep`
    # resumes only a sweep of the same parameters in the same order).
    try:
        with open(os.path.join(sweep_dir(work, script), "sweep.json")) as fh:
            before = json.load(fh).get("params") or []
        if sorted(before) == sorted(keys):
            keys = list(before)
    except (OSError, ValueError):
        pass
    rows = sweep_dir(work, script) + ".rows.csv"
    with open(rows, "w") as f:
        f.write(",".join(["run"] + keys) + "\n")
        for r, sets in todo:
            vals = [os.path.join(work, sets[k]) if k == "state" else str(sets[k]) for k in keys]
            f.write(",".join([run_name(r)] + vals) + "\n")
    # One thread per run (the results do not depend on it; the cores go to the runs).
    cmd = [exe, "sweep", script_path(script), "--rows", rows, "--out", sweep_dir(work, script),
           "--jobs", str(jobs), "--threads", "1"]
    print("$ " + " ".join(cmd), flush=True)
    return subprocess.run(cmd).returncode


def trubal(exe, script, sets, work, log):
    cmd = [exe, script_path(script), "--json", "--threads", "1"]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    t0 = time.time()
    with open(log, "w") as f:
        f.write("# " + " ".join(cmd) + "\n")
        f.flush()
        r = subprocess.run(cmd, cwd=work, stdout=f, stderr=subprocess.STDOUT)
    dt = time.time() - t0
    with open(log, "a") as f:
        f.write(f"# exit {r.returncode} wall {dt:.1f} s\n")
    return r.returncode, dt


def module_state(work, state):
    """A module session restarted from WORK/STATE, or None when the binary is to be used."""
    if trubal_module is None or os.environ.get("TRUBAL_BIN"):
        return None
    s = trubal_module.Session(threads=1, json=True, dir=work)
    s.run(f"restart {state}")
    return s


def balls_of(exe, work, state):
    """Positions, radii, agglomerates of a saved state (the module's arrays, or `PRint
    Balls`)."""
    s = module_state(work, state)
    if s is not None:
        p = s.particles()
        return [{"pos": x, "radius": r, "agglomerate": a} for x, r, a in
                zip(p["position"].tolist(), p["radius"].tolist(), p["agglomerate"].tolist())]
    tmp = os.path.join(work, "_balls.tru")
    with open(tmp, "w") as f:
        f.write(f"restart {state}\nprint balls\n")
    r = subprocess.run([exe, tmp, "--json", "--threads", "1"], cwd=work, capture_output=True, text=True, check=True)
    for line in r.stdout.splitlines():
        if line.startswith("{"):
            d = json.loads(line)
            if d.get("print") == "balls":
                return d["balls"]
    raise RuntimeError("no balls printed for " + state)


def state_summary(exe, work, state):
    """One line on a prepared state: particles, bonds, coordination, bridges with a net
    compressive / tensile force (solid + static + viscous, Lian's 7391 / 7515 count), the
    largest net force, kinetic energy, circumscribing radius and fractal dimension (7.1)."""
    s = module_state(work, state)
    d = {}
    if s is not None:
        # The contacts and particles as the module's arrays; PRint's small items as JSON.
        for line in s.run("print info clusters").splitlines():
            o = json.loads(line)
            d[o["print"]] = o
        c = s.contacts()
        net = [(f if t else 0.0) + bf for f, t, bf in
               zip(c["normal_force"].tolist(), c["touching"].tolist(), c["bridge_force"].tolist())]
        bridged = c["bridge"].tolist()
        d["energy"] = {"kinetic": s.energy()["kinetic"]}
        balls = balls_of(exe, work, state)
    else:
        tmp = os.path.join(work, "_state.tru")
        with open(tmp, "w") as f:
            f.write(f"restart {state}\nprint info contacts clusters energy balls\n")
        r = subprocess.run([exe, tmp, "--json", "--threads", "1"], cwd=work, capture_output=True, text=True, check=True)
        for line in r.stdout.splitlines():
            if line.startswith("{"):
                o = json.loads(line)
                d[o["print"]] = o
        net, bridged = [], []
        for c in d["contacts"]["contacts"]:
            b = c.get("bridge")
            net.append((c["normal_force"] if c["touching"] else 0.0)
                       + (b["viscous_force"] - b["static_force"] if b else 0.0))
            bridged.append(b is not None)
        balls = d["balls"]["balls"]
    comp = sum(1 for f, b in zip(net, bridged) if b and f > 0)
    tens = sum(1 for f, b in zip(net, bridged) if b and not f > 0)
    fmax = max((abs(f) for f in net), default=0.0)
    out = []
    for agg in sorted({x["agglomerate"] for x in balls}):
        bs = [x for x in balls if x["agglomerate"] == agg]
        c = [sum(x["pos"][k] for x in bs) / len(bs) for k in range(3)]
        rc = max(math.dist(x["pos"], c) + x["radius"] for x in bs)
        rm = sum(x["radius"] for x in bs) / len(bs)
        df = math.log(len(bs)) / math.log(rc / rm)
        out.append(f"agglomerate {agg}: {len(bs)} particles, R_c {1e6 * rc:.1f} um, D_f {df:.3f}")
    i, cl = d["info"], d["clusters"]
    return (
        f"{state}: {i['balls']} particles, {i['contacts']} solid contacts, {i['bridges']} bridges "
        f"({comp} net compressive, {tens} net tensile), coordination {cl['coordination']:.3f}, "
        f"largest net contact force {fmax:.3e} N, kinetic energy {d['energy']['kinetic']:.3e} J; "
        + "; ".join(out)
    )


def wall_height(exe, work, state, clearance=0.5e-6):
    """Plane z = h, `clearance` below the lowest particle surface."""
    b = balls_of(exe, work, state)
    return min(x["pos"][2] - x["radius"] for x in b) - clearance


def approach_shift(exe, work, state, clearance=1e-6):
    """MOVe distance (along -x) of agglomerate 2 that leaves `clearance` between the closest
    surfaces of the two agglomerates (their centres lie on one x line)."""
    b = balls_of(exe, work, state)
    a1 = [x for x in b if x["agglomerate"] == 1]
    a2 = [x for x in b if x["agglomerate"] == 2]
    # Candidates: the 150 particles of each agglomerate nearest the other.
    a1.sort(key=lambda x: -(x["pos"][0] + x["radius"]))
    a2.sort(key=lambda x: x["pos"][0] - x["radius"])
    shift = math.inf
    for p in a1[:150]:
        for q in a2[:150]:
            rr = p["radius"] + q["radius"]
            dy = q["pos"][1] - p["pos"][1]
            dz = q["pos"][2] - p["pos"][2]
            rho2 = dy * dy + dz * dz
            if rho2 >= rr * rr:
                continue
            # q moved by -s along x touches p when qx - s - px = sqrt(rr^2 - rho^2).
            s = q["pos"][0] - p["pos"][0] - math.sqrt(rr * rr - rho2)
            shift = min(shift, s)
    return shift - clearance


def needed_states(t, runs):
    """The prepared states the runs start from, when the table's derivation says (Olsson's:
    one per liquid content), else None (all of them)."""
    if t.get("derive") in ("olsson", "olsson_regime"):
        return {"olsson_dry.sav" if r["liquid"] == "dry" else f"olsson_{r['liquid']}.sav" for r in runs}
    return None


def derive(kind, exe, work, run, cache):
    sets = dict(run)
    if kind == "wall":
        key = ("wall", run["state"])
        if key not in cache:
            cache[key] = wall_height(exe, work, run["state"])
        sets["wall"] = f"{cache[key]:.8e}"
    elif kind == "approach":
        state = run.get("state", "lian_ch7.sav")
        key = ("approach", state)
        if key not in cache:
            cache[key] = approach_shift(exe, work, state)
        v, th = float(run["v"]), math.radians(float(run["theta"]))
        # Relative velocity v at angle theta to the line of centres, split equally.
        sets.update(
            {
                "state": state,
                "dx": f"{cache[key]:.8e}",
                "v1x": f"{0.5 * v * math.cos(th):.10g}",
                "v1y": f"{0.5 * v * math.sin(th):.10g}",
                "v2x": f"{-0.5 * v * math.cos(th):.10g}",
                "v2y": f"{-0.5 * v * math.sin(th):.10g}",
                "n": run.get("n", "12000"),
                "smin": run.get("smin", "default"),
            }
        )
    elif kind in ("olsson", "olsson_regime"):
        state = "olsson_dry.sav" if run["liquid"] == "dry" else f"olsson_{run['liquid']}.sav"
        # ~600 us: 4 x 4300 x 35 ns dry, 4 x 12500 x 12 ns wet.
        n = run.get("n", "4300" if run["liquid"] == "dry" else "12500")
        sets = {"state": state}
        if kind == "olsson":  # (olsson_regime.tru places its wall from the state itself)
            key = ("wall", state)
            if key not in cache:
                cache[key] = wall_height(exe, work, state)
            sets["wall"] = f"{cache[key]:.8e}"
        sets.update({"v": run["v"], "n": n, "dashpot": run.get("dashpot", "trubal")})
        if kind == "olsson_regime":
            sets["n"] = run.get("n", "4300" if run["liquid"] == "dry" else "125000")
            sets["smin"] = run.get("smin", "default")
            sets["law"] = run.get("law", "hertz")
            sets["pair"] = run.get("pair", "default")
    return sets


# ---------------------------------------------------------------------------------------------
# Measures


def measures(objs, run):
    """The row of one finished run."""
    bonds = [o for o in objs if o.get("print") == "bonds"]
    clus = [o for o in objs if o.get("print") == "clusters"]
    en = [o for o in objs if o.get("print") == "energy"]
    if not bonds or not clus or len(en) < 2:
        return None
    b, c, e0, e1 = bonds[-1], clus[-1], en[0], en[-1]
    info = [o for o in objs if o.get("print") == "info"][-1]
    # Particles that left the open work-space were removed: they are debris (of unknown
    # cluster size; mostly singlets) and count in Olsson's fragmentation.
    lost = info["lost"]
    n = sum(c["sizes"]) + lost
    debris = c["debris"] + lost
    rest = c["sizes"][1:]
    big = sum(s for s in rest if s > 10)
    two = "theta" in run and "largest_by_agglomerate" in c  # two agglomerates (Lian ch. 7)
    ke0 = b["incident_kinetic"]
    d0, d1 = e0["dissipated"], e1["dissipated"]

    def share(k):
        return (d1[k] - d0[k]) / ke0 if ke0 > 0 else 0.0

    row = {
        "cycles": e1["cycle"] - e0["cycle"],
        "time_us": 1e6 * (e1["time"] - e0["time"]),
        "damage_ratio": b["damage_ratio"],
        "damage_ratio_prev": bonds[-2]["damage_ratio"] if len(bonds) > 1 else "",
        "new_ratio": b["new_ratio"],
        "bond_probability_z8": 8.0 / 12.0 * (1.0 - b["damage_ratio"] + b["new_ratio"]),
        "bond_probability": b["bond_probability"],
        "initial_bonds": b["initial"],
        "broken": b["broken"],
        "new": b["new"],
        "particles": n,
        "largest": c["largest"],
        "largest_pct": 100.0 * c["largest"] / n if n else 0.0,
        "debris": debris,
        "lost": lost,
        "debris_singlets_pct": 100.0 * c["singlets"] / debris if debris else 0.0,
        "debris_doublets_pct": 200.0 * c["doublets"] / debris if debris else 0.0,
        "debris_triplets_pct": 300.0 * c["triplets"] / debris if debris else 0.0,
        "debris_over10_pct": 100.0 * big / debris if debris else 0.0,
        "largest_debris_cluster": rest[0] if rest else 0,
        "fragmentation": c["fragmentation"] + lost,
        "fragmentation_pct": 100.0 * (c["fragmentation"] + lost) / n if n else 0.0,
        "n_fragments": max(len(c["fragments"]) - 1, 0),
        "singles_and_pairs": n - sum(c["fragments"]),
        "olsson_damage_ratio": b["damage_ratio"] - b["new_ratio"],
        "capture_ratio": c["capture_ratio"],
        # Both agglomerates (of n/2 particles each) mostly in the largest cluster (the same
        # rule as PRint CLUsters' `coalesced`, recomputed for logs of older binaries).
        "coalesced": (min(c["largest_by_agglomerate"][1:]) > n / 4) if two else "",
        "largest_from_1_2": "/".join(str(x) for x in c["largest_by_agglomerate"][1:]) if two else "",
        "fractal_dimension": c["fractal_dimension"],
        "delta": b["delta"],
        "incident_kinetic": ke0,
        "e_viscous": share("viscous"),
        "e_friction": share("friction"),
        "e_rupture": share("rupture"),
        "e_damping": share("damping_contact") + share("damping_mass"),
        "e_adhesion": share("adhesion"),
        "ke_left": e1["kinetic"] / ke0 if ke0 > 0 else 0.0,
        # Stored (strain + bridge) energy released during the run, e.g. by stretched bridges of
        # the prepared state that close: with it the dissipated shares can exceed 1 in all.
        "e_stored_released": (e0["strain"] + e0["bridge"] - e1["strain"] - e1["bridge"]) / ke0 if ke0 > 0 else 0.0,
        "residual_rel": e1["residual"] / e1["input"] if e1["input"] else 0.0,
    }
    return row


def progress(objs, run):
    """The rows of one run's printouts in time (tables with `progress`: every PRint BONds /
    CLUsters / ENErgy after the reference, e.g. the checks of lian_ch6_impact_rest.tru)."""
    bonds = [o for o in objs if o.get("print") == "bonds"]
    clus = [o for o in objs if o.get("print") == "clusters"]
    en = [o for o in objs if o.get("print") == "energy"]
    rows = []
    for b, c, e in zip(bonds, clus, en[1:]):
        ke0 = b["incident_kinetic"]
        # (The particles removed so far are not known at each printout: `lost` is the run's
        # final count, and the shares below are of the particles still present.)
        n = sum(c["sizes"])
        rows.append({
            **{k: v for k, v in run.items() if k not in ("state",)},
            "time_us": f"{1e6 * (e['time'] - en[0]['time']):.6g}",
            "damage_ratio": f"{b['damage_ratio']:.6g}",
            "new_ratio": f"{b['new_ratio']:.6g}",
            "largest": c["largest"],
            "present": n,
            "debris_present": c["debris"],
            "singlets": c["singlets"],
            "doublets": c["doublets"],
            "triplets": c["triplets"],
            "in_clusters_over10": sum(x for x in c["sizes"][1:] if x > 10),
            "largest_debris_cluster": c["sizes"][1] if len(c["sizes"]) > 1 else 0,
            "ke_left": f"{e['kinetic'] / ke0:.6g}" if ke0 > 0 else "",
            "dissipated": f"{(e['dissipated']['total'] - en[0]['dissipated']['total']) / ke0:.6g}" if ke0 > 0 else "",
        })
    return rows


# ---------------------------------------------------------------------------------------------
# Charts: the points go to a CSV file, `trubal chart` draws it (doc/plots.md).

CHARTS = os.path.join(ROOT, "target", "charts")


def chart(path, title, series, xlabel, ylabel, logx=False, refs=(), ours="", ref="", keys=None,
          hlines=(), hline_label="", points=False, extra=()):
    """Draws series [(key, [(x, y), ...])] solid with markers and refs [(key, [(x, y)])]
    dashed (a reference with a series' key takes its colour) to the PNG `path`, with `trubal
    chart`. The legend says "OURS KEY" and "REF KEY" (ours, ref: e.g. "trubal", "Olsson"; ""
    gives the key alone). keys: the order of the keys, so that a key keeps its colour in every
    chart of a table. The points are written to target/charts/NAME.csv first."""
    os.makedirs(CHARTS, exist_ok=True)
    data = os.path.join(CHARTS, os.path.splitext(os.path.basename(path))[0] + ".csv")
    with open(data, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["key", "x", "y", "reference"])
        for key, pts in series:
            w.writerows([key, repr(float(x)), repr(float(y)), ""] for x, y in pts)
        for key, pts in refs:
            w.writerows([key, repr(float(x)), "", repr(float(y))] for x, y in pts)
    keys = keys or list(dict.fromkeys([k for k, _ in series] + [k for k, _ in refs]))
    args = [trubal_binary(), "chart", data, "--x", "x", "--y", "y", "--by", "key", "--out", path,
            "--title", title, "--xlabel", xlabel, "--ylabel", ylabel, "--label", f"y={ours}"]
    if refs:
        args += ["--ref", "reference", "--label", f"reference={ref}"]
    for k in keys:
        args += ["--key", k]
    if logx:
        args.append("--logx")
    if points:
        args.append("--points")
    if hlines:
        args += ["--hline", ",".join(repr(float(v)) for v in hlines), "--hline-label", hline_label]
    args += list(extra)
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
    print("wrote", path)


# The legend's words for the table's group columns, the axes' names with units.
GROUP_NAMES = {"eta": "η", "gamma": "Γ", "v": "v", "smin": "S_min"}
AXES = {
    "v": "impact velocity v [m/s]",
    "theta": "impact angle θ from the normal [°]",
    "damage_ratio": "damage ratio D_r",
    "fragmentation_pct": "fragmentation [%]",
    "e_viscous": "viscous dissipation [J]",
}


def group_key(group, values):
    """The legend's text of one group of runs: "η = 0.01, Γ = 0.025", "0.1 % liquid", "dry"."""
    parts = []
    for g, v in zip(group, values):
        if g == "liquid":
            parts.append("dry" if v == "dry" else f"{v} % liquid")
        elif g == "v":
            parts.append(f"v = {v} m/s")
        else:
            parts.append(f"{GROUP_NAMES.get(g, g)} = {v}")
    return ", ".join(parts)


def lian_fit(vo, grid, vmax):
    """Lian's fit D_r = log10(v / v_o) from v_o (D_r = 0) to his fastest run of the series
    (vmax, cases-lian1994.md Tables 6.1 and 7.1): not beyond his data."""
    return [(vo, 0.0)] + [(v, math.log10(v / vo)) for v in sorted(set(grid) | {vmax}) if vo < v <= vmax]


def lian_cos2(d_o):
    """Lian's oblique law D_r = D_o cos²Θ (eq. 7.4) from his normal-impact D_o, 0-85°."""
    return (f"{d_o:.3f} cos²θ", [(t, d_o * math.cos(math.radians(t)) ** 2) for t in range(0, 90, 5)])


# The theses' results drawn dashed, by the key of the group of our runs they belong to
# ("/".join of the group's values): Lian's D_r = log10(v / v_o), Olsson's Table 4:1.
LIAN6_GRID = (0.3, 0.5, 0.7, 1, 1.5, 2, 3, 5, 8)
LIAN7_GRID = (0.7, 1, 1.2, 1.5, 2, 3, 4, 5, 6, 7, 10, 15)
REFERENCES = {
    "lian6": [(eta, lian_fit(vo, LIAN6_GRID, vmax)) for eta, vo, vmax in (("0", 0.35, 2.0), ("0.01", 0.44, 3.0),
                                                                          ("0.1", 0.98, 8.0))],
    "lian7": [(key, lian_fit(vo, LIAN7_GRID, vmax))
              for key, vo, vmax in (("0.001/0.025", 0.73, 2.0), ("0.01/0.025", 0.91, 5.0), ("0.01/0.05", 1.19, 5.0),
                                   ("0.1/0.025", 2.29, 15.0))],
    # D_o = log10(v / v_o) of his normal fits: 2 m/s, eta = 0.01 (0.342); 5 m/s, eta = 0.01
    # (0.740); 2 m/s, eta = 0.001 (0.438).
    "lian7_oblique": [lian_cos2(0.342)],
    "lian7_oblique5": [lian_cos2(0.740)],
    "lian7_oblique001": [lian_cos2(0.438)],
    "olsson": [
        ("dry", [(0.5, 0.025), (1, 2.6), (1.5, 27.3), (2, 38.5), (2.5, 65.1), (3, 69.5)]),
        ("0.01", [(1.5, 0), (2, 0.2), (2.5, 0.4), (3, 3.1), (5.2, 24.6)]),
        ("0.1", [(2, 0), (2.5, 0.15), (3, 1.4), (5.2, 17.0)]),
        ("1", [(2.5, 0), (3, 0.05), (5.2, 6.5)]),
    ],
}
REFERENCES["lian6_debris"] = REFERENCES["lian6_small"] = REFERENCES["lian6"]
REFERENCES["lian7_lianprep"] = REFERENCES["lian7"]
REFERENCES["lian7_oblique_lianprep"] = REFERENCES["lian7_oblique"]
REFERENCES["olsson_long"] = REFERENCES["olsson"][:1]
REFERENCES["olsson_dry"] = REFERENCES["olsson"][:1]
REFERENCES["olsson_regime"] = REFERENCES["olsson_liggghts"] = REFERENCES["olsson"]
REFERENCES["olsson_long_liggghts"] = REFERENCES["olsson"][:1]
REF_NAMES = {"lian": "Lian (1994)", "olsson": "Olsson (2017)"}
# The order of the groups (their colours), the same in every chart of a table.
KEY_ORDER = {"eta": ["0", "0.001", "0.01", "0.1"], "liquid": ["dry", "0.01", "0.1", "1"]}


def number_or_zero(v):
    try:
        return float(v)
    except ValueError:
        return 0.0


def draw_table(name, t, work):
    """The chart of table `name` from doc/data/NAME.csv: to doc/data/NAME.png if the docs show
    it (`figure` in TABLES), else to WORK/NAME.png."""
    with open(os.path.join(DATA, name + ".csv")) as fh:
        rows = list(csv.DictReader(fh))
    group = t["group"] if isinstance(t["group"], tuple) else (t["group"],)
    ours = {}
    for row in rows:
        try:
            x, y = float(row[t["x"]]), float(row[t["y"]])
        except (ValueError, KeyError):
            continue
        ours.setdefault(tuple(row[g] for g in group), []).append((x, y))
    # A reference's key is a group's values joined by "/" (its colour is the group's), or a
    # text of its own.
    refs = [(tuple(k.split("/")), pts) for k, pts in REFERENCES.get(name, [])]
    order = KEY_ORDER.get(group[0], [])

    def position(k):
        return (order.index(k[0]) if k[0] in order else len(order), [number_or_zero(v) for v in k])

    def text(k):
        return group_key(group, k) if len(k) == len(group) else "/".join(k)

    groups = sorted(set(ours) | {k for k, _ in refs if len(k) == len(group)}, key=position)
    keys = [text(k) for k in groups] + [text(k) for k, _ in refs if len(k) != len(group)]
    png = os.path.join(DATA if t.get("figure") else work, name + ".png")
    chart(png, t["title"], [(text(k), ours[k]) for k in groups if k in ours],
          AXES.get(t["x"], t["x"]), AXES.get(t["y"], t["y"]), t.get("logx", False),
          [(text(k), pts) for k, pts in refs], ours="trubal",
          ref=REF_NAMES["olsson" if name.startswith("olsson") else "lian"], keys=keys)
    return png


def copy_pictures(name, t, work, runs, exe):
    """The pictures a table's run drew (`pictures` in TABLES: PREFIX and {ITEMS: NAME}):
    PLot's last plot_cNNNNNNNN_ITEMS.png of each finished run that asked for them
    (`pictures` = 1) copied to doc/img/PREFIX_NAME.png, and doc/data/TABLE_pictures.txt naming
    the run, its files and their cycle (with its provenance)."""
    prefix, items = t["pictures"]
    lines = []
    for r in runs:
        if r.get("pictures") != "1" or finished(work, t["script"], r) is None:
            continue
        rundir = os.path.join(sweep_dir(work, t["script"]), "runs", run_name(r))
        for item, suffix in items.items():
            made = sorted(f for f in os.listdir(rundir)
                          if re.fullmatch(r"plot_c\d{8}_" + item + r"\.png", f))
            if not made:
                print(f"  (no {item} picture in {rundir})")
                continue
            dest = f"{prefix}_{suffix}.png"
            shutil.copyfile(os.path.join(rundir, made[-1]), os.path.join(ROOT, "doc", "img", dest))
            lines.append(f"doc/img/{dest}: {made[-1]} of run {run_name(r)} ({t['script']})")
    if lines:
        out = os.path.join(DATA, name + "_pictures.txt")
        with open(out, "w") as f:
            f.write("\n".join(lines) + "\n")
        provenance.record(out, exe)
        print("wrote", out)


def fit_thresholds(series, lo=0.02, hi=0.95):
    """Lian's D_r = log10(v / v_o) per series: v_o with the slope fixed at 1 (mean of
    log10 v - D_r), and a free least-squares line D_r = s log10(v / v_o'), over the points
    with lo < D_r < hi."""
    lines = []
    for label, pts in sorted(series.items()):
        p = [(math.log10(v), d) for v, d in pts if lo < d < hi]
        if not p:
            lines.append(f"{label}: no point with {lo} < D_r < {hi}")
            continue
        vo = 10 ** (sum(x - d for x, d in p) / len(p))
        txt = f"{label}: v_o = {vo:.3f} m/s (slope 1, {len(p)} points)"
        if len(p) > 1:
            mx = sum(x for x, _ in p) / len(p)
            md = sum(d for _, d in p) / len(p)
            sxx = sum((x - mx) ** 2 for x, _ in p)
            slope = sum((x - mx) * (d - md) for x, d in p) / sxx
            txt += f"; free fit: slope {slope:.3f}, v_o = {10 ** (mx - md / slope):.3f} m/s"
        lines.append(txt)
    return lines


# ---------------------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("table", nargs="?")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--work")
    ap.add_argument("--only", action="append", default=[],
                    help="key=value (run only matching runs; the CSV still gets every run finished in the work directory)")
    ap.add_argument("--force", action="store_true")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--plot-only", action="store_true", help="only collect the logs and plot")
    ap.add_argument("--chart-only", action="store_true",
                    help="only draw the chart again from doc/data/TABLE.csv (no run, no collection)")
    a = ap.parse_args()
    if a.list or not a.table:
        for name, t in TABLES.items():
            print(f"{name}: {len(t['runs'])} runs of {t['script']}")
            if a.list:
                for r in t["runs"]:
                    print("   ", run_name(r))
        return
    t = TABLES[a.table]
    # Absolute: the derived --set values run helper scripts with the work directory as cwd.
    work = os.path.abspath(a.work or os.path.join(ROOT, "target", "experiments", t.get("work", a.table)))
    if a.chart_only:
        os.makedirs(work, exist_ok=True)
        draw_table(a.table, t, work)
        return
    os.makedirs(os.path.join(work, "logs"), exist_ok=True)
    os.makedirs(DATA, exist_ok=True)
    exe = trubal_binary()
    runs = [r for r in t["runs"] if all(str(r.get(k)) == v for k, v in (o.split("=", 1) for o in a.only))]

    if not a.plot_only:
        need = needed_states(t, runs)
        for script, sets, state in t["prepare"]:
            if os.path.exists(os.path.join(work, state)) and not a.force:
                continue
            if need is not None and state not in need:
                continue  # (no selected run starts from it)
            log = os.path.join(work, "logs", "prepare_" + state + ".log")
            print(f"preparing {state} ({script}) ...", flush=True)
            rc, dt = trubal(exe, script, sets, work, log)
            print(f"  {state}: exit {rc}, {dt:.0f} s", flush=True)
            if rc != 0:
                sys.exit(f"preparation failed, see {log}")
        if a.force:
            for r in runs:
                shutil.rmtree(os.path.join(sweep_dir(work, t["script"]), "runs", run_name(r)), ignore_errors=True)
                log = os.path.join(work, "logs", run_name(r) + ".log")
                if os.path.exists(log):
                    os.remove(log)
        cache = {}
        todo = [(r, derive(t.get("derive"), exe, work, r, cache)) for r in runs
                if finished(work, t["script"], r) is None]
        print(f"{a.table}: {len(todo)} runs to do of {len(runs)}, {a.jobs} at a time", flush=True)
        if todo:
            run_sweep(exe, work, t["script"], todo, a.jobs)

    # Collect.
    states = [st for _, _, st in t["prepare"] if os.path.exists(os.path.join(work, st))]
    if states:
        with open(os.path.join(DATA, a.table + "_states.txt"), "w") as f:
            for state in states:
                line = state_summary(exe, work, state)
                print(line, flush=True)
                f.write(line + "\n")
        provenance.record(os.path.join(DATA, a.table + "_states.txt"), exe)
    rows = []
    steps = []
    # The table's rows are every run finished in the work directory, not only those `--only`
    # selected this time: a run of one row must not drop the others from doc/data.
    selected = [run_name(r) for r in runs]
    for r in t["runs"]:
        got = finished(work, t["script"], r)
        if got is None and run_name(r) not in selected:
            continue
        if t.get("progress"):
            # A run still going (or stopped) gives its checks so far, marked unfinished.
            objs = got[0] if got else json_lines(os.path.join(sweep_dir(work, t["script"]), "runs",
                                                              run_name(r), "output.jsonl"))
            steps += [dict(row, finished="yes" if got else "no") for row in progress(objs, r)]
        m = measures(got[0], r) if got else None
        if m is None:
            print(f"  (no result for {run_name(r)})")
            continue
        row = {k: v for k, v in r.items() if k not in ("state",)}
        row.update(m)
        row["wall_s"] = got[1]
        rows.append(row)
    if steps:
        out = os.path.join(DATA, a.table + "_progress.csv")
        with open(out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(steps[0]))
            w.writeheader()
            w.writerows(steps)
        provenance.record(out, exe, runs=len(rows), of_runs=len(t["runs"]))
        print("wrote", out)
    if t.get("pictures"):
        copy_pictures(a.table, t, work, runs, exe)
    if not rows:
        return
    keys = []
    for row in rows:
        for k in row:
            if k not in keys:
                keys.append(k)
    out = os.path.join(DATA, a.table + ".csv")
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
    provenance.record(out, exe, runs=len(rows), of_runs=len(t["runs"]))
    print("wrote", out)
    group = t["group"] if isinstance(t["group"], tuple) else (t["group"],)
    series = {}
    for row in rows:
        label = "/".join(str(row[g]) for g in group)
        series.setdefault(label, []).append((float(row[t["x"]]), float(row[t["y"]])))
    if t["x"] == "v" and t["y"] == "damage_ratio" and t.get("fit", True):
        fits = fit_thresholds(series)
        with open(os.path.join(DATA, a.table + "_fit.txt"), "w") as f:
            for line in fits:
                print(line)
                f.write(line + "\n")
        provenance.record(os.path.join(DATA, a.table + "_fit.txt"), exe)
    draw_table(a.table, t, work)


if __name__ == "__main__":
    main()
