#!/usr/bin/env bash
# check_first_step.sh COFLOW CONFIG OUT MAX_DT MIN_STEPS [--set ...]
# A flow started from rest and driven by a face (a lid, an inlet) or a body
# must take its first steps at the CFL limit of that speed (seed 003 eq. 4.1),
# not the whole window: the first row of series/fluid.csv (the first window:
# the caller sets coupling.window to the output interval) must show a last
# step of at most MAX_DT s and at least MIN_STEPS steps in the window. (Before
# 2026-12-07 fv took the fluid's own speeds alone: a cavity at rest made its
# first step the whole 1 s window, 160 times the CFL step.)
set -u
bin=$1 cfg=$2 out=$3 max_dt=$4 min_steps=$5; shift 5
rm -rf "$out"
"$bin" run "$cfg" --set run.output.dir="$out" "$@" >"$out.log" 2>&1 ||
  { tail -n 20 "$out.log"; echo "FAIL: the run failed"; exit 1; }
csv=$out/series/fluid.csv
[ -f "$csv" ] || { echo "FAIL: no $csv"; exit 1; }
# The first row after the header, the units line and the t = 0 row.
awk -F, -v max_dt="$max_dt" -v min_steps="$min_steps" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  /^#/ { next }
  $col["time"] + 0 == 0 { next }
  !done { done = 1; dt = $col["dt"]; steps = $col["steps"]
          printf "first window: t = %s s, %s steps, last step %s s (at most %s s and at least %s steps asked)\n", $col["time"], steps, dt, max_dt, min_steps
          ok = (dt + 0 <= max_dt + 0) && (steps + 0 >= min_steps + 0) && dt == dt + 0 }
  END { if (!done) { print "FAIL: no row after t = 0"; exit 1 } exit ok ? 0 : 1 }' "$csv" ||
  { echo "FAIL: the first steps are longer than the CFL limit of the driving speed"; exit 1; }
echo "ok"
