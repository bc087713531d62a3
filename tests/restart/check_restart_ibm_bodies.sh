#!/usr/bin/env bash
# check_restart_ibm_bodies.sh BIN_DIR CONFIG OUT
# CONFIG has two immersed bodies (configs/validation/ibm_couette.yaml). Its
# checkpoint, restarted into another directory with one body (the first),
# must stop naming both counts: the series row in the checkpoint holds six
# sums a body, and before 2026-12-07 the first 6 n + 2 of them were read, so
# the removed body's sums went into the next columns without a word.
set -u
bin=$1 cfg=$2 out=$3
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$out"; mkdir -p "$out"
short=(--set run.end_time=0.5 --set run.output.every=0.5)
"$bin/coflow" run "$cfg" --set run.output.dir="$out/a" "${short[@]}" --set run.checkpoint.every=0.25 >"$out/a.log" 2>&1 ||
  { tail -n 20 "$out/a.log"; fail "the first run"; }
one='immersed.ibm.bodies=[{name: rotor, mesh: geometry/cylinder.stl, motion: {angular_velocity: [0.0, 0.0, 1.0]}}]'
timeout 120 "$bin/coflow" run "$cfg" --set run.output.dir="$out/b" "${short[@]}" --set "$one" \
  --restart "$out/a/checkpoints/window_000001" >"$out/b.log" 2>&1 && { tail -n 20 "$out/b.log"; fail "the restart with one body ran"; }
grep -qF "the checkpoint's series row holds the sums of 2 immersed bodies, and this run has 1" "$out/b.log" ||
  { tail -n 20 "$out/b.log"; fail "no message naming both body counts"; }
echo "a restart with one body of two stops naming both counts"
