#!/usr/bin/env bash
# check_restart_columns.sh BIN_DIR CONFIG OUT
# A restart into the directory of the run it goes on from appends to that
# run's series: with other columns (here a probe added) it must stop with a
# message that names the file and both column lists, not append rows under
# the old header; into a new directory the same restart runs.
set -u
bin=$1 cfg=$2 out=$3
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
one='run.output.probes=[{name: a, point: [0.016, 0.016, 0.03]}]'
two='run.output.probes=[{name: a, point: [0.016, 0.016, 0.03]}, {name: b, point: [0.01, 0.01, 0.01]}]'
short=(--set run.end_time=0.02 --set run.output.every=0.01 --set run.checkpoint.every=0.01)
"$bin/coflow" run "$cfg" --set run.output.dir="$out/run" "${short[@]}" --set "$one" >"$out/run.log" 2>&1 ||
  { tail -n 20 "$out/run.log"; echo "FAIL: the first run"; exit 1; }
first=$(ls -d "$out"/run/checkpoints/window_* | head -n 1)
timeout 120 "$bin/coflow" run "$cfg" --set run.output.dir="$out/run" "${short[@]}" --set "$two" --restart "$first" \
  >"$out/same.log" 2>&1
rc=$?
# Stopped with a message: exit 1 or 2, not 0 (it ran), 124 (it hung) or a signal's 128 + N.
[ $rc -eq 1 ] || [ $rc -eq 2 ] || { tail -n 20 "$out/same.log"; echo "FAIL: the restart with a probe added: exit $rc, expected 1 or 2"; exit 1; }
grep -qF "series/probes.csv: the run this restart goes on from wrote the columns time,a_ux,a_uy,a_uz,a_p; this run writes time,a_ux,a_uy,a_uz,a_p,b_ux,b_uy,b_uz,b_p" \
  "$out/same.log" || { tail -n 20 "$out/same.log"; echo "FAIL: no message naming probes.csv and both column lists"; exit 1; }
[ "$(head -n 1 "$out/run/series/probes.csv")" = "time,a_ux,a_uy,a_uz,a_p" ] || { echo "FAIL: probes.csv's header changed"; exit 1; }
awk -F, 'NR > 2 && NF != 5 { bad = 1 } END { exit bad }' "$out/run/series/probes.csv" ||
  { echo "FAIL: probes.csv has rows of another width"; exit 1; }
# The checkpoint is still there: the restart with the run's own probe goes on.
"$bin/coflow" run "$cfg" --set run.output.dir="$out/run" "${short[@]}" --set "$one" --restart "$first" >"$out/again.log" 2>&1 ||
  { tail -n 20 "$out/again.log"; echo "FAIL: the restart with the run's own settings after the refused one"; exit 1; }
"$bin/coflow" run "$cfg" --set run.output.dir="$out/new" "${short[@]}" --set "$two" --restart "$first" >"$out/new.log" 2>&1 ||
  { tail -n 20 "$out/new.log"; echo "FAIL: the restart into a new directory"; exit 1; }
[ "$(head -n 1 "$out/new/series/probes.csv")" = "time,a_ux,a_uy,a_uz,a_p,b_ux,b_uy,b_uz,b_p" ] ||
  { echo "FAIL: the new directory's probes.csv lacks the new header"; exit 1; }
echo "a restart that changes a series' columns stops with the file and both lists; into a new directory it runs: ok"
