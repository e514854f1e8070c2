#!/bin/bash
# Cost per time step of trubal against N (settling beds, S1 material and box).
# Not part of `cargo test`. See scripts/bench/README.md and scale2tru.py.
#
# usage: scripts/bench/scaling.sh
# knobs (environment):
#   OUT=dir                    (default ./bench-out); results in OUT/scaling.tsv
#   REPS=3  REP_START=1
#   SCALE_SIZES="1000 10000 100000 1000000"
#   SCALE_STEPS=100            time steps per run (the first Cycle includes the first
#                              contact search, as in every run)
#   SCALE_KINDS="loose lattice"
#   QUIET_CORES=, MAX_WAIT=600, RETRIES=2, TRUBAL=path   as in run_bench.sh
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
OUT=${OUT:-$PWD/bench-out}
REPS=${REPS:-3}
REP_START=${REP_START:-1}
SCALE_SIZES=${SCALE_SIZES:-"1000 10000 100000 1000000"}
SCALE_STEPS=${SCALE_STEPS:-100}
SCALE_KINDS=${SCALE_KINDS:-"loose lattice"}
MAX_WAIT=${MAX_WAIT:-600}
TRUBAL=${TRUBAL:-$root/target/release/trubal}
[ -x "$TRUBAL" ] || { echo "no trubal binary at $TRUBAL: run 'cargo build --release' first" >&2; exit 1; }
TRUBAL=$(cd "$(dirname "$TRUBAL")" && pwd)/$(basename "$TRUBAL")
mkdir -p "$OUT/logs"
OUT=$(cd "$OUT" && pwd)
RES="$OUT/scaling.tsv"
[ -f "$RES" ] || printf "scene\tcode\tN\tpar\tsteps\trep\twall_s\tloop_s\tcpu_s\tmaxrss_kB\tcontacts\textra\tloadavg_before\tcpu_pct\tloop_cpu_pct\n" > "$RES"
. "$here/lib.sh"

REP_END=$((REP_START + REPS - 1))
for rep in $(seq "$REP_START" "$REP_END"); do
  echo "=== scaling repetition $rep ($REP_START..$REP_END)  $(date -u +%H:%M:%S)"
  for kind in $SCALE_KINDS; do
    for n in $SCALE_SIZES; do
      deck="scale_${kind}_$n.tru"
      nn=$(python3 "$here/scale2tru.py" "$kind" "$n" "$SCALE_STEPS" "$OUT/$deck" | sed -n 's/^N=\([0-9]*\).*/\1/p')
      (cd "$OUT" && run_timed "$kind" trubal "$nn" "t${SCALE_THREADS:-1}" "$SCALE_STEPS" "$rep" "$OUT/logs/scale_${kind}_N${n}_r$rep" "$TRUBAL" --threads "${SCALE_THREADS:-1}" "$deck")
    done
  done
done
echo
python3 "$here/summarize.py" "$RES"
