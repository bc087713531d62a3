#!/usr/bin/env bash
# The benchmarks' command lines: --help prints the usage and exits 0; a bad
# argument exits 2 with a message naming it, before any work starts (each
# earlier read its count with atoi: --help ran zero steps and crashed).
#   check_args.sh BIN_DIR
set -u
bin=$1
fail=0
expect() {  # expect RC PATTERN BENCH ARGS...
  local rc=$1 pattern=$2 bench=$3
  shift 3
  local out got
  out=$(timeout 20 "$bin/$bench" "$@" 2>&1)
  got=$?
  if [ "$got" -ne "$rc" ] || ! grep -q -- "$pattern" <<<"$out"; then
    echo "FAIL: $bench $*: exit $got (expected $rc), output:"
    echo "$out" | head -5
    fail=1
  else
    echo "ok: $bench $* -> $got"
  fi
}
for b in bench-lbm bench-dem bench-dpm bench-coupler-exchange bench-coupled bench-ibm bench-fv bench-amr; do
  expect 0 "Usage:" "$b" --help
done
for b in bench-lbm bench-dem bench-dpm bench-fv bench-amr; do
  expect 2 "steps: Value 0 not in range" "$b" 0
  expect 2 "steps: Value ten not in range" "$b" ten
done
expect 2 "cells: Value 1 not in range" bench-coupler-exchange 1
expect 2 "The following argument was not expected" bench-lbm 10 20
expect 2 "excludes" bench-fv --channel --cavity
expect 2 "plate: File does not exist" bench-ibm 64 /nonexistent/plate.stl
expect 2 "configs: Directory does not exist" bench-coupled /nonexistent/configs
expect 2 "configs: Directory does not exist" bench-amr --configs /nonexistent/configs
exit $fail
