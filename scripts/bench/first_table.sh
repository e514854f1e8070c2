#!/bin/bash
# doc/performance.md's first table in one command (issue 50): the harness on S1 10k and 50k,
# S2 and the moist agglomerate (one and two threads, idle and with a busy loop on the other
# core, against LIGGGHTS and LAMMPS), the S1 run at equal error, then the table.
# The accuracy ladders of S2 and moist (equal_error_agg.py) are read from
# doc/data/bench/equal_error_agg.json when present (they time nothing: rerun them apart).
# About 20 minutes on the project machine; run it on a quiet machine.
#
# usage: scripts/bench/first_table.sh [OUT]     (OUT: work folder, default ./bench-out)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
OUT=${1:-$PWD/bench-out}
OUT=$OUT REPS=${REPS:-3} BUSY=1 S1_STEPS=5000 S1_STEPS_50000=3000 S2_STEPS=4000 \
  "$here/run_bench.sh"
python3 "$here/equal_error.py" --bed "$OUT" --reps "${EQ_REPS:-2}"
python3 "$here/first_table.py" "$OUT/results.tsv"
