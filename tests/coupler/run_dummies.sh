#!/usr/bin/env bash
# run_dummies.sh BIN_DIR CONFIG OUT [--set key=value ...]
# Runs the dummy components through the launcher; the dummies check every value
# they receive and abort the run on the first wrong one.
set -u
bin=$1 cfg=$2 out=$3; shift 3
"$bin/coflow" run "$cfg" --exe fluid="$bin/coflow-dummy-fluid" --exe immersed="$bin/coflow-dummy-immersed" \
  --exe particles="$bin/coflow-dummy-particles" --set run.output.dir="$out" "$@" >"$out.log" 2>&1
rc=$?
if [ $rc -ne 0 ]; then tail -n 30 "$out.log"; echo "FAIL: exit status $rc"; exit 1; fi
grep -q '"status": "ok"' "$out/summary.json" || { echo "FAIL: summary.json"; exit 1; }
# The fluid dummy counts the windows whose values it checked: none would mean
# that nothing was compared.
checked=$(sed -n 's/.*"dummy.checked_windows": *\([0-9.e+]*\).*/\1/p' "$out/summary.json" | head -n 1)
awk -v c="${checked:-0}" 'BEGIN { exit !(c > 0) }' || { echo "FAIL: no window was checked (dummy.checked_windows=${checked:-missing})"; exit 1; }
echo "checked windows: $checked"
