#!/usr/bin/env bash
# check_restart_refused.sh BIN_DIR CONFIG OUT
# A restart that cannot go on from its checkpoint stops with exit 2 and a
# message before the launcher cuts the run directory back: one whose
# run.end_time is before the checkpoint's time (it ran no window, reported
# success, and its summary ended before its series), and one with another
# run.output.every (its snapshots, numbered by it, would be written over the
# old ones), one with another box or coupling scheme. The directory is the
# same, file for file and byte for byte, after each; the restart with the
# run's own settings then goes on.
set -u
bin=$1 cfg=$2 out=$3
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
short=(--set run.end_time=0.03 --set run.output.every=0.01 --set run.checkpoint.every=0.01 --set run.checkpoint.keep=3)
"$bin/coflow" run "$cfg" --set run.output.dir="$out/run" "${short[@]}" >"$out/run.log" 2>&1 ||
  { tail -n 20 "$out/run.log"; echo "FAIL: the first run"; exit 1; }
first=$(ls -d "$out"/run/checkpoints/window_* | head -n 1)
state() { (cd "$out/run" && find . -type f ! -name '*.log' ! -path './logs/*' | sort | xargs md5sum); }
before=$(state)
refused() {  # refused CHECKPOINT NAME EXPECTED-TEXT OVERRIDES...
  local from=$1 name=$2 text=$3; shift 3
  timeout 120 "$bin/coflow" run "$cfg" --set run.output.dir="$out/run" "${short[@]}" "$@" --restart "$from" \
    >"$out/$name.log" 2>&1
  local rc=$?
  [ $rc -eq 2 ] || { tail -n 20 "$out/$name.log"; echo "FAIL: $name: exit $rc, expected 2"; exit 1; }
  grep -qF "$text" "$out/$name.log" || { cat "$out/$name.log"; echo "FAIL: $name: no message '$text'"; exit 1; }
  [ "$(state)" = "$before" ] || { diff <(echo "$before") <(state) | head; echo "FAIL: $name changed the run directory"; exit 1; }
  echo "$name: refused with exit 2, the directory unchanged: ok"
}
second=$(ls -d "$out"/run/checkpoints/window_* | sed -n 2p)
refused "$second" early_end "run.end_time = 0.01 s is before the checkpoint's time, 0.02 s" --set run.end_time=0.01
refused "$first" other_every "run.output.every = 0.02 s, but the checkpoint's run wrote snapshots every 0.01 s" \
  --set run.output.every=0.02
# Another box (the same cells, shifted) and another scheme: before
# 2026-12-07 the first loaded the fields and grains onto the new box and
# rewrote run.xdmf for it, the second dropped the loads in flight.
refused "$first" other_box "but the checkpoint's run had [0, 0, 0] to [0.032, 0.032, 0.064]" \
  --set 'domain.lower=[0.001,0,0]' --set 'domain.upper=[0.033,0.032,0.064]'
refused "$first" other_scheme \
  "coupling.scheme = parallel-explicit, but the checkpoint was written by a serial-explicit run" \
  --set coupling.scheme=parallel-explicit
"$bin/coflow" run "$cfg" --set run.output.dir="$out/run" "${short[@]}" --restart "$first" >"$out/again.log" 2>&1 ||
  { tail -n 20 "$out/again.log"; echo "FAIL: the restart with the run's own settings"; exit 1; }
echo "restarts that cannot go on are refused before the directory is cut back: ok"
