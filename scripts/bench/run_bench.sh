#!/bin/bash
# trubal vs. peer DEM codes (LIGGGHTS, LAMMPS) on the same scenes, in one run,
# alternating the codes within every repetition (trubal, peer, trubal's next
# scene, peer, ...), so that a change in machine load hits both alike.
# Not part of `cargo test`. See scripts/bench/README.md.
#
# usage: scripts/bench/run_bench.sh
# knobs (environment):
#   OUT=dir              work/output folder (default: ./bench-out); results in OUT/results.tsv
#   REPS=3               repetitions (medians reported); REP_START=1 first repetition number
#   SCENES="s1 s2 moist" which scenes
#   S1_SIZES="10000 50000"  S1_STEPS=20000  S1_STEPS_<N>=... per-size override (e.g. S1_STEPS_50000=10000)
#   S2_STEPS=20000       agglomerate scenes (s2 = JKR, moist = bridges + dry reference)
#   PEERS="liggghts lammps"  peers to run when installed (missing ones are skipped)
#   PEER_RANKS="1"       MPI ranks for the peers ("1 2" adds 2-rank runs)
#   TRUBAL_THREADS="1 2" trubal thread counts (--threads; par label t1, t2)
#   BUSY=1               also run trubal at each thread count while a busy loop holds one
#                        core (another program on a shared machine; par label t1busy, t2busy)
#   TANG=noslip          trubal's tangential law (noslip = the peers' Mindlin no-slip + Coulomb; md)
#   MOIST_LIGGGHTS=1     also run the LIGGGHTS easo/capillary/viscous deck (if present)
#   QUIET_CORES=         if set (e.g. 1), wait before each run (up to MAX_WAIT=600 s) until
#                        that many cores are idle (measured over 5 s)
#   RETRIES=2            repeat a run that got < 90 % CPU up to this many times (all
#                        attempts are recorded; summarize.py drops the disturbed ones)
#   TRUBAL=path          the trubal binary (default: target/release/trubal of this tree)
#   PEERS_DIR=/work/shared/peers   the peers' decks and generators
# Requires: python3, /usr/bin/time (package `time`); peers from
#   apt-get install -y --no-install-recommends liggghts lammps openmpi-bin time
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
OUT=${OUT:-$PWD/bench-out}
REPS=${REPS:-3}
REP_START=${REP_START:-1}
SCENES=${SCENES:-"s1 s2 moist"}
S1_SIZES=${S1_SIZES:-"10000 50000"}
S1_STEPS=${S1_STEPS:-20000}
S2_STEPS=${S2_STEPS:-20000}
PEERS=${PEERS:-"liggghts lammps"}
PEER_RANKS=${PEER_RANKS:-"1"}
TRUBAL_THREADS=${TRUBAL_THREADS:-"1 2"}
BUSY=${BUSY:-0}
TANG=${TANG:-noslip}
MOIST_LIGGGHTS=${MOIST_LIGGGHTS:-1}
MAX_WAIT=${MAX_WAIT:-600}
TRUBAL=${TRUBAL:-$root/target/release/trubal}
PEERS_DIR=${PEERS_DIR:-/work/shared/peers}
MPIRUN="mpirun --allow-run-as-root --mca btl_vader_single_copy_mechanism none -np"

[ -x "$TRUBAL" ] || { echo "no trubal binary at $TRUBAL: run 'cargo build --release' first" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "/usr/bin/time is missing: apt-get install time" >&2; exit 1; }
TRUBAL=$(cd "$(dirname "$TRUBAL")" && pwd)/$(basename "$TRUBAL")
mkdir -p "$OUT/logs"
OUT=$(cd "$OUT" && pwd)
RES="$OUT/results.tsv"
[ -f "$RES" ] || printf "scene\tcode\tN\tpar\tsteps\trep\twall_s\tloop_s\tcpu_s\tmaxrss_kB\tcontacts\textra\tloadavg_before\tcpu_pct\tloop_cpu_pct\n" > "$RES"

