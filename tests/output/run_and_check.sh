#!/usr/bin/env bash
# run_and_check.sh COFLOW CONFIG OUTDIR PVPYTHON SCRIPT
set -eu
coflow=$1 cfg=$2 out=$3 pv=$4 script=$5
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"
"$coflow" run "$cfg" --set run.output.dir="$out" >"$out.log" 2>&1 || { cat "$out.log"; exit 1; }
[ -f "$out/run.xdmf" ] && [ -f "$out/summary.json" ] || { echo "FAIL: run.xdmf or summary.json missing"; exit 1; }
grep -q '"status": "ok"' "$out/summary.json" || { echo "FAIL: summary status"; cat "$out/summary.json"; exit 1; }
[ -n "$pv" ] && [ -x "$pv" ] || { echo "FAIL: pvpython not found (install python3-paraview)"; exit 1; }
"$pv" --force-offscreen-rendering "$script" "$out"
# Every dataset carries its SI units, and particle files their species table.
fluid=$(ls "$out"/fluid/step_*.h5 2>/dev/null | tail -n 1)
if [ -n "$fluid" ]; then
  h5dump -a /velocity/units "$fluid" | grep -q '"m/s"' || { echo "FAIL: $fluid: velocity has no units attribute m/s"; exit 1; }
fi
particles=$(ls "$out"/particles/step_*.h5 2>/dev/null | tail -n 1)
if [ -n "$particles" ]; then
  h5dump -a /position/units "$particles" | grep -q '"m"' || { echo "FAIL: $particles: position has no units m"; exit 1; }
  h5dump -a /species_names "$particles" | grep -q 'DATA' || { echo "FAIL: $particles: no species_names"; exit 1; }
fi
echo "units and species names in the HDF5 files: ok"
# Every series names its columns on the first line and gives their units on
# the second, one per column.
for f in "$out"/series/*.csv; do
  names=$(sed -n 1p "$f" | awk -F, '{ print NF }')
  units=$(sed -n 2p "$f")
  [[ $units == "# s,"* ]] || { echo "FAIL: $f: the second line is not the units line: $units"; exit 1; }
  [ "$(echo "$units" | awk -F, '{ print NF }')" = "$names" ] || { echo "FAIL: $f: $names columns, other number of units"; exit 1; }
done
echo "units lines in the series: ok"
