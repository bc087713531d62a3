#!/usr/bin/env bash
# check_restart.sh BIN_DIR CONFIG OUT EVERY [--set ...]
# A run restarted from its first checkpoint must end exactly where the same run
# without interruption ends (bit for bit: every difference coflow-check prints
# is exactly 0), and only run.checkpoint.keep checkpoints may remain.
set -u
bin=$1 cfg=$2 out=$3 every=$4; shift 4
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" "$@"
run "$out/checkpointed" --set run.checkpoint.every="$every" --set run.checkpoint.keep=2 "$@"
n=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | wc -l)
[ "$n" -eq 2 ] || { echo "FAIL: $n checkpoints kept, expected 2"; ls "$out/checkpointed/checkpoints"; exit 1; }
ls -d "$out"/checkpointed/checkpoints/*.partial >/dev/null 2>&1 && { echo "FAIL: a partial checkpoint was left"; exit 1; }
first=$(ls -d "$out"/checkpointed/checkpoints/window_* | head -n 1)
run "$out/restarted" --restart "$first" "$@"
m=$("$bin/coflow-check" compare "$out/straight" "$out/restarted") || { echo "$m"; echo "FAIL: compare"; exit 1; }
echo "$m"
# Every *_difference line must be exactly zero, and there must be at least one.
diffs=$(echo "$m" | grep -E '^[a-z_]+_difference=')
[ -n "$diffs" ] || { echo "FAIL: coflow-check printed no difference"; exit 1; }
nonzero=$(echo "$diffs" | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || { echo "FAIL: the restarted run differs: $nonzero"; exit 1; }
echo "restart from $(basename "$first") is bit-identical"