have() {  # have PEER: the peer's binary is installed and wanted
  case " $PEERS " in *" $1 "*) ;; *) return 1 ;; esac
  case $1 in liggghts) command -v liggghts >/dev/null ;; lammps) command -v lmp >/dev/null ;; *) return 1 ;; esac
}
for p in $PEERS; do have "$p" || echo "note: peer $p is not installed: its runs are skipped"; done

. "$here/lib.sh"

peer_pre() { if [ "$1" = 1 ]; then echo ""; else echo "$MPIRUN $1"; fi; }

# ---------------------------------------------------------------- inputs
case " $SCENES " in *" s1 "*)
  for n in $S1_SIZES; do
    [ -f "$OUT/bed$n.data" ] || python3 "$PEERS_DIR/s1_settle/gen_bed.py" "$n" "$OUT/bed$n.data" 12345
    # trubal: CReate the bed once and save it (CReate is O(N) per particle); timed runs RESTart it.
    if [ ! -f "$OUT/bed$n.sav" ] || [ "$TRUBAL" -nt "$OUT/bed$n.sav" ]; then
      echo "building trubal checkpoint bed$n.sav (N=$n, CReate lines)"
      python3 "$here/bed2tru.py" "$OUT/bed$n.data" "$OUT/build_bed$n.tru" 0 "bed$n.sav"
      (cd "$OUT" && /usr/bin/time -f "  build: %e s wall, %M kB" "$TRUBAL" build_bed$n.tru > "$OUT/logs/build_bed$n.out" 2>&1) \
        || { echo "building bed$n.sav failed: see $OUT/logs/build_bed$n.out" >&2; exit 1; }
      tail -1 "$OUT/logs/build_bed$n.out"
    fi
  done
;; esac
case " $SCENES " in *" s2 "*|*" moist "*)
  for v in jkr dry moist; do
    python3 "$here/agg2tru.py" "$v" "$S2_STEPS" "$OUT/agg_$v.tru" > "$OUT/agg_$v.info"
    # The peers' tangential law is Mindlin's no-slip spring with a Coulomb cap: ours is
    # NOSLIP (TANG=mdr: our default, the exact Hertz-Mindlin law; md: Mindlin-Deresiewicz).
    sed -i "s/^fraction 0.2$/fraction 0.2\nset tangential $TANG/" "$OUT/agg_$v.tru"
  done
  if have lammps; then
    agg_info=$(python3 "$PEERS_DIR/s2_agglomerate/gen_agglomerate.py" "$OUT/agg.data")
    zbot=$(echo "$agg_info" | sed -n 's/.*zbottom=\([-0-9.e+]*\).*/\1/p')
    zwall=$(python3 -c "print('%.15e' % ($zbot - 1.0e-6))")
  fi
;; esac

# trubal_runs SCENE N STEPS REP LOGNAME DECK: the deck at every thread count of TRUBAL_THREADS
# (and, with BUSY=1, again at each while a busy loop holds one core).
trubal_runs() {
  local scene=$1 n=$2 steps=$3 rep=$4 name=$5 deck=$6 t busy
  for t in $TRUBAL_THREADS; do
    (cd "$OUT" && run_timed "$scene" trubal "$n" "t$t" "$steps" "$rep" "$OUT/logs/${name}_t${t}_r$rep" \
      "$TRUBAL" --threads "$t" "$deck")
  done
  [ "$BUSY" = 1 ] || return 0
  for t in $TRUBAL_THREADS; do
    sh -c 'while :; do :; done' & busy=$!
    (cd "$OUT" && run_timed "$scene" trubal "$n" "t${t}busy" "$steps" "$rep" "$OUT/logs/${name}_t${t}busy_r$rep" \
      "$TRUBAL" --threads "$t" "$deck")
    kill "$busy"; wait "$busy" 2>/dev/null
  done
}

