# Shared by run_bench.sh and scaling.sh (sourced): wait_quiet, run_one, run_timed.
# Expects RES (the results file); optional QUIET_CORES, MAX_WAIT, RETRIES.

# Idle cores of the machine over the next 5 s (from /proc/stat).
idle_cores() {
  local a b
  a=$(awk '/^cpu /{print $5+$6, $2+$3+$4+$5+$6+$7+$8+$9}' /proc/stat); sleep 5
  b=$(awk '/^cpu /{print $5+$6, $2+$3+$4+$5+$6+$7+$8+$9}' /proc/stat)
  awk -v a="$a" -v b="$b" -v n="$(nproc)" 'BEGIN{split(a,x," "); split(b,y," "); t=y[2]-x[2]; if(t<=0){print n; exit} printf "%.2f", n*(y[1]-x[1])/t}'
}

# With QUIET_CORES set (e.g. 1): wait, up to MAX_WAIT s, until that many cores are idle.
wait_quiet() {
  [ -z "${QUIET_CORES:-}" ] && return
  local t=0
  while [ "$t" -lt "${MAX_WAIT:-600}" ]; do
    awk -v i="$(idle_cores)" -v q="$QUIET_CORES" 'BEGIN{exit !(i >= q)}' && return
    t=$((t + 5))
  done
}

# run_one SCENE CODE N PAR STEPS REP LOGBASE cmd...   (in the current directory)
# Wall time, CPU time, peak RSS and CPU share from /usr/bin/time -v; the load
# average before the run; the code's own loop time: "Loop time of" (LAMMPS,
# LIGGGHTS: the last one), TRUBAL_TIMING cycle_wall_s (trubal, summed over Cycles).
run_one() {
  local scene=$1 code=$2 n=$3 par=$4 steps=$5 rep=$6 log=$7; shift 7
  wait_quiet
  local load; load=$(cut -d' ' -f1 /proc/loadavg)
  TRUBAL_TIMING=1 /usr/bin/time -v -o "$log.time" "$@" > "$log.out" 2>&1
  local rc=$?
  local wall rss cpu cpus loop loopcpu="" contacts extra=""
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/{n=split($2,a,":"); s=0; for(i=1;i<=n;i++) s=s*60+a[i]; print s}' "$log.time")
  rss=$(awk -F': ' '/Maximum resident set size/{print $2}' "$log.time")
  cpu=$(awk -F': ' '/Percent of CPU this job got/{sub("%","",$2); print $2}' "$log.time")
  cpus=$(awk -F': ' '/User time/{u=$2} /System time/{s=$2} END{print u+s}' "$log.time")
  if [ "$code" = trubal ]; then
    loop=$(awk '/^TRUBAL_TIMING/{for(i=1;i<=NF;i++) if($i ~ /^cycle_wall_s=/){sub("cycle_wall_s=","",$i); s+=$i; k=1}} END{if(k) printf "%.6f", s}' "$log.out")
    # CPU share of the time steps alone (the process share includes start-up)
    loopcpu=$(awk '/^TRUBAL_TIMING/{for(i=1;i<=NF;i++){if($i ~ /^cycle_wall_s=/){sub("cycle_wall_s=","",$i); w+=$i} if($i ~ /^cycle_cpu_s=/){sub("cycle_cpu_s=","",$i); c+=$i}}} END{if(w>0) printf "%.0f", 100*c/w}' "$log.out")
    contacts=$(grep -E "^contacts [0-9]+ particle-particle" "$log.out" | tail -1 | awk '{print $2}')
    local lost; lost=$(grep -E "lost through open sides" "$log.out" | tail -1 | sed -n 's/.*open sides \([0-9]*\).*/\1/p')
    [ -n "$lost" ] && [ "$lost" != 0 ] && extra="lost=$lost"
    local br; br=$(grep -E "^liquid bridges" "$log.out" | tail -1 | awk '{print $3}')
    [ -n "$br" ] && extra="$extra bridges=$br"
    if [ "$rc" -eq 0 ] && grep -q "error:" "$log.out"; then rc=98; fi
  else
    loop=$(grep -E "^Loop time of" "$log.out" | tail -1 | awk '{print $4}')
    local res; res=$(grep -m1 PEER_RESULT "$log.out")
    contacts=$(echo "$res" | sed -n 's/.*contacts_pp=\([0-9]*\).*/\1/p')
    [ -z "$contacts" ] && contacts=$(echo "$res" | sed -n 's/.*contacts_overlap_end=\([0-9]*\).*/\1/p')
  fi
  [ "$rc" -ne 0 ] && extra="$extra FAILED(rc=$rc)"
  [ -z "$loopcpu" ] && loopcpu=$cpu
  printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n" "$scene" "$code" "$n" "$par" "$steps" "$rep" \
    "${wall:-nan}" "${loop:-nan}" "${cpus:-nan}" "${rss:-nan}" "${contacts:-nan}" "${extra# }" "$load" "${cpu:-nan}" "${loopcpu:-nan}" >> "$RES"
  echo "  $scene $code N=$n par=$par steps=$steps rep=$rep wall=${wall}s loop=${loop}s cpu=${cpu}% loop_cpu=${loopcpu}% rss=${rss}kB contacts=${contacts} load=$load ${extra# }"
  # status 3: the run got less than 90 % of the cores it asked for (summarize.py drops it)
  local want=1; case $par in np*) want=${par#np} ;; esac
  awk -v c="${loopcpu:-0}" -v w="$want" 'BEGIN{exit !(c < 90 * w)}' && return 3
  return 0
}

# run_timed: run_one, repeated up to RETRIES (default 2) more times while the run got
# < 90 % CPU; every attempt is recorded (the disturbed ones are dropped by summarize.py).
run_timed() {
  local k=0 a1=$1 a2=$2 a3=$3 a4=$4 a5=$5 a6=$6 log=$7; shift 7
  while :; do
    run_one "$a1" "$a2" "$a3" "$a4" "$a5" "$a6" "$log$([ $k -gt 0 ] && echo "_a$k")" "$@"
    [ $? -ne 3 ] && return
    k=$((k + 1)); [ "$k" -gt "${RETRIES:-2}" ] && return
    echo "    (< 90 % CPU: repeated, attempt $((k + 1)))"
  done
}

