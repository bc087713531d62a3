#!/usr/bin/env bash
# fault.sh BIN_DIR CONFIG OUT COMPONENT MODE
# MODE: fail (an exception), kill (SIGKILL of one rank), hang (a rank stops answering),
# nan (particles: a point sent with a NaN position; the point exchange stops the run).
# The launcher must exit non-zero within 10 s, naming the component.
set -u
bin=$1 cfg=$2 out=$3 comp=$4 mode=$5
start=$(date +%s%N)
timeout 60 "$bin/coflow" run "$cfg" --exe fluid="$bin/coflow-dummy-fluid" --exe immersed="$bin/coflow-dummy-immersed" \
  --exe particles="$bin/coflow-dummy-particles" --set run.output.dir="$out" \
  --set "$comp.dummy.${mode}_at_window=2" --set "$comp.dummy.fail_rank=1" --set particles.ranks=2 \
  --set coupling.timeout=3 >"$out.log" 2>&1
rc=$?
elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
echo "exit status $rc after $elapsed_ms ms"
[ $rc -ne 0 ] && [ $rc -ne 124 ] || { echo "FAIL: expected a non-zero exit (not a timeout)"; tail -n 20 "$out.log"; exit 1; }
if [ "$elapsed_ms" -gt 10000 ]; then echo "FAIL: took longer than 10 s"; exit 1; fi
if [ "$mode" = hang ]; then
  # The partner that waited names itself and says why.
  grep -q "run failed in component" "$out.log" && grep -q "without an answer" "$out.log" || { echo "FAIL: no timeout message"; tail -n 20 "$out.log"; exit 1; }
else
  grep -q "run failed in component '$comp'" "$out.log" || { echo "FAIL: component '$comp' not named"; tail -n 20 "$out.log"; exit 1; }
fi
if [ "$mode" = nan ]; then
  grep -q "point exchange: record 0 of this rank has a position that is not finite (.*, nan, " "$out.log" ||
    { echo "FAIL: no message on the position"; tail -n 20 "$out.log"; exit 1; }
fi
grep -q '"status": "failed"' "$out/summary.json" || { echo "FAIL: summary.json does not say failed"; exit 1; }
# The rank that misbehaved (fail_rank=1 above), as a JSON number; a partner's
# timeout knows no rank.
if [ "$mode" != hang ]; then
  grep -q "\"failed_component\": \"$comp\"," "$out/summary.json" && grep -q '"failed_rank": 1,' "$out/summary.json" ||
    { echo "FAIL: summary.json does not name $comp's rank 1"; cat "$out/summary.json"; exit 1; }
fi