REP_END=$((REP_START + REPS - 1))
for rep in $(seq "$REP_START" "$REP_END"); do
  echo "=== repetition $rep ($REP_START..$REP_END)  $(date -u +%H:%M:%S)"
  case " $SCENES " in *" s1 "*)
    for n in $S1_SIZES; do
      v="S1_STEPS_$n"; steps=${!v:-$S1_STEPS}
      d="$OUT/s1_N${n}_rep$rep"; mkdir -p "$d"
      printf "restart bed%s.sav\nset tangential %s\ncycle %s\nprint info\n" "$n" "$TANG" "$steps" > "$OUT/run_bed${n}_$steps.tru"
      trubal_runs s1 "$n" "$steps" "$rep" "s1_trubal_N${n}" "run_bed${n}_$steps.tru"
      for np in $PEER_RANKS; do
        pre=$(peer_pre "$np")
        have liggghts && (cd "$d" && run_timed s1 liggghts "$n" "np$np" "$steps" "$rep" "$OUT/logs/s1_liggghts_N${n}_np${np}_r$rep" \
          $pre liggghts -in "$PEERS_DIR/s1_settle/in.settle.liggghts" -var data "$OUT/bed$n.data" -var nsteps "$steps" -var px "$np" -log none)
        have lammps && (cd "$d" && run_timed s1 lammps "$n" "np$np" "$steps" "$rep" "$OUT/logs/s1_lammps_N${n}_np${np}_r$rep" \
          $pre lmp -in "$PEERS_DIR/s1_settle/in.settle.lammps" -var data "$OUT/bed$n.data" -var nsteps "$steps" -var px "$np" -log none -nocite)
      done
    done
  ;; esac
  case " $SCENES " in *" s2 "*)
    n=$(sed -n 's/^N=\([0-9]*\).*/\1/p' "$OUT/agg_jkr.info")
    trubal_runs s2 "$n" "$S2_STEPS" "$rep" s2_trubal agg_jkr.tru
    if have lammps; then
      n0=$(sed -n 's/.*N=\([0-9]*\).*/\1/p' <<< "$agg_info")
      for np in $PEER_RANKS; do
        d="$OUT/s2_np${np}_rep$rep"; mkdir -p "$d"
        pre=$(peer_pre "$np")
        (cd "$d" && run_timed s2 lammps "$n0" "np$np" "$S2_STEPS" "$rep" "$OUT/logs/s2_lammps_np${np}_r$rep" \
          $pre lmp -in "$PEERS_DIR/s2_agglomerate/in.agglomerate.lammps" -var data "$OUT/agg.data" -var zwall "$zwall" \
          -var nsteps "$S2_STEPS" -var px "$np" -var vimp 1.0 -var outdir "$d" -log none -nocite)
      done
    fi
  ;; esac
  case " $SCENES " in *" moist "*)
    n=$(sed -n 's/^N=\([0-9]*\).*/\1/p' "$OUT/agg_dry.info")
    trubal_runs dry "$n" "$S2_STEPS" "$rep" dry_trubal agg_dry.tru
    if [ "$MOIST_LIGGGHTS" = 1 ] && have liggghts && [ -f "$here/in.agglomerate_moist.liggghts" ]; then
      d="$OUT/moist_lig_rep$rep"; mkdir -p "$d"
      python3 "$here/agg2tru.py" data "$OUT/agg_lig.data" > "$OUT/agg_lig.info"
      zw=$(sed -n 's/.*zwall=\([-0-9.e+]*\).*/\1/p' "$OUT/agg_lig.info")
      for wet in 0 1; do
        sc=dry; [ "$wet" = 1 ] && sc=moist
        (cd "$d" && run_timed "$sc" liggghts "$n" np1 "$S2_STEPS" "$rep" "$OUT/logs/${sc}_liggghts_r$rep" \
          liggghts -in "$here/in.agglomerate_moist.liggghts" -var data "$OUT/agg_lig.data" -var zwall "$zw" \
          -var nsteps "$S2_STEPS" -var wet "$wet" -log none)
      done
    fi
    trubal_runs moist "$n" "$S2_STEPS" "$rep" moist_trubal agg_moist.tru
  ;; esac
done

echo
python3 "$here/summarize.py" "$RES"
