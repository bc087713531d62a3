#!/usr/bin/env bash
# check_start_failures.sh BIN_DIR CONFIG OUT
# A component executable that never joins the run must end it with a message
# naming it, within run.launch.start_timeout (not hang, and not wait for
# coupling.timeout, which bounds the ranks' waits once started), and summary.json must say
# why: one that exits 0 at once (/bin/true: the others wait in MPI start-up)
# and one that fails at once (/bin/false); and a launch that ignores the
# watchdog's SIGTERM (an mpirun that hangs) is killed, and the pipe that its
# child still holds abandoned.
set -u
bin=$1 cfg=$2 out=$3
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
start=$(date +%s)
timeout 60 "$bin/coflow" run "$cfg" --exe fluid=/bin/true --set run.launch.start_timeout=5 --set run.output.dir="$out/true" \
  >"$out/true.log" 2>&1; rc=$?
took=$(( $(date +%s) - start ))
cat "$out/true.log" | tail -n 3
[ $rc -ne 124 ] || fail "/bin/true as the fluid: the launch hung (killed after 60 s)"
[ $rc -ne 0 ] || fail "/bin/true as the fluid: exit status 0"
[ $took -le 20 ] || fail "/bin/true as the fluid: took $took s with run.launch.start_timeout 5"
# Open MPI either holds the others in MPI start-up (then the watchdog stops
# the run after run.launch.start_timeout and names the executable) or, now and then
# under load, aborts the job itself when /bin/true exits without MPI_Init
# (then the launcher says that the MPI launcher or an executable stopped at
# start).
if grep -q "did not start within 5 s" "$out/true.log"; then
  grep -q "fluid=/bin/true" "$out/true.log" || fail "the executable is not named"
  grep -q '"reason": "fluid, immersed, particles did not start' "$out/true/summary.json" || fail "summary.json reason"
else
  grep -q "the MPI launcher or an executable stopped at start; see the output above" "$out/true.log" ||
    fail "no start-up message"
fi
timeout 60 "$bin/coflow" run "$cfg" --exe fluid=/bin/false --set run.output.dir="$out/false" >"$out/false.log" 2>&1; rc=$?
tail -n 2 "$out/false.log"
[ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "/bin/false as the fluid: exit status $rc"
grep -q "before any component started" "$out/false.log" || fail "/bin/false: no message"
grep -q "see $out/false/logs/" "$out/false.log" && fail "/bin/false: points at a logs directory that does not exist"
grep -q '"reason": ""' "$out/false/summary.json" && fail "/bin/false: empty reason in summary.json"
# An mpirun that hangs and ignores SIGTERM, whose child holds the output pipe:
# the watchdog kills it run.launch.stop_grace (here 2 s, 10 by default) after
# its SIGTERM and leaves the pipe 2 s later.
mkdir -p "$out/fake"
printf '#!/bin/bash\ntrap "" TERM\nsleep 100\n' >"$out/fake/mpirun"
chmod +x "$out/fake/mpirun"
start=$(date +%s)
PATH="$out/fake:$PATH" timeout 60 "$bin/coflow" run "$cfg" --set run.launch.start_timeout=2 \
  --set run.launch.stop_grace=2 --set run.output.dir="$out/stuck" >"$out/stuck.log" 2>&1; rc=$?
stuck=$(( $(date +%s) - start ))
tail -n 3 "$out/stuck.log"
[ $rc -ne 124 ] || fail "a launch ignoring SIGTERM: the launcher hung (killed after 60 s)"
[ $rc -ne 0 ] || fail "a launch ignoring SIGTERM: exit status 0"
[ $stuck -ge 5 ] || fail "a launch ignoring SIGTERM: ended after $stuck s, before start_timeout 2 + twice 2 s of grace"
[ $stuck -le 16 ] || fail "a launch ignoring SIGTERM: took $stuck s (start_timeout 2 + twice 2 s of grace)"
grep -q "the launch did not end 2 s after SIGTERM (run.launch.stop_grace): killing it" "$out/stuck.log" ||
  fail "no kill message"
grep -q '"reason": "fluid, immersed, particles did not start' "$out/stuck/summary.json" || fail "stuck: summary.json reason"
echo "ok: stopped in $took s; a launch ignoring SIGTERM killed in $stuck s"
