#!/bin/bash
# doc/performance.md's first table in one command (issue 50): the harness on S1 10k and 50k,
# S2 and the moist agglomerate (one and two threads, idle and with a busy loop on the other
# core, against LIGGGHTS and LAMMPS), the S1 run at equal error, then the table.
# The agglomerates at equal error (equal_error_agg_speed.py) take their steps from the
# accuracy ladders of equal_error_agg.py (which time nothing: rerun it apart when a law moves).
# About 30 minutes on the project machine; run it on a quiet machine.
#
# usage: scripts/bench/first_table.sh [OUT]     (OUT: work folder, default ./bench-out)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
OUT=${1:-$PWD/bench-out}
# The binary every part times (the harness reads TRUBAL too; default: this tree's release build).
TRUBAL=${TRUBAL:-$(cd "$here/../.." && pwd)/target/release/trubal}
export TRUBAL
OUT=$OUT REPS=${REPS:-3} BUSY=1 S1_STEPS=5000 S1_STEPS_50000=3000 S2_STEPS=4000 \
  "$here/run_bench.sh"
python3 "$here/equal_error.py" --trubal "$TRUBAL" --bed "$OUT" --reps "${EQ_REPS:-2}"
python3 "$here/equal_error_agg_speed.py" --trubal "$TRUBAL" --bed "$OUT" --reps "${EQ_REPS:-2}"
python3 "$here/first_table.py" "$OUT/results.tsv"
