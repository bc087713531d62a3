#!/usr/bin/env bash
# check_interrupt.sh BIN_DIR CONFIG OUT [SIGNAL]
# Ctrl-C (SIGINT to the launcher) stops the run with a message saying what was
# written and the command that restarts from the last checkpoint; that command
# then finishes the run. With SIGNAL HUP (the terminal or ssh session closed):
# the run stops the same way (mpirun gets SIGTERM), exit status 129.
set -u
bin=$1 cfg=$2 out=$3 sig=${4:-INT}
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; tail -n 20 "$out/run.log"; exit 1; }
# mpirun --tag-output puts "[1,N]<stdout>:" before each line of the ranks: the
# launcher still takes the progress tags (checked below).
"$bin/coflow" run "$cfg" --set run.output.dir="$out/run" --set run.checkpoint.every=0.05 \
  --set 'run.launch.mpi_args=[--tag-output]' >"$out/run.log" 2>&1 &
pid=$!
# A finished checkpoint: window_NNNNNN, not the window_NNNNNN.partial it is
# renamed from (a listing made during the rename may see neither name, so
# the loop looks again rather than checking once after a .partial was seen).
written=0
for i in $(seq 1 600); do
  ls -d "$out"/run/checkpoints/window_*[0-9] >/dev/null 2>&1 && { written=1; break; }
  sleep 0.1
done
[ $written -eq 1 ] || { kill "$pid"; fail "no checkpoint written"; }
sleep 0.5
kill -"$sig" "$pid"
wait "$pid"; rc=$?
number=$(kill -l "$sig")
[ $rc -eq $((128 + number)) ] || fail "exit status $rc after SIG$sig, expected $((128 + number))"
grep -q "coflow: interrupted after" "$out/run.log" || fail "no interruption message"
if [ "$sig" != INT ]; then
  grep -q "\"reason\": \"interrupted by signal $number" "$out/run/summary.json" || fail "summary.json reason"
  # No component failed: JSON nulls, not empty strings.
  grep -q '"failed_component": null,' "$out/run/summary.json" && grep -q '"failed_rank": null,' "$out/run/summary.json" ||
    fail "summary.json names a failed component or rank: $(cat "$out/run/summary.json")"
  pgrep -f "coflow-fluid.*$out/run" >/dev/null; st=$?  # 1: none; 0: one runs; else pgrep itself failed
  [ $st -eq 1 ] || fail "a component still runs after SIG$sig (pgrep status $st)"
  echo "ok: SIG$sig stopped the run (exit status $rc) and said how to restart"
  exit 0
fi
grep -q "^progress:" "$out/run.log" || fail "no progress line under --tag-output"
grep -q "@coflow progress" "$out/run.log" && fail "raw progress lines under --tag-output"
grep -q '"reason": "interrupted by signal 2' "$out/run/summary.json" || fail "summary.json reason"
restart=$(sed -n 's/^ *coflow run .* --restart //p' "$out/run.log" | tr -d "'")
[ -n "$restart" ] && [ -d "$restart" ] || fail "no restart command naming a checkpoint"
grep -q -- "--set run.output.dir=$out/run " "$out/run.log" || fail "the restart command lacks the run's --set"
# The printed command itself, as a user would paste it (coflow on the PATH).
command=$(grep -A2 "restart from the last checkpoint with:" "$out/run.log" | sed -n 's/^ *\(coflow run .*\)$/\1/p')
[ -n "$command" ] || fail "no restart command line"
PATH="$bin:$PATH" bash -c "$command" >"$out/restart.log" 2>&1 ||
  { tail -n 20 "$out/restart.log"; fail "the printed restart command failed: $command"; }
grep -q "^coflow: restarting from $restart" "$out/restart.log" || fail "the printed command did not restart from $restart"
grep -q '"status": "ok"' "$out/run/summary.json" || fail "the restarted run did not finish"
echo "ok: interrupted, told how to restart from $(basename "$restart"), restarted to the end"
