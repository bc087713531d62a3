#!/usr/bin/env bash
# check_restart_auto_window.sh BIN_DIR OUT
# tests/restart/analytic_taylor_green.yaml has no natural step: its window
# (0.1 s) comes from run.output.every and run.end_time (1 s).
# 1. Restarted from its checkpoint at window 6, it ends exactly where the run
#    without interruption ends (the analytic fluid's time was a running sum
#    of windows, 0.6 after six, and a restart set it to 6 x 0.1 =
#    0.6000000000000001: the fields differed at round-off).
# 2. A restart to run.end_time 1.25 s, whose outputs give windows of 0.05 s,
#    is refused with exit 2 before the launcher cuts the directory back
#    (before, every component's clock refused it after the cut: the finished
#    run's last snapshot and summary were gone), and the restart it suggests
#    (coupling.window 0.1, end 1.3 s) runs, removing an unfinished
#    checkpoint folder that an interrupted run left.
set -u
bin=$1 out=$2
cfg=$(dirname "$0")/analytic_taylor_green.yaml
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; fail "$dir"; }; }
run "$out/straight"
run "$out/checkpointed" --set run.checkpoint.every=0.6
cp=$out/checkpointed/checkpoints/window_000006
grep -q "window_from_outputs: true" "$cp/checkpoint.yaml" || { cat "$cp/checkpoint.yaml"; fail "the checkpoint does not say that its window came from the outputs"; }
run "$out/restarted" --restart "$cp"
m=$("$bin/coflow-check" compare "$out/straight" "$out/restarted") || { echo "$m"; fail "compare"; }
echo "$m"
diffs=$(echo "$m" | grep -E '^[a-z_]+_difference=')
[ -n "$diffs" ] || fail "coflow-check printed no difference"
nonzero=$(echo "$diffs" | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || fail "the restarted run differs: $nonzero"
echo "restart from window 6 is bit-identical"
state() { (cd "$out/checkpointed" && find . -type f ! -name '*.log' ! -path './logs/*' | sort | xargs md5sum); }
before=$(state)
timeout 120 "$bin/coflow" run "$cfg" --set run.output.dir="$out/checkpointed" --set run.end_time=1.25 \
  --restart latest >"$out/longer.log" 2>&1
rc=$?
[ $rc -eq 2 ] || { tail -n 20 "$out/longer.log"; fail "a restart to 1.25 s: exit $rc, expected 2"; }
grep -qF "took windows of 0.1 s from its outputs and end time" "$out/longer.log" &&
  grep -qF "give windows of 0.05 s; restart with --set coupling.window=0.1 and a run.end_time that is a whole number of them (e.g. 1.3)" "$out/longer.log" ||
  { cat "$out/longer.log"; fail "no message naming both windows"; }
[ "$(state)" = "$before" ] || { diff <(echo "$before") <(state) | head; fail "the refused restart changed the run directory"; }
echo "the restart to 1.25 s is refused, the directory unchanged"
# An unfinished checkpoint an interrupted run left (its folder would be
# reused, and a file this run does not write promoted with it) goes too.
stale=$out/checkpointed/checkpoints/window_000012.partial
mkdir -p "$stale/fluid" && echo stale >"$stale/fluid/fv_turbulence.h5"
timeout 60 "$bin/coflow" run "$cfg" --set run.output.dir="$out/checkpointed" --restart "$stale" >"$out/partial.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -qF "an unfinished checkpoint (a run stopped while writing it)" "$out/partial.log" ||
  { cat "$out/partial.log"; fail "--restart of an unfinished checkpoint: exit $rc, expected 2 and a message"; }
run "$out/checkpointed" --set run.end_time=1.3 --set coupling.window=0.1 --restart latest
[ ! -e "$stale" ] || fail "the unfinished checkpoint $stale was left"
grep -qF "window_000012.partial: an unfinished checkpoint, removed" "$out/checkpointed.log" ||
  { cat "$out/checkpointed.log"; fail "the rewind did not say that it removed the unfinished checkpoint"; }
grep -q '"time_reached": 1.3' "$out/checkpointed/summary.json" || { cat "$out/checkpointed/summary.json"; fail "the suggested restart did not reach 1.3 s"; }
echo "the suggested restart (coupling.window 0.1, end 1.3 s) runs to its end"
