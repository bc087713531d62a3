#!/usr/bin/env bash
# jet.sh CASE BIN_DIR OUT MODE CONFIG "PLATE ARGS" [ARGS...]
# Writes a plate mesh with scripts/make_plate_stl.py (PLATE ARGS: its options, - for the defaults)
# into OUT/plate.stl, then runs validate.sh with particles.walls pointing at
# it; in ARGS, @WALLS@ stands for that override (compare mode: inside each
# override list; other modes: add --set @WALLS@), and @PLATE@ for the mesh's
# path (an immersed body of the same plate).
set -u
case_name=$1 bin=$2 out=$3 mode=$4 cfg=$5 plate_args=$6; shift 6
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
# shellcheck disable=SC2086
[ "$plate_args" = "-" ] && plate_args=""
/usr/bin/python3 "$here/../../../scripts/make_plate_stl.py" "$out/plate.stl" $plate_args || { echo "FAIL: plate"; exit 1; }
walls="particles.walls=[{\"mesh\":\"$out/plate.stl\",\"restitution\":0.3,\"friction\":0.1}]"
args=()
for a in "$@"; do
  a=${a//@WALLS@/$walls}
  args+=("${a//@PLATE@/$out/plate.stl}")
done
exec "$here/../validate.sh" "$case_name" "$bin" "$out" "$mode" "$cfg" "${args[@]}"
