#!/usr/bin/env bash
# check_restart_series.sh BIN_DIR CONFIG OUT EVERY SERIES [--rows-after] [--set ...]
# A run restarted from its first checkpoint must write the series file SERIES
# (relative to the run's directory, e.g. series/dispersion.csv) byte for byte
# as the same run without interruption does. --rows-after: the series is
# written row by row (a restarted run writes the rows after its checkpoint
# into its own directory): its rows must equal the straight run's last rows.
set -u
bin=$1 cfg=$2 out=$3 every=$4 series=$5; shift 5
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
after=0
if [ "${1:-}" = --rows-after ]; then after=1; shift; fi
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" "$@"
run "$out/checkpointed" --set run.checkpoint.every="$every" "$@"
first=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | head -n 1)
[ -n "$first" ] || { echo "FAIL: no checkpoint written"; exit 1; }
run "$out/restarted" --restart "$first" "$@"
[ -s "$out/straight/$series" ] || { echo "FAIL: $series not written"; exit 1; }
if [ $after -eq 1 ]; then
  rows=$(($(wc -l <"$out/restarted/$series") - 2))
  [ $rows -gt 0 ] || { echo "FAIL: no rows after the restart"; exit 1; }
  cmp <(tail -n $rows "$out/straight/$series") <(tail -n $rows "$out/restarted/$series") ||
    { echo "FAIL: the $rows rows of $series after the restart differ"; exit 1; }
  echo "$series: the $rows rows after a restart from $(basename "$first") are identical"
  exit 0
fi
cmp "$out/straight/$series" "$out/restarted/$series" || { echo "FAIL: $series differs after the restart"; exit 1; }
echo "$series after a restart from $(basename "$first"): identical ($(wc -l <"$out/straight/$series") lines)"
