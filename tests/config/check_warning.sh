#!/usr/bin/env bash
# Usage: check_warning.sh CONFIG COFLOW
# The config is valid but its pre-run report must warn: `coflow validate`
# exits 0 and prints the warning of its first line ("# warn: text"), and
# `coflow validate --strict` turns it into exit status 2.
set -u
cfg=$1; bin=$2
expect=$(head -n 1 "$cfg" | sed -n 's/^# warn: //p')
[ -n "$expect" ] || { echo "FAIL: $cfg has no '# warn:' first line"; exit 1; }
dir=$(dirname "$cfg"); base=$(basename "$cfg")
out=$(cd "$dir" && "$bin" validate "$base" 2>&1); rc=$?
[ $rc -eq 0 ] || { echo "FAIL: exit status $rc, expected 0"; echo "$out"; exit 1; }
case "$out" in
  *"warning: $expect"*) ;;
  *) echo "FAIL: warning not found"; echo "  expected: warning: $expect"; echo "  got:      $out"; exit 1 ;;
esac
(cd "$dir" && "$bin" validate --strict "$base" >/dev/null 2>&1); rc=$?
[ $rc -eq 2 ] || { echo "FAIL: --strict gave exit status $rc, expected 2"; exit 1; }
echo "ok: $base warns: $expect"
