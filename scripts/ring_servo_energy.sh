#!/bin/bash
# The energy books of the ring-servo shear of tests/it/cell.rs
# (`the_ring_servo_holds_the_principal_stress_angle`) under MDR and MD, with variations:
# servo gain, FRAction, the restitution dashpot, the servo off. Each run prepares the
# packing as the test does (40,000 cycles, servo S0 then RING 120), then shears at
# ed12 = 20 1/s for 3000 cycles (at FRAction 0.2; the same time at smaller steps) in
# Cycles of 50 (of 100, 200), printing the energy after each; the last runs replace the
# shear by a compression along one axis, without a servo (GRID in the 7th field).
# Usage: [BUILD=label] scripts/ring_servo_energy.sh BINARY OUT.csv (BUILD: the source the binary
# was built from, default git describe of the work tree)
set -e
bin=$1; out=$2; dir=$(mktemp -d)
run() { # name law gain servo extra-line cycles-per-print [grid]
    f=$dir/$1.tru
    { echo "start 1e-3 1e-3 1e-3 100 1000 0"
      [ "$2" = md ] && echo "set tangential md"
      printf 'rad 8e-5 1\ndensity 2600 1\nymd 1e8 1\npra 0.25 1\nfriction 0.3 1\n'
      printf 'damping restitution 0.2\nrge 100 1 1 0\ngain 2e-2 600\nmode 1\n'
      printf 'cycle 20000 s0 2e4\ncycle 20000 s0 2e4 ring 120\nprint energy\n'
      printf 'grid %s\ngain %s 600\nmode 0\n' "${7:-0 0 0 20 0 0}" "$3"
      [ -n "$5" ] && echo "$5"
      i=0; while [ $i -lt 60 ]; do echo "cycle $6 $4"; echo "print energy"; i=$((i+1)); done
    } > "$f"
    "$bin" "$f" > "$dir/$1.out" 2>&1 || { echo "$1 failed" >&2; cat "$dir/$1.out" >&2; exit 1; }
    paste -d' ' <(grep "cell " "$dir/$1.out" | awk '{print $9}') \
        <(grep residual "$dir/$1.out" | awk '{print $2}') \
        <(grep "contact damping" "$dir/$1.out" | awk '{print $9}') |
    awk -v n="$1" -v law="$2" -v g="$3" -v s="$4" -v x="$5" -v gr="${7:-0 0 0 20 0 0}" '
        NR==1 {r0=$2; i0=$1; d0=$3; mx=0; at=0}
        {d=$2-r0; if (d>mx) {mx=d; at=NR-1}}
        END {printf "%s,%s,%s,%s,%s,%s,%.4e,%d,%.4e,%.4e,%.4e\n", n, law, gr, g, (s==""?"none":s), (x==""?"-":x), mx, at, $2-r0, $1-i0, $3-d0}'
}
{
echo "# The ring-servo shear of tests/it/cell.rs: rise of the books' residual (stored - input + dissipated) over the first 3000 cycles' time of the shear."
echo "# Made by: scripts/ring_servo_energy.sh $bin $out"
echo "# Build: ${BUILD:-$(git describe --always --dirty)}, $(date -u "+%Y-%m-%d %H:%M UTC")"
echo "# max_rise: the largest rise of the residual over its value at the shear's start (J), at print max_at (of 60); final_rise at the last print; cell_input and contact_damping: what the books took in and booked in the 60 prints. The cell's input before the shear: 5.86e-7 J."
echo "run,law,grid,gain,servo,extra,max_rise_J,max_at,final_rise_J,cell_input_J,contact_damping_J"
S="s22 2e4 s33 2e4 ring 105"
run mdr mdr 1e-3 "$S" "" 50
run md md 1e-3 "$S" "" 50
run mdr_gain3e-4 mdr 3e-4 "$S" "" 50
run mdr_fraction0.1 mdr 1e-3 "$S" "fraction 0.1" 100
run mdr_fraction0.05 mdr 1e-3 "$S" "fraction 0.05" 200
run mdr_restitution1 mdr 1e-3 "$S" "damping restitution 1" 50
run md_restitution1 md 1e-3 "$S" "damping restitution 1" 50
run mdr_no_servo mdr 1e-3 "" "" 50
run md_no_servo md 1e-3 "" "" 50
run mdr_ed11_only mdr 1e-3 "" "" 50 "-2 0 0 0 0 0"
run md_ed11_only md 1e-3 "" "" 50 "-2 0 0 0 0 0"
run mdr_ed22_only mdr 1e-3 "" "" 50 "0 -2 0 0 0 0"
run mdr_ring_no_shear mdr 1e-3 "$S" "" 50 "0 0 0 0 0 0"
} > "$out"
# The whole test: 40,000 cycles of the shear, the residual over the input at the end.
long() { # law
    f=$dir/long_$1.tru
    { echo "start 1e-3 1e-3 1e-3 100 1000 0"
      [ "$1" = md ] && echo "set tangential md"
      printf 'rad 8e-5 1\ndensity 2600 1\nymd 1e8 1\npra 0.25 1\nfriction 0.3 1\n'
      printf 'damping restitution 0.2\nrge 100 1 1 0\ngain 2e-2 600\nmode 1\n'
      printf 'cycle 20000 s0 2e4\ncycle 20000 s0 2e4 ring 120\nprint grid\n'
      printf 'grid 0 0 0 20 0 0\ngain 1e-3 600\nmode 0\n'
      printf 'cycle 40000 s22 2e4 s33 2e4 ring 105\nprint energy\n'
    } > "$f"
    "$bin" "$f" > "$dir/long_$1.out" 2>&1 || { echo "long $1 failed" >&2; cat "$dir/long_$1.out" >&2; exit 1; }
    paste -d' ' <(grep "^ *input " "$dir/long_$1.out" | awk '{print $9}') \
        <(grep residual "$dir/long_$1.out" | awk '{print $2}') \
        <(grep "image offset" "$dir/long_$1.out" | awk '{print $12}') \
        <(grep "^work-space" "$dir/long_$1.out" | awk '{print $2}') |
    awk -v law="$1" '{printf "# whole test (80,000 cycles), %s: image offset before the shear %.4e m (L_x %.4e m); cell input %.4e J, residual %.4e J (%.3f %% of the input)\n", law, $3, $4, $1, $2, 100*$2/$1}'
}
{ long mdr; long md; } >> "$out"
rm -r "$dir"
