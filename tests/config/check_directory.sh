#!/usr/bin/env bash
# Usage: check_directory.sh COFLOW
# A directory given where the configuration file belongs (`coflow validate
# DIR`, `coflow run --dry-run DIR`) is bad input: exit status 2 and one line
# saying so, not an uncaught exception (it was: status 134).
set -u
bin=$1
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
mkdir "$dir/case.yaml"
status=0
for args in "validate" "run --dry-run"; do
  out=$(cd "$dir" && "$bin" $args case.yaml 2>&1); rc=$?
  if [ $rc -ne 2 ]; then echo "FAIL ($args): exit status $rc, expected 2"; echo "$out"; status=1; continue; fi
  case "$out" in
    *"case.yaml: is a directory, not a file"*) echo "ok ($args): $out" ;;
    *) echo "FAIL ($args): message not found"; echo "  got: $out"; status=1 ;;
  esac
done
exit $status
