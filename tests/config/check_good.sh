#!/usr/bin/env bash
# Every configuration under configs/ must validate, and open with a comment
# saying what it shows.
set -u
bin=$1; dir=$2; status=0; n=0
# Generated geometry (not in git) that configs refer to: write it when absent.
plate="$dir/cases/geometry/jet_plate.stl"
[ -f "$plate" ] || /usr/bin/python3 "$dir/../scripts/make_plate_stl.py" "$plate" >/dev/null || { echo "FAIL: $plate"; exit 1; }
for cfg in $(find "$dir" -name "*.yaml" | sort); do
  n=$((n + 1))
  out=$("$bin" validate "$cfg" 2>&1 >/dev/null) || { echo "FAIL: $cfg"; echo "$out"; status=1; }
  head -n 1 "$cfg" | grep -q '^# [A-Za-z]' || { echo "FAIL: $cfg: the first line is not a comment saying what it shows"; status=1; }
done
[ $n -gt 0 ] || { echo "FAIL: no configs in $dir"; exit 1; }
echo "$n configs checked"
exit $status
