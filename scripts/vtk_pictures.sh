#!/usr/bin/env bash
# The pictures of doc/output.md, "VTK files": doc/img/vtk_network.png (the breaking JKR
# agglomerate of golden/agglomerate_wall_impact.tru at its last cycle, spheres by radius and
# the contact network as tubes by normal force) and doc/img/vtk_field.png (its density field,
# FIEld 20 20 20 5e-5, on the x-z plane through the middle), rendered off-screen by
# tests/vtk/render.py with the VTK of .ci/vtk-venv.
#
# usage: scripts/vtk_pictures.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
py=$(bash "$root/.ci/vtk-venv")
(cd "$root" && cargo build --profile ci --quiet)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
{
    grep -v '^#' "$root/golden/agglomerate_wall_impact.tru"
    printf 'set outdir "out"\nvtk file break\nfield 20 20 20 5e-5 file break\n'
} > "$work/pictures.tru"
(cd "$work" && "$root/target/ci/trubal" pictures.tru > run.out)
grep -h "VTk: frame\|FIEld at" "$work/run.out"
"$py" "$root/tests/vtk/render.py" network "$work/out" break 6001 "$root/doc/img/vtk_network.png"
"$py" "$root/tests/vtk/render.py" field "$work/out/break_field_c00006001.vti" density "$root/doc/img/vtk_field.png"
