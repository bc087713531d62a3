#!/usr/bin/env bash
# check_restart_across.sh BIN_DIR CONFIG OUT EVERY "A" "B"
# A checkpoint written by one variant or rank count (A: space-separated
# key=value overrides) restarts another (B): the restarted run must end
# exactly where a straight run of B ends (every difference coflow-check
# prints exactly 0).
set -u
bin=$1 cfg=$2 out=$3 every=$4 a=$5 b=$6
rm -rf "$out"; mkdir -p "$out"
sets() { for kv in $1; do printf -- '--set\n%s\n' "$kv"; done; }
mapfile -t sa < <(sets "$a")
mapfile -t sb < <(sets "$b")
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" "${sb[@]}"
run "$out/checkpointed" --set run.checkpoint.every="$every" "${sa[@]}"
first=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | head -n 1)
[ -n "$first" ] || { echo "FAIL: no checkpoint written"; exit 1; }
run "$out/restarted" --restart "$first" "${sb[@]}"
m=$("$bin/coflow-check" compare "$out/straight" "$out/restarted") || { echo "$m"; echo "FAIL: compare"; exit 1; }
echo "$m"
diffs=$(echo "$m" | grep -E '^[a-z_]+_difference=')
[ -n "$diffs" ] || { echo "FAIL: coflow-check printed no difference"; exit 1; }
nonzero=$(echo "$diffs" | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || { echo "FAIL: the restarted run differs: $nonzero"; exit 1; }
echo "B ($b) restarted from A's ($a) $(basename "$first") is bit-identical to B straight"
