#!/usr/bin/env bash
# run_and_check.sh COFLOW CONFIG OUTDIR PVPYTHON SCRIPT
set -eu
coflow=$1 cfg=$2 out=$3 pv=$4 script=$5
rm -rf "$out"
"$coflow" run "$cfg" --set run.output.dir="$out" >"$out.log" 2>&1 || { cat "$out.log"; exit 1; }
[ -f "$out/run.xdmf" ] && [ -f "$out/summary.json" ] || { echo "FAIL: run.xdmf or summary.json missing"; exit 1; }
grep -q '"status": "ok"' "$out/summary.json" || { echo "FAIL: summary status"; cat "$out/summary.json"; exit 1; }
[ -n "$pv" ] && [ -x "$pv" ] || { echo "FAIL: pvpython not found (install python3-paraview)"; exit 1; }
"$pv" --force-offscreen-rendering "$script" "$out"
