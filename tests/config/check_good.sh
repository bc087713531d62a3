#!/usr/bin/env bash
# Every configuration under configs/ must validate.
set -u
bin=$1; dir=$2; status=0; n=0
for cfg in $(find "$dir" -name "*.yaml" | sort); do
  n=$((n + 1))
  out=$("$bin" validate "$cfg" 2>&1 >/dev/null) || { echo "FAIL: $cfg"; echo "$out"; status=1; }
done
[ $n -gt 0 ] || { echo "FAIL: no configs in $dir"; exit 1; }
echo "$n configs checked"
exit $status
