#!/usr/bin/env bash
# check_restart_torn.sh BIN_DIR CONFIG OUT EVERY
# What a run cut short leaves behind must not mislead its restart:
# 1. a series row cut short (no newline: a full disk or a kill mid-row) goes
#    at the rewind, and the restarted run's series/fluid.csv equals the
#    straight run's byte for byte (the row was kept and the next one glued on);
# 2. the summary of the run being restarted goes at the rewind: a restart
#    that then ends with exit status 0 but finishes nothing (an executable
#    that exits at once) fails, and its summary.json says so (it reported the
#    earlier run's "ok" and exited 0).
set -u
bin=$1 cfg=$2 out=$3 every=$4
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; fail "$dir"; }; }
run "$out/straight" --set run.checkpoint.every="$every"
first=$(ls -d "$out"/straight/checkpoints/window_*[0-9] 2>/dev/null | head -n 1)
[ -n "$first" ] || fail "no checkpoint written"
grep -q '"status": "ok"' "$out/straight/summary.json" || fail "the straight run's summary is not ok"
cp -a "$out/straight" "$out/torn"
series="$out/torn/series/fluid.csv"
# The rows up to the checkpoint's time and a torn one after them, "0" (a
# time at or before the checkpoint's, as "0.35" cut to "0.3" can be).
t=$(sed -n 's/^time: *//p' "$first/checkpoint.yaml")
awk -F, -v t="$t" 'NR <= 2 || $1 + 0 <= t + 1e-9' "$out/straight/series/fluid.csv" >"$series"
printf '0' >>"$series"
run "$out/torn" --restart "$out/torn/checkpoints/$(basename "$first")"
cmp "$out/straight/series/fluid.csv" "$series" || fail "series/fluid.csv after a restart over a torn row differs"
grep -q "rows after t = .* removed" "$out/torn.log" || fail "the rewind did not say it cut the torn row"
echo "a torn series row: cut at the rewind; series/fluid.csv after the restart identical"
"$bin/coflow" run "$cfg" --set run.output.dir="$out/torn" --restart "$out/torn/checkpoints/$(basename "$first")" \
  --exe fluid=/bin/true --set run.launch.start_timeout=20 >"$out/true.log" 2>&1
rc=$?
[ $rc -ne 0 ] || { cat "$out/true.log"; fail "a restart whose fluid (/bin/true) finished nothing: exit status 0"; }
grep -q '"status": "failed"' "$out/torn/summary.json" || fail "summary.json does not say failed: $(cat "$out/torn/summary.json")"
grep -q "does not hold a finished run" "$out/true.log" || { cat "$out/true.log"; fail "no message"; }
grep -q '"exit_code": 0' "$out/torn/summary.json" || fail "the failed summary is not the exit-0 launch's"
echo "a restart that finished nothing: exit status $rc, summary.json failed"
