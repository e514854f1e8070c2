#!/usr/bin/env bash
# Two trubal builds at the same time, one thread each, pinned to CPU 0 and CPU 1 (swapped
# every repetition), on the same command file: the paired ratio B/A of their `Cycle` times.
#
#   scripts/bench/side_by_side.sh A B DECK [REPS]
#
# A and B are trubal binaries, DECK a command file (paths in it relative to the current
# directory). Both runs of a repetition share the machine's load, its L3 cache and its
# memory bandwidth, so a change of the host's load hits both alike: on the project's
# shared 2-core machine the same binary against itself gives medians within 1 % (range
# about +-8 %), where runs one after the other drift by 10-15 %. Compares one-thread
# builds only (two-thread runs need both cores: alternate them with REPS of run_bench.sh).
# Prints each repetition's times (s) and the median and range of B/A.
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 A B DECK [REPS]" >&2
    exit 2
fi
A=$1
B=$2
DECK=$3
REPS=${4:-6}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cycle_time() { # cpu binary -> summed cycle_wall_s of the run
    TRUBAL_TIMING=1 taskset -c "$1" "$2" --threads 1 "$DECK" 2>&1 >/dev/null |
        sed -n 's/.*cycle_wall_s=\([0-9.]*\).*/\1/p' |
        awk '{s += $1} END {printf "%.6f\n", s}'
}
for r in $(seq "$REPS"); do
    if [ $((r % 2)) = 1 ]; then ca=0 cb=1; else ca=1 cb=0; fi
    cycle_time "$ca" "$A" >"$tmp/a" &
    cycle_time "$cb" "$B" >"$tmp/b"
    wait
    echo "$(cat "$tmp/a") $(cat "$tmp/b")"
done | awk '
    { print; r[NR] = $2 / $1 }
    END {
        n = NR
        for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (r[j] < r[i]) { t = r[i]; r[i] = r[j]; r[j] = t }
        m = (n % 2) ? r[(n + 1) / 2] : (r[n / 2] + r[n / 2 + 1]) / 2
        printf "B/A median %.3f [%.3f-%.3f] over %d paired runs\n", m, r[1], r[n], n
    }'
