#!/usr/bin/env bash
# check_restart_series.sh BIN_DIR CONFIG OUT EVERY SERIES [--set ...]
# A run restarted from its first checkpoint must write the series file SERIES
# (relative to the run's directory, e.g. series/dispersion.csv) byte for byte
# as the same run without interruption does.
set -u
bin=$1 cfg=$2 out=$3 every=$4 series=$5; shift 5
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" "$@"
run "$out/checkpointed" --set run.checkpoint.every="$every" "$@"
first=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | head -n 1)
[ -n "$first" ] || { echo "FAIL: no checkpoint written"; exit 1; }
run "$out/restarted" --restart "$first" "$@"
[ -s "$out/straight/$series" ] || { echo "FAIL: $series not written"; exit 1; }
cmp "$out/straight/$series" "$out/restarted/$series" || { echo "FAIL: $series differs after the restart"; exit 1; }
echo "$series after a restart from $(basename "$first"): identical ($(wc -l <"$out/straight/$series") lines)"
