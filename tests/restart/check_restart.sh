#!/usr/bin/env bash
# check_restart.sh BIN_DIR CONFIG OUT EVERY [--set ...]
# A run restarted from its first checkpoint must end exactly where the same run
# without interruption ends (bit for bit: every difference coflow-check prints
# is exactly 0), and only run.checkpoint.keep checkpoints may remain.
# RESTART_SETS (environment, optional): overrides for the restarted run only,
# e.g. "fluid.ranks=3": a checkpoint restarts on another number of ranks
# (each rank reads its own block of the global fields), which for a
# component that gives the same bits on any number of ranks (lbm) must
# still end exactly where the straight run ends.
set -u
bin=$1 cfg=$2 out=$3 every=$4; shift 4
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; echo "FAIL: $dir"; exit 1; }; }
run "$out/straight" "$@"
run "$out/checkpointed" --set run.checkpoint.every="$every" --set run.checkpoint.keep=2 "$@"
n=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | wc -l)
[ "$n" -eq 2 ] || { echo "FAIL: $n checkpoints kept, expected 2"; ls "$out/checkpointed/checkpoints"; exit 1; }
ls -d "$out"/checkpointed/checkpoints/*.partial >/dev/null 2>&1 && { echo "FAIL: a partial checkpoint was left"; exit 1; }
first=$(ls -d "$out"/checkpointed/checkpoints/window_* | head -n 1)
# A test may require a state in that checkpoint (CHECKPOINT_HOLDS: an
# extended regular expression some line of its .csv files must match).
if [ -n "${CHECKPOINT_HOLDS:-}" ] && ! grep -rqE --include='*.csv' "$CHECKPOINT_HOLDS" "$first"; then
  echo "FAIL: no line of $first matches '$CHECKPOINT_HOLDS'"; exit 1
fi
other=(); for s in ${RESTART_SETS:-}; do other+=(--set "$s"); done
run "$out/restarted" --restart "$first" "$@" "${other[@]}"
m=$("$bin/coflow-check" compare "$out/straight" "$out/restarted") || { echo "$m"; echo "FAIL: compare"; exit 1; }
echo "$m"
# Every *_difference line must be exactly zero, and there must be at least one.
diffs=$(echo "$m" | grep -E '^[a-z_]+_difference=')
[ -n "$diffs" ] || { echo "FAIL: coflow-check printed no difference"; exit 1; }
nonzero=$(echo "$diffs" | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || { echo "FAIL: the restarted run differs: $nonzero"; exit 1; }
echo "restart from $(basename "$first") is bit-identical"
# The event logs of a restart into a new directory hold the events after the
# checkpoint under the same header as the straight run's.
for f in "$out"/straight/events/*.csv; do
  [ -e "$f" ] || continue
  rel=${f#"$out/straight/"}
  [ "$(head -n 1 "$f")" = "$(head -n 1 "$out/restarted/$rel" 2>/dev/null)" ] ||
    { echo "FAIL: $rel of the restart into a new directory does not start with the header '$(head -n 1 "$f")'"; exit 1; }
done
# A second restart into that same new directory (a first try that failed,
# redone) cuts its event logs by time, not to the sizes the checkpoint's own
# directory had (before 2026-12-07 nothing was cut there, and every event
# after the checkpoint was logged twice): they end as after the first.
if ls "$out"/restarted/events/*.csv >/dev/null 2>&1; then
  rm -rf "$out/first-events"; cp -r "$out/restarted/events" "$out/first-events"
  run "$out/restarted" --restart "$first" "$@" "${other[@]}"
  for f in "$out"/first-events/*.csv; do
    rel=events/$(basename "$f")
    cmp -s "$f" "$out/restarted/$rel" ||
      { diff "$f" "$out/restarted/$rel" | head -5; echo "FAIL: $rel after a second restart into $out/restarted differs from the first's"; exit 1; }
  done
  echo "a second restart into the same new directory: event logs as after the first ($(cat "$out"/first-events/*.csv | wc -l) lines)"
fi
# summary.json counts the windows each run ran: all of them straight, those
# after the checkpoint's window when restarted.
w0=$(basename "$first" | sed 's/^window_0*//'); w0=${w0:-0}
counts() { /usr/bin/python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print(s["windows"], s["restarted_from_window"], s["windows_run"])' "$1/summary.json"; }
read -r total from ran <<<"$(counts "$out/straight")"
[ "$from" -eq 0 ] && [ "$ran" -eq "$total" ] || { echo "FAIL: straight run: windows $total, restarted_from_window $from, windows_run $ran"; exit 1; }
read -r total2 from ran <<<"$(counts "$out/restarted")"
[ "$total2" -eq "$total" ] && [ "$from" -eq "$w0" ] && [ "$ran" -eq $((total - w0)) ] ||
  { echo "FAIL: restarted run: windows $total2, restarted_from_window $from (want $w0), windows_run $ran (want $((total - w0)))"; exit 1; }
echo "summary.json: $total windows; the restart ran $ran from window $w0"
# Restarting from the older checkpoint into the directory of the finished run
# must not mix histories: the series, event logs and snapshot indexes are cut
# back to the checkpoint, so after the rerun they equal the straight run's,
# bit for bit; then --restart latest picks the run's newest checkpoint and
# changes nothing.
same_series() {
  for f in "$out"/straight/series/*.csv "$out"/straight/events/*.csv "$out"/straight/*/index.csv; do
    [ -e "$f" ] || continue
    rel=${f#"$out/straight/"}
    cmp -s "$f" "$out/checkpointed/$rel" || { echo "FAIL ($1): $rel differs from the straight run's"; diff "$f" "$out/checkpointed/$rel" | head -5; exit 1; }
  done
}
run "$out/checkpointed" --restart "$first" --set run.checkpoint.every="$every" --set run.checkpoint.keep=2 "$@"
grep -q "the run directory goes back to that time" "$out/checkpointed.log" || { echo "FAIL: the rewind was not reported"; exit 1; }
same_series "restart into the finished run's directory"
run "$out/checkpointed" --restart latest --set run.checkpoint.every="$every" --set run.checkpoint.keep=2 "$@"
same_series "--restart latest"
echo "restart into the same directory keeps one history; --restart latest: ok"
# A restart clears the failure reason of the run it goes on from (the
# launcher would report a stale logs/FAILED as this run's).
echo "fluid: a failure of an earlier run" >"$out/checkpointed/logs/FAILED"
run "$out/checkpointed" --restart latest --set run.checkpoint.every="$every" --set run.checkpoint.keep=2 "$@"
[ ! -e "$out/checkpointed/logs/FAILED" ] || { echo "FAIL: the restart kept the earlier run's logs/FAILED"; exit 1; }
# A fresh run into the directory removes the earlier run's checkpoints and
# says so (they would be pruned in place of its own, and be its `latest`). The
# removal comes before the first step: the run ends at the first checkpoint's
# time, its results unread.
run "$out/checkpointed" "$@" --set run.checkpoint.every=0 --set run.end_time="$every"
grep -q "checkpoint(s) of the run before it in $out/checkpointed/checkpoints are removed" "$out/checkpointed.log" ||
  { echo "FAIL: a fresh run did not report the earlier checkpoints' removal"; exit 1; }
left=$(ls -d "$out"/checkpointed/checkpoints/window_* 2>/dev/null | wc -l)
[ "$left" -eq 0 ] || { echo "FAIL: a fresh run left $left checkpoints of the run before it"; exit 1; }
echo "a restart clears logs/FAILED; a fresh run removes the earlier checkpoints: ok"
