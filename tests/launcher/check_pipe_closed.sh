#!/usr/bin/env bash
# check_pipe_closed.sh BIN_DIR CONFIG OUT
# `coflow run ... | head -n 1`: the reader of the launcher's output goes away
# at once. The run must still finish and say so in summary.json, with exit
# status 0 (the launcher ignores SIGPIPE; it died of it and left mpirun
# without its reader).
set -u
bin=$1 cfg=$2 out=$3
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$bin/coflow" run "$cfg" --set run.output.dir="$out/run" 2>"$out/stderr.log" | head -n 1 >"$out/first.log"
rc=${PIPESTATUS[0]}
[ -s "$out/first.log" ] || fail "head read nothing"
[ $rc -eq 0 ] || { tail -n 20 "$out/stderr.log"; fail "exit status $rc with the output's reader gone"; }
grep -q '"status": "ok"' "$out/run/summary.json" 2>/dev/null || fail "the run did not finish (summary.json)"
echo "ok: the output's reader went after one line; the run finished (exit status 0, summary ok)"
