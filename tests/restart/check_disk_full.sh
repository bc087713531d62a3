#!/usr/bin/env bash
# check_disk_full.sh BIN_DIR CONFIG OUT EVERY
# A run whose disk fills up must stop at once with a message that names the
# failed write and the full disk (exit 1, not a hang or a crash), leave no
# temporary files (summary.json.tmp.*, step_N.h5.tmp) and no "ok"
# summary, and go on with --restart latest once there is room: the restarted
# run's series equal a straight run's byte for byte and its snapshots hold
# the same data (h5diff).
# The run directory is a tmpfs of a fixed size, mounted in a mount namespace
# of this script's own (unshare: it goes when the script ends, whatever
# happens). Two sizes, 50 % and 60 % of what the straight run writes, fill
# the disk at different writes (a snapshot after the first checkpoint; the
# second checkpoint, left .partial). Needs root (or CAP_SYS_ADMIN) to mount:
# exit 77 (skipped) without it.
set -u
bin=$1 cfg=$2 out=$3 every=$4
if [ -z "${COFLOW_IN_NAMESPACE:-}" ]; then
  COFLOW_IN_NAMESPACE=1 unshare --mount --propagation private true 2>/dev/null ||
    { echo "SKIP: cannot make a mount namespace (unshare --mount needs root)"; exit 77; }
  exec env COFLOW_IN_NAMESPACE=1 unshare --mount --propagation private "$0" "$@"
fi
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT
rm -rf "$out"; mkdir -p "$out/disk"
dir=""
fail() {  # the tmpfs goes with this script's namespace: keep the failed run's logs
  [ -n "$dir" ] && [ -d "$dir/logs" ] && cp -r "$dir/logs" "$out/failed-logs" 2>/dev/null
  echo "FAIL: $*"; exit 1
}
run() { "$bin/coflow" run "$cfg" --set run.checkpoint.every="$every" "$@"; }
run --set run.output.dir="$out/straight" >"$out/straight.log" 2>&1 || { tail -n 20 "$out/straight.log"; fail "straight run"; }
total=$(du -sk "$out/straight" | cut -f1)
for percent in 50 60; do
  size=$((total * percent / 100))
  [ "$size" -gt 0 ] || fail "the straight run wrote nothing (du: $total KiB)"  # size=0 is an unlimited tmpfs
  mount -t tmpfs -o size=${size}k tmpfs "$out/disk" || { echo "SKIP: cannot mount a tmpfs"; exit 77; }
  dir="$out/disk/run" log="$out/full$percent.log"
  timeout 20 "$bin/coflow" run "$cfg" --set run.checkpoint.every="$every" --set run.output.dir="$dir" >"$log" 2>&1
  rc=$?
  [ $rc -eq 1 ] || { tail -n 20 "$log"; fail "$percent %: exit status $rc on a full disk (1 expected; 124: hung)"; }
  grep -Eq "coflow: run failed in component '.*(HDF5 error while (writing|creating|closing)|failed writing|cannot write|cannot append).*bytes free: the disk is full" "$log" ||
    { tail -n 20 "$log"; fail "$percent %: the failure does not say the disk is full"; }
  ! grep -q '"status": "ok"' "$dir/summary.json" 2>/dev/null || fail "$percent %: summary.json says ok"
  left=$(find "$dir" -name '*.tmp.*' -o -name '*.tmp')
  [ -z "$left" ] || fail "$percent %: temporary files left: $left"
  ls -d "$dir"/checkpoints/window_*[0-9] >/dev/null 2>&1 || fail "$percent %: no checkpoint fitted (raise the sizes)"
  echo "$percent % of the straight run's ${total} KiB: $(grep -o "HDF5 error while [a-z ]*" "$log" | head -n 1);" \
    "checkpoints $(ls "$dir/checkpoints" | tr '\n' ' ')"
  mount -o remount,size=$((total * 4))k "$out/disk" || fail "remount"
  run --set run.output.dir="$dir" --restart latest >"$out/restart$percent.log" 2>&1 ||
    { tail -n 20 "$out/restart$percent.log"; fail "$percent %: the restart once there is room"; }
  grep -q '"status": "ok"' "$dir/summary.json" || fail "$percent %: the restart's summary is not ok"
  cmp "$out/straight/series/fluid.csv" "$dir/series/fluid.csv" || fail "$percent %: series/fluid.csv differs"
  cmp "$out/straight/fluid/index.csv" "$dir/fluid/index.csv" || fail "$percent %: fluid/index.csv differs"
  for f in "$out"/straight/fluid/step_*.h5; do
    h5diff "$f" "$dir/fluid/$(basename "$f")" || fail "$percent %: $(basename "$f") differs (h5diff)"
  done
  echo "  restarted with room: series and snapshots equal the straight run's"
  umount "$out/disk" || fail "umount"
done
