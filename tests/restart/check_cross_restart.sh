#!/usr/bin/env bash
# check_cross_restart.sh BIN_DIR CONFIG OUT EVERY VARIANT_A VARIANT_B BOUND [--set ...]
# fv and fv-reference write one checkpoint format, so that either restarts the
# other's: VARIANT_B restarted from VARIANT_A's first checkpoint must end
# within BOUND (velocity and pressure, coflow-check compare) of VARIANT_B run
# straight through. Not bit for bit: before the checkpoint the two variants
# differ by their solvers' round-off (fv against fv-reference, 1e-12 here).
set -u
bin=$1 cfg=$2 out=$3 every=$4 a=$5 b=$6 bound=$7; shift 7
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" --set fluid.solver="$b" "$@"
run "$out/checkpointed" --set fluid.solver="$a" --set run.checkpoint.every="$every" "$@"
first=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | head -n 1)
[ -n "$first" ] || { echo "FAIL: $a wrote no checkpoint"; exit 1; }
run "$out/restarted" --set fluid.solver="$b" --restart "$first" "$@"
m=$("$bin/coflow-check" compare "$out/straight" "$out/restarted") || { echo "$m"; echo "FAIL: compare"; exit 1; }
echo "$m"
echo "$m" | grep -E '^(max|pressure)_difference=' | awk -F= -v b="$bound" -v a="$a" -v v="$b" '
  { n++; if (!($2 + 0 <= b + 0)) { printf "FAIL: %s is above %s (or not a number)\n", $0, b; bad = 1 } }
  END { if (n < 2) { print "FAIL: coflow-check printed no differences"; exit 1 }
        if (bad) exit 1; printf "%s restarted from %s'"'"'s checkpoint: within %s\n", v, a, b }'
