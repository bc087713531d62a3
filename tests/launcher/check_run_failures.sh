#!/usr/bin/env bash
# check_run_failures.sh BIN_DIR CASES_DIR OUT
# A component that fails in the middle of a run must end the whole run with
# its message, a non-zero exit status and summary.json's status "failed" with
# the same reason, within seconds (not hang). Each case of CASES_DIR names
# the message it must give in the table below.
set -u
bin=$1 cases=$2 out=$3
rm -rf "$out"; mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fail() { echo "FAIL: $*"; exit 1; }
check() {  # case, the message it must give, --set options
  local name=$1 msg=$2 dir="$out/$1"
  shift 2
  timeout 60 "$bin/coflow" run "$cases/$name.yaml" --set run.output.dir="$dir" "$@" >"$out/$name.log" 2>&1
  local rc=$?
  grep "coflow: run failed" "$out/$name.log"
  [ $rc -ne 124 ] || fail "$name: hung (killed after 60 s)"
  [ $rc -ne 0 ] || fail "$name: exit status 0"
  grep -qF "$msg" "$out/$name.log" || fail "$name: no message '$msg' in $out/$name.log"
  grep -q '"status": "failed"' "$dir/summary.json" || fail "$name: summary.json status is not failed"
  grep -qF "$msg" "$dir/summary.json" || fail "$name: summary.json reason lacks '$msg'"
}
check fv_k_epsilon_blow_up \
  "fv: k and epsilon would need 3.2e+09 advection sub-steps at t = 0.01 s (the velocity is far above the step's CFL limit); lower fluid.fv.cfl or fluid.fv.max_step"
check fv_lid_beyond_double \
  "fv: the viscous solve of u_x's right-hand side is not finite (|b|^2 = inf): the flow is blowing up"
# The same through hypre's multigrid-preconditioned solve (a viscous step far
# from diagonally dominant), where hypre called it converged.
check fv_lid_beyond_double \
  "fv: the viscous solve of u_x's right-hand side is not finite (|b|^2 = inf): the flow is blowing up" \
  --set fluid.viscosity=1.0
check fv_lid_beyond_double "fv-reference: the viscous solve's right-hand side is not finite" \
  --set fluid.solver=fv-reference
check dem_coincident_grains "dem: particles 0 and 8 have the same centre at t = 0 s: two grains were placed in one place"
check dem_coincident_grains "dem: particles 0 and 8 have the same centre at t = 0 s" --set particles.solver=dem-reference
check dem_crushed_past_fixed_step \
  "the particle step 2e-05 s (particles.time_step) now exceeds the critical step 8.329e-06 s (seed 000 eq. 2.19) of the lightest grain"
# On 3 fluid ranks every rank fails. Each rank writes its own files: rank 0
# logs/fluid.log, the others only their warnings and errors in
# logs/fluid.<rank>.log; each failing rank its reason in a piece that the
# launcher gathers into logs/FAILED (no two ranks append to one file:
# appends from several hosts to one file on NFS can overwrite each other).
# The first rank's MPI_Abort may end the others before they write, so
# logs/FAILED holds one to three reasons (tests/unit/coupler/test_log.cpp
# checks the ranks' files deterministically).
check fv_k_epsilon_blow_up "fv: k and epsilon would need" --set fluid.ranks=3
d="$out/fv_k_epsilon_blow_up"
n=$(grep -c "^fluid rank [012]: fv: k and epsilon would need" "$d/logs/FAILED")
[ "$n" -ge 1 ] && [ "$n" = "$(wc -l <"$d/logs/FAILED")" ] ||
  fail "logs/FAILED does not hold the ranks' reasons, one a line: $(cat "$d/logs/FAILED")"
! ls "$d"/logs/FAILED.* >/dev/null 2>&1 || fail "the ranks' pieces of logs/FAILED were left: $(ls "$d/logs")"
grep -v "\[fluid:0\]" "$d/logs/fluid.log" && fail "logs/fluid.log holds lines from other ranks than 0"
for r in 1 2; do
  [ ! -e "$d/logs/fluid.$r.log" ] || ! grep -v "\[fluid:$r\] \[\(warning\|error\|critical\)\]" "$d/logs/fluid.$r.log" ||
    fail "logs/fluid.$r.log holds other lines than rank $r's warnings and errors"
done
echo "ok"
