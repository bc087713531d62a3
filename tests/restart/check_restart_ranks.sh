#!/usr/bin/env bash
# check_restart_ranks.sh BIN_DIR CONFIG OUT EVERY "RESTART_SETS" [--set ...]
# A checkpoint restarts on another number of ranks (docs/output.md): each
# rank reads its own block of the global fields. For a component that gives
# the same bits on any number of ranks (lbm), the run restarted with
# RESTART_SETS (e.g. "fluid.ranks=3") from its first checkpoint must end
# exactly where the straight run ends: every difference coflow-check prints
# is exactly 0.
set -u
bin=$1 cfg=$2 out=$3 every=$4 other=$5; shift 5
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" "$@"
run "$out/checkpointed" --set run.checkpoint.every="$every" "$@"
first=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | head -n 1)
[ -n "$first" ] || { echo "FAIL: no checkpoint written"; exit 1; }
sets=(); for s in $other; do sets+=(--set "$s"); done
run "$out/restarted" --restart "$first" "$@" "${sets[@]}"
m=$("$bin/coflow-check" compare "$out/straight" "$out/restarted") || { echo "$m"; echo "FAIL: compare"; exit 1; }
echo "$m"
diffs=$(echo "$m" | grep -E '^[a-z_]+_difference=')
[ -n "$diffs" ] || { echo "FAIL: coflow-check printed no difference"; exit 1; }
nonzero=$(echo "$diffs" | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || { echo "FAIL: the run restarted with $other differs: $nonzero"; exit 1; }
echo "restart from $(basename "$first") with $other is bit-identical"
